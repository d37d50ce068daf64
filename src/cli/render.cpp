#include <algorithm>
#include <filesystem>
#include <optional>

#include "cli/subcommands.h"
#include "core/files.h"
#include "core/names.h"
#include "pipeline/prepare.h"
#include "render/camera_path.h"
#include "render/gltf.h"
#include "pipeline/html_report.h"
#include "pipeline/run_scenario.h"
#include "render/frames.h"
#include "render/image.h"
#include "render/renderer.h"
#include "render/replay.h"

namespace sscs::cli {

namespace {

/// `sscs export RUN|BUNDLE --out FILE.glb`: the run's vault with its motion as an animation.
int export_run(const Common& common, const std::string& path, const std::string& out) {
  const std::string ext = std::filesystem::path(out).extension().string();
  if (ext != ".glb" && ext != ".gltf") {
    std::cerr << fmt::format("sscs: error: cannot export a run to '{}': only glTF (.glb, .gltf) holds its motion\n", out);
    return kInputError;
  }
  Expected<std::shared_ptr<OpenedRun>> run = OpenedRun::open(path);
  // Its files are read within the run's folder (a bundle's: where it was unpacked).
  CompileOptions options;
  if (run && !common.apply(options, {(*run)->dir()})) return kInputError;
  std::string warnings;
  Expected<std::string> bytes = run ? run_gltf(**run, options, ext == ".glb", &warnings) : Unexpected{run.error()};
  if (!warnings.empty() && !common.quiet) std::cerr << warnings;
  std::string err = bytes ? write_file_atomic(out, *bytes) : bytes.error();
  if (!err.empty()) {
    std::cerr << (err.ends_with('\n') ? err : "sscs: error: " + err + "\n");
    return kInputError;
  }
  if (!common.quiet) std::cout << fmt::format("wrote {} (the run {} with its motion)\n", out, path);
  return kOk;
}

}  // namespace

int run_export(const Common& common, const std::string& input, const std::string& out) {
  namespace fs = std::filesystem;
  // A run folder or bundle (a .zip): the run with its motion.
  if (fs::is_directory(input) || fs::path(input).extension() == ".zip") return export_run(common, input, out);
  CompileOptions options;
  if (!common.apply(options, {input})) return kInputError;
  Sources sources;
  Diagnostics diag;
  auto [wc, geometry] = prepare_vault(input, options, sources, diag, {.visuals = true, .contacts = nullptr});  // drawn: what devices look like
  if (report_diagnostics(diag, sources, common)) return kInputError;
  if (std::string err = write_export(*wc, geometry, {vault_cameras(*wc, geometry), nullptr}, out); !err.empty()) {
    std::cerr << "sscs: error: " << err << "\n";
    return kInputError;
  }
  if (!common.quiet) std::cout << fmt::format("wrote {} ({} objects)\n", out, wc->objects.size());
  return kOk;
}

int run_report(const Common& common, const std::string& input, const std::string& html) {
  namespace fs = std::filesystem;
  if (std::string why = html_target_refusal(html, {input}); !why.empty()) {
    std::cerr << "sscs: error: " << why << "\n";
    return kInputError;
  }
  if (!common.set.empty()) {
    std::cerr << "sscs: error: sscs report takes no --set: a report shows the values it was made with\n";
    return kInputError;
  }
  CompileOptions options;
  std::error_code ec;
  Expected<std::string> page = Unexpected{fmt::format("{}: expected a run folder or bundle, a sweep folder or a check's JSON report", input)};
  if (!fs::exists(input, ec)) {
    page = Unexpected{fmt::format("{}: no such file or folder", input)};
  } else if (fs::is_directory(input, ec) && fs::exists(fs::path(input) / "results.json", ec)) {
    page = sweep_html(input, html);
  } else if ((fs::is_directory(input, ec) && fs::exists(fs::path(input) / "resolved" / "scenario.yaml", ec)) || fs::path(input).extension() == ".zip") {
    Expected<std::shared_ptr<OpenedRun>> run = OpenedRun::open(input);
    if (run && !common.apply(options, {(*run)->dir()})) return kInputError;  // read within the run's folder
    page = run ? run_html(**run, options) : Unexpected{run.error()};
  } else if (fs::is_directory(input, ec) && !fs::exists(fs::path(input) / "resolved" / "scenario.yaml", ec)) {
    page = Unexpected{fmt::format("{}: neither a run folder (resolved/scenario.yaml) nor a sweep folder (results.json)", input)};
  } else if (fs::path(input).extension() == ".json") {
    if (!common.apply(options, {input})) return kInputError;
    std::string warnings;
    page = report_json_html(input, options, [&](const std::string& vault) { common.confine_to(vault); }, &warnings);
    if (!common.quiet) std::cerr << warnings;
  }
  std::string err = page ? write_file_atomic(html, *page) : page.error();
  if (!err.empty()) {
    std::cerr << (err.ends_with('\n') ? err : "sscs: error: " + err + "\n");
    return kInputError;
  }
  if (!common.quiet) std::cout << fmt::format("HTML report: {}\n", html);
  return kOk;
}

int run_render(const Common& common, const RenderArgs& args) {
  int width = 0, height = 0;
  if (!parse_size(args.size, width, height)) return kInputError;
  if (std::filesystem::path(args.out).extension() != ".png") {
    std::cerr << fmt::format("sscs: error: --out expects a .png file, found '{}'\n", args.out);
    return kInputError;
  }
  if (args.fov != 0 && !(args.fov > 1 && args.fov < 179)) {
    std::cerr << fmt::format("sscs: error: --fov expects degrees between 1 and 179, found {:g}\n", args.fov);
    return kInputError;
  }
  Eigen::Vector3d eye, target;
  for (auto [text, v, name] : {std::tuple{&args.eye, &eye, "--eye"}, std::tuple{&args.target, &target, "--target"}})
    if (!text->empty() && !parse_vec3(*text, *v)) {
      std::cerr << fmt::format("sscs: error: {} expects x,y,z in metres, found '{}'\n", name, *text);
      return kInputError;
    }
  CompileOptions options;
  if (!common.apply(options, {args.vault})) return kInputError;
  Sources sources;
  Diagnostics diag;
  auto [wc, geometry] = prepare_vault(args.vault, options, sources, diag, {.visuals = true, .contacts = nullptr});  // drawn: what devices look like
  if (report_diagnostics(diag, sources, common)) return kInputError;
  // A named camera of the vault, compiled like a scenario's keyframe.
  std::optional<CameraPath> named;
  if (!args.camera.empty()) {
    auto it = std::find_if(wc->cameras.begin(), wc->cameras.end(), [&](const auto& c) { return c.first == args.camera; });
    if (it == wc->cameras.end()) {
      std::vector<std::string> names;
      for (const auto& c : wc->cameras) names.push_back(c.first);
      std::cerr << fmt::format("sscs: error: {} has no camera named '{}'; its cameras: {}{}\n", args.vault, args.camera,
                               names.empty() ? "none (add a cameras: mapping)" : fmt::format("{}", fmt::join(names, ", ")),
                               did_you_mean(args.camera, names));
      return kInputError;
    }
    named = CameraPath({it->second});  // compiled with the vault
  }
  RenderOptions ro;
  ro.width = width;
  ro.height = height;
  ro.shadows = args.shadows;
  // The overview (the default three-quarter view, or the vault's `overview` camera) looks into
  // the vault through the walls on its side: with 5-8 m walls it showed mostly walls.
  ro.see_through = args.walls == "see-through" || (args.walls == "auto" && ((args.eye.empty() && args.camera.empty()) || args.camera == "overview"));
  Renderer renderer(*wc, geometry, ro);
  Camera camera = named ? named->at(0, ScenePose::of(geometry), renderer.bounds(), double(width) / height)
                        : framing_camera(renderer.bounds(), args.fov > 0 ? args.fov : 45, double(width) / height);
  if (args.fov > 0) camera.fov = args.fov;
  if (!args.target.empty()) camera.target = target;
  if (!args.eye.empty()) camera.eye = eye;
  if ((camera.eye - camera.target).norm() < 1e-9) {
    std::cerr << "sscs: error: --eye and --target are the same point\n";
    return kInputError;
  }
  if (std::string err = write_file_atomic(args.out, encode_png(renderer.render(camera))); !err.empty()) {
    std::cerr << "sscs: error: " << err << "\n";
    return kInputError;
  }
  if (!common.quiet) {
    // The walls drawn see-through, by name (the first six).
    std::string through;
    const std::vector<int> walls = ro.see_through ? see_through_walls(*wc, geometry, camera.eye, renderer.bounds().center()) : std::vector<int>();
    for (size_t k = 0; k < walls.size() && k < 6; ++k) through += (k ? ", " : ", see-through: ") + wc->objects[walls[k]].name;
    if (walls.size() > 6) through += fmt::format(" and {} more", walls.size() - 6);
    std::cout << fmt::format("wrote {} ({}x{}, eye [{:.2f}, {:.2f}, {:.2f}], target [{:.2f}, {:.2f}, {:.2f}], fov {:g}{})\n",
                             args.out, width, height, camera.eye.x(), camera.eye.y(), camera.eye.z(), camera.target.x(),
                             camera.target.y(), camera.target.z(), camera.fov, through);
  }
  return kOk;
}


/// `sscs replay RUN --out DIR [--camera FILE] [--size WxH]`: the run's frames drawn again from
/// its logs (at the run's frame times, or every 1/fps of its duration), with its own cameras or
/// those of a camera file. Written to a hidden folder and renamed when complete.
int run_replay(const Common& common, const ReplayArgs& args) {
  namespace fs = std::filesystem;
  const std::string scenario = (fs::path(args.run) / "resolved" / "scenario.yaml").string();
  if (!fs::is_regular_file(scenario)) {
    std::cerr << fmt::format("sscs: error: {}: not a run folder (expected {})\n", args.run, scenario);
    return kInputError;
  }
  CompileOptions options;
  if (!common.apply(options, {args.run})) return kInputError;
  PreparedScenario ps;
  if (!ps.prepare(scenario, options, args.camera)) {
    std::cerr << ps.diag.format(ps.sources, common.color_for(stderr));
    return kInputError;
  }
  report_diagnostics(ps.diag, ps.sources, common);  // warnings
  const Workcell& wc = *ps.wc;
  const Plan& plan = *ps.plan;
  RenderOptions ro;
  ro.width = plan.settings.width;
  ro.height = plan.settings.height;
  if (!args.size.empty() && !parse_size(args.size, ro.width, ro.height)) return kInputError;
  ro.shadows = args.shadows;
  ro.see_through = args.walls == "see-through";
  std::vector<int> driven;
  for (const Track& track : plan.tracks) driven.push_back(track.object);
  auto recorded = RecordedRun::read(args.run, wc, ps.geometry, driven);
  if (!recorded) {
    std::cerr << "sscs: error: " << recorded.error() << "\n";
    return kInputError;
  }
  recorded->set_arrivals(plan.arrivals);
  Expected<std::vector<double>> frame_times = recorded->frame_times(plan.settings.fps);
  if (!frame_times) {
    std::cerr << "sscs: error: " << frame_times.error() << "\n";
    return kInputError;
  }
  const std::vector<double>& times = *frame_times;
  if (std::string why = replay_target_refusal(args.out, args.force); !why.empty()) {
    std::cerr << "sscs: error: " << why << "\n";
    return kInputError;
  }
  StagedDir staging(args.out);
  {
    FrameRecorder recorder(wc, ps.geometry, ps.cameras, ro, staging.path() + "/frames");
    recorder.set_focus([&](double t) { return plan_focus(wc, plan, t); });  // the action camera's, as the run's
    for (size_t n = 0; n < times.size(); ++n) recorder.frame(static_cast<int>(n), times[n], recorded->at(times[n]));
    recorder.finish(staging.path() + "/contact_sheet.png");
  }
  if (std::string err = staging.commit(); !err.empty()) {
    std::cerr << "sscs: error: " << err << "\n";
    return kInputError;
  }
  if (!common.quiet) std::cout << fmt::format("replayed {} frames of {} into {}\n", times.size(), args.run, args.out);
  return kOk;
}


}  // namespace sscs::cli
