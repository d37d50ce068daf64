#include "pipeline/live_check.h"

#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "check/check.h"
#include "model/shape.h"
#include "pipeline/html_report.h"
#include "pipeline/prepare.h"
#include "pipeline/run_scenario.h"
#include "render/gltf.h"
#include "report/html.h"

namespace sscs {

namespace {

namespace fs = std::filesystem;

/// Every file a compile read (absolute): its sources and the meshes of its geometry.
std::vector<std::string> files_read(const std::string& path, const Sources& sources, const GeometryModel* geometry) {
  std::set<std::string> files;
  auto read = [&](const std::string& file) {
    std::error_code ec;
    if (file.empty() || file.front() == '<' || !fs::is_regular_file(file, ec)) return;  // (texts of no file: a plugin's types)
    files.insert(fs::absolute(file).lexically_normal().string());
  };
  // The file served, even when it cannot be read now (deleted, being replaced): its folder stays
  // watched, so its return is checked (a server stuck on "does not exist" until restarted).
  files.insert(fs::absolute(path).lexically_normal().string());
  for (uint32_t f = 1; f < sources.size(); ++f) read(sources.path(f));
  if (geometry)
    for (const ObjectGeometry& g : geometry->objects)
      for (const auto* shapes : {&g.shapes, &g.visual_shapes})
        for (const Shape& s : *shapes)
          if (s.mesh) read(s.mesh->path);
  return {files.begin(), files.end()};
}

/// `out` says the input errors of `diag`.
void input_errors(LiveCheck& out, const Diagnostics& diag, const Sources& sources) {
  out.errors = diag.format(sources);
  const size_t n = diag.errors().size();
  out.summary = fmt::format("{} input error{}", n, n == 1 ? "" : "s");
}

}  // namespace

struct LiveVaultMaker {
  static void make(LiveVault& v, const std::string& path, const CompileOptions& options, LibraryCache& library,
                   const std::atomic<bool>* cancel, LiveCheck& out) {
    Diagnostics diag;
    v.vault_ = prepare_vault(path, options, v.sources_, diag, {.visuals = true, .contacts = nullptr}, library);
    out.files = files_read(path, v.sources_, v.vault_.wc ? &v.vault_.geometry : nullptr);
    if (diag.has_errors() || !v.vault_.wc) {
      input_errors(out, diag, v.sources_);
      return;
    }
    const Workcell& wc = *v.vault_.wc;
    CheckOptions check_options;
    check_options.describe_passes = true;
    check_options.cancel = cancel;
    v.reports_.push_back({&wc, path, check(wc, v.vault_.geometry, check_options), std::nullopt, diag.warnings(), options.overrides});
    const CheckReport& r = v.reports_.back().report;
    out.summary = fmt::format("{} passed, {} failed, {} warnings", r.passed, r.failed, r.warnings);
    v.data_ = json_in_script(check_report(v.reports_, v.sources_, {&v.vault_.geometry}, /*models=*/false).data);
    std::vector<std::string> keys = object_model_keys(wc, v.vault_.geometry);
    auto named = std::make_shared<LiveVault::Keys>();
    for (size_t o = 0; o < wc.objects.size(); ++o) named->emplace(wc.objects[o].name, std::move(keys[o]));
    v.keys_ = std::move(named);
    out.compiled = true;
  }
};

std::string LiveVault::page() const { return check_html(reports_, sources_, {&vault_.geometry}); }

std::string LiveVault::changed_model(const Keys& before, std::vector<std::string>& removed) const {
  const Workcell& wc = *vault_.wc;
  for (const auto& [name, key] : before)
    if (!keys_->count(name)) removed.push_back(name);
  GltfScene scene;
  scene.only.assign(wc.objects.size(), 0);
  bool any = false;
  for (size_t o = 0; o < wc.objects.size(); ++o) {
    auto it = before.find(wc.objects[o].name);
    scene.only[o] = it == before.end() || it->second != keys_->at(wc.objects[o].name);
    any = any || scene.only[o];
  }
  if (!any) return "";
  Expected<std::string> glb = gltf_file(wc, vault_.geometry, scene, true);
  return glb ? *glb : "";
}

LiveCheck live_check(const std::string& path, const CompileOptions& options, LibraryCache& library, const std::atomic<bool>* cancel) {
  LiveCheck out;
  auto vault = std::make_shared<LiveVault>();
  LiveVaultMaker::make(*vault, path, options, library, cancel, out);
  if (out.compiled) out.vault = std::move(vault);
  return out;
}

LiveCheck live_run(const std::string& path, const CompileOptions& options, const std::string& scratch) {
  LiveCheck out;
  PreparedScenario ps;
  const bool prepared = ps.prepare(path, options);
  out.files = files_read(path, ps.sources, ps.wc ? &ps.geometry : nullptr);
  if (!prepared || ps.diag.has_errors()) {
    input_errors(out, ps.diag, ps.sources);
    return out;
  }
  RunRequest request;
  request.out = (fs::path(scratch) / "run").string();
  request.frames = false;
  Expected<RunSummary> ran = run_scenario(ps, request);
  if (!ran) {  // not the input's fault (a full disk): said like an input error, over the last good view
    out.errors = fmt::format("sscs serve: the run could not be written: {}\n", ran.error());
    out.summary = "the run failed";
    return out;
  }
  Expected<std::shared_ptr<OpenedRun>> run = OpenedRun::open(request.out);
  Expected<std::string> page = run ? run_html(**run, options) : Expected<std::string>(Unexpected{run.error()});
  if (!page) {
    out.errors = fmt::format("sscs serve: the run's page could not be made: {}\n", page.error());
    out.summary = "the run's page failed";
    return out;
  }
  out.page = std::move(*page);
  out.compiled = true;
  const RunSummary& summary = *ran;
  out.summary = !summary.unfinished.empty()
                    ? fmt::format("ran {:.3f} s, no cycle time ({})", summary.simulated, summary.unfinished)
                : summary.stopped_by.empty()
                    ? fmt::format("ran {:.3f} s (cycle time {:.3f} s), {} collisions, {} events", summary.simulated, summary.cycle_time,
                                  summary.collisions, summary.events)
                    : fmt::format("ran {:.3f} s: stopped by {} at {:.3f} s", summary.simulated, summary.stopped_by, summary.stopped_at);
  return out;
}

}  // namespace sscs
