#include "pipeline/html_report.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/archive.h"
#include "core/digest.h"
#include "kinematics/envelope.h"
#include "pipeline/prepare.h"
#include "render/gltf.h"
#include "render/replay.h"
#include "report/html.h"

namespace sscs {

namespace fs = std::filesystem;
using json = nlohmann::json;

/// Tool points per device in a check page's reach picture.
constexpr int kReachPoints = 800;

namespace {

std::string generator() { return fmt::format("sscs {}", SSCS_VERSION); }

Expected<json> read_json(const std::string& path) {
  std::optional<std::string> text = read_file_bytes(path);
  if (!text) return Unexpected{fmt::format("{}: cannot be read", path)};
  json j = json::parse(*text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return Unexpected{fmt::format("{}: not JSON", path)};
  return j;
}

}  // namespace

Expected<std::shared_ptr<OpenedRun>> OpenedRun::open(const std::string& path) {
  auto run = std::make_shared<OpenedRun>();
  run->given_ = path;
  run->dir_ = path;
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) {
    // The bundle unpacked beside the system's temporary files, under a name of this process.
    run->unpacked_.emplace((fs::temp_directory_path() / fmt::format("sscs-run-{}", ::getpid())).string());
    if (std::string err = unzip_into(path, run->unpacked_->path(), {"frames/"}); !err.empty()) return Unexpected{err};
    run->dir_ = run->unpacked_->path();
  }
  if (!fs::is_regular_file(fs::path(run->dir_) / "resolved" / "scenario.yaml", ec))
    return Unexpected{fmt::format("{}: not a run folder or bundle (expected resolved/scenario.yaml in it)", path)};
  return run;
}

Expected<std::string> run_gltf(const OpenedRun& run, const CompileOptions& options, bool binary, std::string* warnings) {
  PreparedScenario ps;
  if (!ps.prepare((fs::path(run.dir()) / "resolved" / "scenario.yaml").string(), options))
    return Unexpected{ps.diag.format(ps.sources)};
  if (warnings) *warnings = ps.diag.format(ps.sources);
  std::vector<int> driven;
  for (const Track& track : ps.plan->tracks) driven.push_back(track.object);
  auto recorded = RecordedRun::read(run.dir(), *ps.wc, ps.geometry, driven);
  if (!recorded) return Unexpected{recorded.error()};
  recorded->set_arrivals(ps.plan->arrivals);
  const Eigen::AlignedBox3d bounds = scene_bounds(ps.geometry);
  SceneAnimation animation;
  animation.times = recorded->log_times();
  animation.moving = recorded->logged_objects();
  animation.at = [&](double t) { return recorded->at(t); };
  animation.aspect = double(ps.plan->settings.width) / ps.plan->settings.height;
  animation.camera = [&](double t, const ScenePose& pose) { return ps.cameras.at(t, pose, bounds, animation.aspect); };
  return gltf_file(*ps.wc, ps.geometry, {vault_cameras(*ps.wc, ps.geometry), &animation}, binary);
}

namespace {

/// Where each device of the vault reaches: {device: [x, y, z, ...]}, world points of its tool
/// (reach_points), to the mm. The page draws them with a failed reach row and on request.
json reach_clouds(const Workcell& wc, const GeometryModel& geometry) {
  json out = json::object();
  for (size_t o = 0; o < wc.objects.size(); ++o) {
    const ObjectGeometry& g = geometry.objects[o];
    if (!g.device || g.device->dof() == 0) continue;
    const Eigen::VectorXd q = g.device->joint_values(&wc.values[wc.objects[o].first_slot + kFirstAttributeSlot]);
    json points = json::array();
    for (const Eigen::Vector3d& p : reach_points(*g.device, q, kReachPoints)) {
      const Eigen::Vector3d w = g.X_world_object * p;
      if (!w.allFinite()) continue;
      for (int k = 0; k < 3; ++k) points.push_back(std::round(w[k] * 1000) / 1000);
    }
    out[wc.objects[o].name] = std::move(points);
  }
  return out;
}

}  // namespace

std::string check_html(const std::vector<VaultReport>& reports, const Sources& sources, const std::vector<const GeometryModel*>& geometry) {
  return html_page(check_report(reports, sources, geometry));
}

HtmlReport check_report(const std::vector<VaultReport>& reports, const Sources& sources, const std::vector<const GeometryModel*>& geometry,
                        bool models) {
  HtmlReport page;
  // The JSON report as `--format json` writes it (no exception: a report it cannot parse is a
  // page that says so, never a crash).
  json all = json::parse(format_json(reports, sources), nullptr, /*allow_exceptions=*/false);
  json list = all.is_discarded() ? json::array() : reports.size() == 1 ? json::array({all}) : all.value("reports", json::array());
  page.data = {{"kind", "check"}, {"generator", generator()}, {"reports", list}, {"models", json::array()}, {"reach", json::array()}};
  std::vector<std::string> names;
  for (size_t i = 0; i < reports.size(); ++i) {
    page.data["reach"].push_back(reach_clouds(*reports[i].workcell, *geometry[i]));
    names.push_back(reports[i].workcell->name);
    if (!models) {  // named as a page with its models names them
      page.data["models"].push_back(fmt::format("sscs-model-{}", i));
      continue;
    }
    Expected<std::string> glb = gltf_file(*reports[i].workcell, *geometry[i], {vault_cameras(*reports[i].workcell, *geometry[i]), nullptr}, true);
    page.data["models"].push_back(glb ? json(fmt::format("sscs-model-{}", page.models.size())) : json());
    if (glb) page.models.push_back(std::move(*glb));
  }
  page.title = fmt::format("sscs check: {}", fmt::join(names, ", "));
  page.data["title"] = page.title;
  return page;
}

Expected<std::string> run_html(const OpenedRun& run, const CompileOptions& options, std::string* warnings) {
  const fs::path dir(run.dir());
  Expected<json> summary = read_json((dir / "summary.json").string());
  if (!summary) return Unexpected{summary.error()};
  json events = json::array();
  {
    std::ifstream in(dir / "events.jsonl");
    if (!in) return Unexpected{fmt::format("{}: no events.jsonl (is the run complete?)", run.given())};
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      if (line.empty()) continue;
      json e = json::parse(line, nullptr, false);
      if (e.is_discarded() || !e.is_object()) return Unexpected{fmt::format("{}/events.jsonl:{}: not a JSON object", run.given(), n)};
      events.push_back(std::move(e));
    }
  }
  json trajectories = json::object();
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir / "trajectories", ec); !ec && it != fs::directory_iterator(); it.increment(ec))
    if (it->path().extension() == ".csv")
      if (std::optional<std::string> text = read_file_bytes(it->path().string())) trajectories[it->path().stem().string()] = *text;
  Expected<std::string> glb = run_gltf(run, options, true, warnings);
  if (!glb) return Unexpected{glb.error()};
  HtmlReport page;
  // A campaign's jobs (its Gantt chart, queue and utilization).
  const std::optional<std::string> jobs = read_file_bytes((dir / "jobs.csv").string());
  page.title = fmt::format("sscs simulate: {} ({})", summary->value("scenario", std::string("run")), summary->value("status", std::string("?")));
  page.models.push_back(std::move(*glb));
  page.data = {{"kind", "run"}, {"title", page.title}, {"generator", generator()}, {"source", run.given()}, {"summary", *summary},
               {"events", events}, {"trajectories", trajectories}, {"model", "sscs-model-0"}};
  if (jobs) page.data["jobs"] = *jobs;
  return html_page(page);
}

