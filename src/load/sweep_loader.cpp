// Sweep files: `sscs: 1`, `sweep: NAME`, vault, scenario, vary, mode, metrics.
#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "core/files.h"
#include "core/yaml_tree.h"
#include "load/load.h"
#include "load/reader.h"
#include "load/sweep.h"

namespace fs = std::filesystem;

namespace sscs {

using load::MapReader;

namespace {

std::string beside(const std::string& file, const std::string& rel) {
  return join_path(fs::path(file).parent_path().string(), rel);
}

VarySpec read_vary(yaml::Node key, yaml::Node value, Diagnostics& diag) {
  VarySpec v;
  v.name = load::name(key, "a varied parameter", diag);
  v.mark = key.mark();
  const char* shape = "{from: A, to: B, step: S} or {values: [...]}";
  if (!value.is_map()) {
    load::expected(diag, value, shape, fmt::format("vary '{}'", v.name));
    return v;
  }
  MapReader r(value, fmt::format("vary '{}'", v.name), diag);
  if (r.has("values")) {
    yaml::Node values = r.take("values");
    if (!values.is_sequence() || values.size() == 0) {
      load::expected(diag, values, "a non-empty sequence of values", fmt::format("vary '{}' values", v.name));
    } else {
      for (size_t i = 0; i < values.size(); ++i) {
        yaml::Node item = values.item(i);
        if (!item.is_scalar() || item.is_null())
          load::expected(diag, item, v.files() ? "a file path" : "a number, a quantity or a string", fmt::format("a value of '{}'", v.name));
        else v.values.push_back(load::scalar(item, "a value", diag));
      }
    }
    if (r.has("from") || r.has("to") || r.has("step"))
      diag.error(r.mark(), fmt::format("vary '{}' has both values and from/to/step; give one of {}", v.name, shape));
    r.take("from"), r.take("to"), r.take("step");
  } else if (v.files()) {
    diag.error(r.mark(), fmt::format("vary '{}' varies whole {}: expected {{values: [{}, ...]}}", v.name,
                                     v.name == "library" ? "type-library folders" : "files", v.name == "library" ? "folder" : "file"));
    return v;
  } else {
    v.range = true;
    v.from = load::scalar(r.require("from"), "from", diag);
    v.to = load::scalar(r.require("to"), "to", diag);
    v.step = load::scalar(r.require("step"), "step", diag);
  }
  r.finish();
  return v;
}

}  // namespace

std::optional<SweepSpec> load_sweep(const std::string& path, Sources& sources, Diagnostics& diag) {
  uint32_t file = read_source(path, sources, diag);
  if (file == 0) return std::nullopt;
  return load_sweep(file, sources, diag);
}

std::optional<SweepSpec> load_sweep(uint32_t file, Sources& sources, Diagnostics& diag) {
  yaml::Document doc = yaml::parse(sources, file, diag);
  if (doc.empty()) return std::nullopt;
  MapReader root(doc.root(), "a sweep file", diag);
  if (!root.ok()) return std::nullopt;
  load::check_version(root, diag);
  SweepSpec s;
  s.path = sources.path(file);
  yaml::Node name = root.require("sweep");
  s.name = load::name(name, "the sweep", diag);
  s.mark = name.valid() ? name.mark() : root.mark();
  s.description = load::text(root.take("description"), "description", diag);
  s.vault = load::scalar(root.take("vault"), "vault", diag);
  s.scenario = load::scalar(root.take("scenario"), "scenario", diag);
  // A campaign runs where a scenario would (campaign-format.md): the same key underneath.
  if (Scalar campaign = load::scalar(root.take("campaign"), "campaign", diag); campaign.present) {
    if (s.scenario.present) diag.error(campaign.mark, "a sweep runs a scenario or a campaign, not both; remove one");
    else s.scenario = campaign, s.campaign = true;
  }
  if (s.vault.present) s.vault_path = beside(s.path, s.vault.text);
  if (s.scenario.present) s.scenario_path = beside(s.path, s.scenario.text);

  yaml::Node vary = root.require("vary");
  if (vary.valid() && (!vary.is_map() || vary.size() == 0)) {
    load::expected(diag, vary, "a mapping of parameters to vary {name: {from, to, step} | {values}}", "vary");
  } else if (vary.valid()) {
    MapReader v(vary, "vary", diag);
    for (auto& [k, val] : v.rest()) s.vary.push_back(read_vary(k, val, diag));
  }
  bool varies_vault = false, varies_scenario = false;
  for (const VarySpec& v : s.vary) {
    varies_vault |= v.name == "vault";
    varies_scenario |= v.name == "scenario";
  }
  if (!s.vault.present && !s.scenario.present && !varies_vault && !varies_scenario)
    diag.error(root.mark(), "a sweep needs a vault (vault: FILE), a scenario (scenario: FILE) or a campaign (campaign: FILE), or varies one");
  for (const VarySpec& v : s.vary) {
    if (v.name == "vault" && s.vault.present)
      diag.error(v.mark, "'vault' is varied and also given (vault:); remove one");
    if (v.name == "scenario" && s.scenario.present)
      diag.error(v.mark, "'scenario' is varied and also given (scenario:); remove one");
  }

  yaml::Node mode = root.take("mode");
  s.mode_mark = mode.valid() ? mode.mark() : root.mark();
  if (mode.valid()) {
    if (mode.is_scalar() && mode.text() == "grid") {
      // the default
    } else if (mode.is_map()) {
      MapReader m(mode, "mode", diag);
      MapReader random(m.require("random"), "random mode", diag);
      if (random.ok()) {
        s.random = true;
        s.n = load::scalar(random.require("n"), "n", diag);
        s.seed = load::scalar(random.require("seed"), "seed", diag);
        random.finish();
      }
      m.finish();
    } else {
      load::expected(diag, mode, "grid or {random: {n: N, seed: S}}", "mode");
    }
  }

  yaml::Node metrics = root.take("metrics");
  if (metrics.valid() && !metrics.is_map()) {
    load::expected(diag, metrics, "a mapping of metric names to expressions", "metrics");
  } else if (metrics.valid()) {
    MapReader m(metrics, "metrics", diag);
    for (auto& [k, val] : m.rest()) {
      MetricSpec metric;
      metric.name = load::name(k, "a metric", diag);
      metric.mark = k.mark();
      if (!val.is_scalar() || val.is_null()) load::expected(diag, val, "an expression", fmt::format("metric '{}'", metric.name));
      else metric.expr = load::scalar(val, "a metric", diag);
      s.metrics.push_back(std::move(metric));
    }
  }
  // Columns of results.csv: a metric may not take the name of another column.
  const std::vector<std::string> reserved = {"variant", "folder", "status", "passed", "failed", "warnings",
                                             "cycle_time", "collisions", "message"};
  for (const MetricSpec& m : s.metrics) {
    bool is_reserved = std::find(reserved.begin(), reserved.end(), m.name) != reserved.end();
    bool is_varied = std::any_of(s.vary.begin(), s.vary.end(), [&](const VarySpec& v) { return v.name == m.name; });
    if (is_reserved || is_varied)
      diag.error(m.mark, fmt::format("metric '{}' has the name of a {} column of results.csv; rename it", m.name,
                                     is_varied ? "varied parameter's" : "fixed"));
  }
  root.finish();
  return s;
}

}  // namespace sscs