Expected<std::string> sweep_html(const std::string& sweep_dir, const std::string& html_path) {
  Expected<json> results = read_json((fs::path(sweep_dir) / "results.json").string());
  if (!results) return Unexpected{fmt::format("{}: not a sweep folder ({})", sweep_dir, results.error())};
  if (!results->contains("variants") || !(*results)["variants"].is_array())
    return Unexpected{fmt::format("{}/results.json: no variants (is it a sweep's results?)", sweep_dir)};
  // Each variant's folder, as a link from where the page is written: its report (a check) or
  // its run's summary.
  const fs::path from = fs::absolute(fs::path(html_path)).parent_path();
  json links = json::object();
  for (const json& v : (*results)["variants"]) {
    const std::string folder = v.is_object() && v.contains("folder") && v["folder"].is_string() ? v["folder"].get<std::string>() : "";
    // A folder of the sweep, named as sscs names them: results.json is an artifact anyone can
    // edit, and a `javascript:` or `../..` folder is no variant's (the page links nothing then).
    const fs::path rel(folder);
    if (folder.empty() || rel.is_absolute() || folder.find_first_of(":\\") != std::string::npos ||
        std::any_of(rel.begin(), rel.end(), [](const fs::path& part) { return part == ".."; }))
      continue;
    const fs::path variant = fs::absolute(fs::path(sweep_dir) / folder);
    fs::path target = variant / "report.json";
    if (!fs::exists(target)) target = variant / "run" / "summary.json";
    if (!fs::exists(target)) target = variant;
    links[folder] = target.lexically_relative(from).generic_string();
  }
  HtmlReport page;
  page.title = fmt::format("sscs sweep: {}", results->value("sweep", std::string("sweep")));
  page.data = {{"kind", "sweep"}, {"title", page.title}, {"generator", generator()}, {"source", sweep_dir}, {"results", *results}, {"links", links}};
  return html_page(page);
}

Expected<std::string> report_json_html(const std::string& json_path, const CompileOptions& options,
                                       const std::function<void(const std::string&)>& confine, std::string* warnings) {
  Expected<json> report = read_json(json_path);
  if (!report) return Unexpected{report.error()};
  json list = report->contains("reports") ? (*report)["reports"] : json::array({*report});
  if (!list.is_array() || list.empty() || !list[0].is_object() || !list[0].contains("results"))
    return Unexpected{fmt::format("{}: not a check report (expected the JSON of sscs check --format json)", json_path)};
  HtmlReport page;
  page.data = {{"kind", "check"}, {"generator", generator()}, {"source", json_path}, {"reports", list}, {"models", json::array()},
               {"notes", json::array()}, {"reach", json::array()}};
  std::vector<std::string> names;
  auto note = [&](const std::string& text) {
    page.data["notes"].push_back(text);
    if (warnings) *warnings += "sscs: warning: " + text + "\n";
  };
  for (const json& r : list) {
    names.push_back(r.value("vault", std::string("?")));
    // The vault again, with the values the report says it was checked with ("set"), for its
    // model. The table is the report's whatever the vault says now; a vault that cannot be
    // found, or no longer has the objects the report names, gets no model (a picture of
    // something else would mislead).
    std::string file = r.value("file", std::string());
    if (!file.empty() && !fs::is_regular_file(file)) {
      const fs::path beside = fs::path(json_path).parent_path() / file;  // paths are as given where sscs check ran
      if (fs::is_regular_file(beside)) file = beside.string();
    }
    std::optional<std::string> glb;
    json reach = json::object();
    if (file.empty() || !fs::is_regular_file(file)) {
      note(fmt::format("{}: no 3D view: its vault '{}' is not found from here (the report names it as sscs check was given it)", r.value("vault", "?"), file));
    } else {
      CompileOptions vault_options = options;
      vault_options.overrides.clear();
      if (r.contains("set") && r["set"].is_object())
        for (const auto& [name, value] : r["set"].items()) vault_options.overrides.emplace_back(name, value.is_string() ? value.get<std::string>() : value.dump());
      confine(file);
      Sources sources;
      Diagnostics diag;
      PreparedVault vault = prepare_vault(file, vault_options, sources, diag, {.visuals = true, .contacts = nullptr});
      std::string missing;
      if (vault.wc)
        for (const json& result : r["results"])
          for (const json& subject : result.value("subject", json::array()))
            if (subject.is_string() && vault.wc->find_object(subject.get<std::string>()) < 0) missing = subject.get<std::string>();
      if (!vault.wc) {
        note(fmt::format("{}: no 3D view: its vault '{}' does not compile now", r.value("vault", "?"), file));
      } else if (!missing.empty()) {
        note(fmt::format("{}: no 3D view: the vault '{}' has no object '{}' the report names (it changed since)", r.value("vault", "?"), file, missing));
      } else {
        Expected<std::string> bytes = gltf_file(*vault.wc, vault.geometry, {vault_cameras(*vault.wc, vault.geometry), nullptr}, true);
        if (bytes) glb = std::move(*bytes);
        else note(fmt::format("{}: no 3D view: {}", r.value("vault", "?"), bytes.error()));
        if (bytes) reach = reach_clouds(*vault.wc, vault.geometry);
      }
    }
    page.data["models"].push_back(glb ? json(fmt::format("sscs-model-{}", page.models.size())) : json());
    page.data["reach"].push_back(std::move(reach));
    if (glb) page.models.push_back(std::move(*glb));
  }
  page.title = fmt::format("sscs check: {}", fmt::join(names, ", "));
  page.data["title"] = page.title;
  return html_page(page);
}

}  // namespace sscs
