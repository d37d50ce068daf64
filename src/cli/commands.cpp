#include "cli/commands.h"
#include "pipeline/prepare.h"

#include <unistd.h>

#include <csignal>

#include <cstdio>
#include <fstream>
#include <functional>
#include <filesystem>
#include <map>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "check/check.h"
#include "compile/compile.h"
#include "geometry/export.h"
#include "geometry/geometry.h"
#include "load/scenario.h"
#include "pipeline/resolved.h"
#include "pipeline/type_listing.h"
#include "core/pose.h"
#include "simulate/plan.h"
#include "simulate/simulate.h"
#include "core/data_dirs.h"
#include "sweep/sweep.h"
#include "core/timer.h"
#include "render/gl.h"
#include "render/camera_path.h"
#include "render/frames.h"
#include "render/renderer.h"
#include "render/replay.h"
#include "report/compare.h"
#include "core/files.h"
#include "core/limits.h"
#include "core/names.h"
#include "report/report.h"

namespace sscs {

namespace {

constexpr int kOk = 0, kViolations = 1, kInputError = 2, kInternalError = 3;

/// Options every subcommand takes.
struct Common {
  std::vector<std::string> library;
  std::vector<std::string> plugins;
  std::vector<std::string> package_paths;
  std::vector<std::string> set;
  bool quiet = false;
  bool allow_vault_plugins = false;
  std::vector<std::string> roots;  // --root
  bool allow_outside_root = false;
  std::string color = "auto";

  /// The options every command takes; `with_set` false for commands that read no vault (types).
  void add_to(CLI::App* app, bool with_set = true) {
    app->add_option("--library", library, "extra type-library folder (repeatable)");
    app->add_option("--plugins", plugins, "load the plugins in this folder (repeatable)");
    app->add_flag("--allow-vault-plugins", allow_vault_plugins, "also load the folders a vault's plugins: key names");
    app->add_option("--package-path", package_paths, "folder of ROS packages for URDF package:// references (repeatable)");
    app->add_option("--root", roots, "a folder files named inside input files may come from, besides the project root "
                                     "(the git work tree holding the input, else its folder); repeatable");
    app->add_flag("--allow-outside-root", allow_outside_root, "let input files name files outside the project root");
    if (with_set) app->add_option("--set", set, "parameter override NAME=VALUE (repeatable)");
    app->add_flag("--quiet", quiet, "print only summaries and errors");
    app->add_option("--color", color, "colour output: auto, always or never")
        ->check(CLI::IsMember({"auto", "always", "never"}));
  }
  /// Confines what files named inside `input` may read: its project root first (the one messages
  /// name), the --root folders, the standard library and the folders given as options.
  void confine_to(const std::string& input) const {
    if (allow_outside_root) return;
    std::vector<std::string> allowed = {project_root_of(input)};
    allowed.insert(allowed.end(), roots.begin(), roots.end());
    allowed.push_back(data_dir("library"));
    for (const auto* dirs : {&library, &plugins, &package_paths}) allowed.insert(allowed.end(), dirs->begin(), dirs->end());
    for (const std::string& dir : ros_package_path()) allowed.push_back(dir);
    confine_reads(allowed);
  }
  bool color_for(FILE* stream) const {
    if (color == "always") return true;
    if (color == "never") return false;
    return isatty(fileno(stream)) && std::getenv("NO_COLOR") == nullptr;
  }
  /// The options in `options`, and the folders files named inside `inputs` (the files or run
  /// folder the command line names) may come from: the project root, the standard library and
  /// the folders given as options. A malformed --set NAME=VALUE is an input error.
  bool apply(CompileOptions& options, const std::vector<std::string>& inputs) const {
    for (const auto& [option, dirs] : {std::pair{"--root", &roots}, std::pair{"--package-path", &package_paths}})
      for (const std::string& r : *dirs) {
        std::error_code ec;
        if (!std::filesystem::is_directory(r, ec)) {
          std::cerr << fmt::format("sscs: error: {} '{}' is no folder\n", option, r);
          return false;
        }
      }
    for (const std::string& input : inputs) confine_to(input);
    for (const std::string& s : set) {
      auto eq = s.find('=');
      if (eq == std::string::npos || eq == 0) {
        std::cerr << fmt::format("sscs: error: --set expects NAME=VALUE, found '{}'\n", s);
        return false;
      }
      options.overrides.emplace_back(s.substr(0, eq), s.substr(eq + 1));
    }
    options.library_dirs = library;
    options.plugin_dirs = plugins;
    options.allow_vault_plugins = allow_vault_plugins;
    options.package_paths = package_paths;
    return true;
  }
};

struct CheckArgs {
  std::vector<std::string> vaults;
  std::string format;
  std::string out;
  bool strict = false;
  std::string baseline;
};

/// The format named, else the --out extension's, else text.
std::string pick_format(const CheckArgs& a) {
  if (!a.format.empty()) return a.format;
  std::string ext = std::filesystem::path(a.out).extension().string();
  if (ext == ".json") return "json";
  if (ext == ".xml") return "junit";
  if (ext == ".sarif") return "sarif";
  return "text";
}

/// Writes the diagnostics to stderr, warnings then errors; true when there were errors (the
/// command then stops, having written nothing).
bool report_diagnostics(const Diagnostics& diag, const Sources& sources, const Common& common) {
  if (!diag.has_errors() && diag.warnings().empty()) return false;
  std::cerr << diag.format(sources, common.color_for(stderr));
  return diag.has_errors();
}

int run_check(const Common& common, const CheckArgs& args) {
  std::string format = pick_format(args);
  CompileOptions options;
  if (!common.apply(options, args.vaults)) return kInputError;
  Sources sources;
  Diagnostics diag;
  // --strict: what sscs would skip or assume with a warning (a degenerate URDF shape) is an
  // input error, as a failed warning constraint fails the gate.
  diag.set_strict(args.strict, "(a warning; an error with --strict)");
  std::vector<Workcell> cells;
  std::vector<GeometryModel> geometry;
  std::vector<std::vector<Diagnostic>> input_warnings;
  cells.reserve(args.vaults.size());
  for (const std::string& path : args.vaults) {
    common.confine_to(path);  // each vault reads within its own project, not another's
    const size_t warned = diag.warnings().size();
    PreparedVault vault = prepare_vault(path, options, sources, diag);
    if (vault.wc) {
      geometry.push_back(std::move(vault.geometry));
      cells.push_back(std::move(*vault.wc));
      input_warnings.emplace_back(diag.warnings().begin() + warned, diag.warnings().end());
    }
    if (diag.full()) break;
  }
  // Inputs in the order they are named: the vaults, then the baseline; every error of both.
  std::optional<Baseline> baseline;
  std::string baseline_error;
  if (!args.baseline.empty()) {
    Expected<Baseline> read = read_baseline(args.baseline);
    if (read) baseline = std::move(*read);
    else baseline_error = read.error();
  }
  if (report_diagnostics(diag, sources, common) || !baseline_error.empty()) {
    if (!baseline_error.empty()) std::cerr << "sscs: error: " << baseline_error << "\n";
    return kInputError;  // nothing written
  }
  StageTimer timer;
  std::vector<VaultReport> reports;
  CheckOptions check_options;
  check_options.describe_passes = format != "text";  // the text report prints failures only
  for (size_t i = 0; i < cells.size(); ++i) {
    reports.push_back({&cells[i], args.vaults[i], check(cells[i], geometry[i], check_options), std::nullopt, input_warnings[i]});
    if (baseline) reports.back().baseline = compare_with_baseline(cells[i], reports.back().report, *baseline);
  }
  timer.lap("check");
  // JSON, JUnit and SARIF are streamed as they are made (to stdout, or to a temporary file renamed
  // into place when complete): a report of 100,000 results is never held whole in memory.
  auto write_report = [&](std::ostream& out) {
    if (format == "json") {
      write_json(out, reports, sources);
    } else if (format == "junit") {
      write_junit(out, reports, sources, args.strict);
    } else if (format == "sarif") {
      write_sarif(out, reports, sources, args.strict, std::filesystem::current_path().string());
    } else {
      // --quiet shortens what the terminal shows, never a report written to a file.
      bool terminal = args.out.empty();
      out << format_text(reports, sources, {terminal && common.color_for(stdout), terminal && common.quiet, args.strict});
    }
  };
  if (args.out.empty()) {
    write_report(std::cout);
    std::cout << std::flush;
    timer.lap("report");
  } else {
    // A report written over a file it was made from (`--out vault.yaml`) would destroy the input.
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path target = fs::weakly_canonical(args.out, ec);
    for (uint32_t f = 1; f < sources.size(); ++f)
      if (fs::exists(sources.path(f), ec) && fs::weakly_canonical(sources.path(f), ec) == target) {
        std::cerr << fmt::format("sscs: error: --out '{}' is an input of this check ({}); write the report elsewhere\n", args.out,
                                 sources.path(f));
        return kInputError;
      }
    std::string err = write_file_atomic(args.out, write_report);
    timer.lap("report");
    if (!err.empty()) {
      std::cerr << "sscs: error: " << err << "\n";
      return kInputError;
    }
    if (!common.quiet) {
      // Keep the summary lines on the terminal when the report goes to a file.
      std::cout << format_text(reports, sources, {common.color_for(stdout), true, args.strict});
    }
  }
  bool violated = std::any_of(reports.begin(), reports.end(), [&](const VaultReport& r) { return r.violated(args.strict); });
  return violated ? kViolations : kOk;
}

int run_types(const Common& common, const std::string& format) {
  Sources sources;
  Diagnostics diag;
  std::vector<std::pair<std::string, SourceMark>> dirs = {{standard_library_dir(), {}}};
  for (const std::string& d : common.library) dirs.push_back({d, {}});
  PluginSet plugins;
  for (const std::string& d : common.plugins) plugins.load_folder(d);  // PluginError: exit 3
  std::vector<ObjectType> types = load_library(dirs, sources, diag, common.package_paths, plugins.types());
  // `types` checks a library: a broken type's errors are input errors here (vaults that do not
  // use it are not affected).
  for (const ObjectType& t : types)
    if (t.broken)
      for (const Diagnostic& d : t.problems)
        if (!d.warning) diag.error(d.mark, d.message);
  if (diag.has_errors()) {
    report_diagnostics(diag, sources, common);
    return kInputError;
  }
  CompileOptions instance_options;
  instance_options.package_paths = common.package_paths;
  // The listing instances every type: what that finds in the library's files (a mesh that
  // cannot be read, an SRDF naming no link) fails the command, before anything is printed.
  std::ostringstream listing;
  write_type_listing(listing, std::move(types), plugins, instance_options, format == "json", sources, diag);
  if (report_diagnostics(diag, sources, common)) return kInputError;
  std::cout << listing.str();
  return kOk;
}

int run_export(const Common& common, const std::string& vault, const std::string& out) {
  CompileOptions options;
  if (!common.apply(options, {vault})) return kInputError;
  Sources sources;
  Diagnostics diag;
  auto [wc, geometry] = prepare_vault(vault, options, sources, diag, {.visuals = true, .contacts = nullptr});  // drawn: what devices look like
  if (report_diagnostics(diag, sources, common)) return kInputError;
  if (std::string err = export_workcell(*wc, geometry, out); !err.empty()) {
    std::cerr << "sscs: error: " << err << "\n";
    return kInputError;
  }
  if (!common.quiet) std::cout << fmt::format("wrote {} ({} objects)\n", out, wc->objects.size());
  return kOk;
}

}  // namespace

/// "WIDTHxHEIGHT" within 16..8192; false (with the message printed) otherwise.
bool parse_size(const std::string& text, int& width, int& height) {
  char tail;
  if (std::sscanf(text.c_str(), "%dx%d%c", &width, &height, &tail) == 2 && width >= 16 && height >= 16 && width <= 8192 &&
      height <= 8192)
    return true;
  std::cerr << fmt::format("sscs: error: --size expects WIDTHxHEIGHT between 16 and 8192, found '{}'\n", text);
  return false;
}

struct RenderArgs {
  std::string vault, out, eye, target, camera, size = "1280x720";
  bool shadows = false;
  double fov = 0;  ///< 0: not given (45, or the named camera's)
};

/// "x,y,z" -> a vector; false when it is not three numbers.
bool parse_vec3(const std::string& text, Eigen::Vector3d& v) {
  double x, y, z;
  char tail;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &x, &y, &z, &tail) != 3) return false;
  v = {x, y, z};
  return v.allFinite();
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
  if (!common.quiet)
    std::cout << fmt::format("wrote {} ({}x{}, eye [{:.2f}, {:.2f}, {:.2f}], target [{:.2f}, {:.2f}, {:.2f}], fov {:g})\n",
                             args.out, width, height, camera.eye.x(), camera.eye.y(), camera.eye.z(), camera.target.x(),
                             camera.target.y(), camera.target.z(), camera.fov);
  return kOk;
}

struct ReplayArgs {
  std::string run, out, camera, size;
  bool shadows = false;
};

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
  auto recorded = RecordedRun::read(args.run, wc, ps.geometry);
  if (!recorded) {
    std::cerr << "sscs: error: " << recorded.error() << "\n";
    return kInputError;
  }
  // The run's own frame times when it recorded frames; else every 1/fps of its duration.
  std::vector<double> times;
  if (std::ifstream index(fs::path(args.run) / "frames" / "index.csv"); index) {
    std::string line;
    std::getline(index, line);
    while (std::getline(index, line)) times.push_back(std::stod(line.substr(line.find(',') + 1)));
  } else {
    for (int n = 0; n <= static_cast<int>(recorded->duration() * plan.settings.fps + 1e-9); ++n)
      times.push_back(static_cast<double>(n) / plan.settings.fps);
  }
  StagedDir staging(args.out);
  {
    FrameRecorder recorder(wc, ps.geometry, ps.cameras, ro, staging.path() + "/frames");
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

volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_interrupt(int) { g_interrupted = 1; }

/// While alive, SIGINT and SIGTERM set g_interrupted (a run stops cleanly, writing nothing half);
/// the handlers before it come back when it goes.
class InterruptGuard {
 public:
  InterruptGuard() {
    struct sigaction action = {};
    action.sa_handler = on_interrupt;
    sigaction(SIGINT, &action, &old_int_);
    sigaction(SIGTERM, &action, &old_term_);
  }
  ~InterruptGuard() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  struct sigaction old_int_ = {}, old_term_ = {};
};

struct SimulateArgs {
  std::string scenario;
  std::string out;     // default: run-<scenario name> unless only a bundle is asked for
  std::string bundle;
  bool no_frames = false;
  std::string video;
  bool shadows = false;
  bool force = false;  // replace an existing run folder or bundle
  std::string wall_limit;  // s of wall-clock time ("": none)
};

int run_simulate(const Common& common, const SimulateArgs& args) {
  const std::string& bundle = args.bundle;
  const std::string& video = args.video;
  const bool no_frames = args.no_frames;
  std::string out = args.out;
  CompileOptions options;
  if (!common.apply(options, {args.scenario})) return kInputError;
  if (!video.empty()) {
    std::string why = no_frames ? "--video needs frames; it cannot go with --no-frames"
                    : std::filesystem::path(video).extension() != ".mp4" ? fmt::format("--video expects a .mp4 file, found '{}'", video)
                    : "";
    if (!why.empty()) {
      std::cerr << "sscs: error: " << why << "\n";
      return kInputError;
    }
  }
  if (!bundle.empty() && std::filesystem::path(bundle).extension() != ".zip") {
    std::cerr << fmt::format("sscs: error: --bundle expects a .zip file, found '{}'\n", bundle);
    return kInputError;
  }
  PreparedScenario ps;
  if (!ps.prepare(args.scenario, options)) {
    std::cerr << ps.diag.format(ps.sources, common.color_for(stderr));
    return kInputError;
  }
  report_diagnostics(ps.diag, ps.sources, common);  // warnings
  const auto& spec = ps.spec;
  const auto& wc = ps.wc;
  const auto& plan = ps.plan;
  const GeometryModel& geometry = ps.geometry;
  if (!video.empty() && !plan->settings.frames) {
    std::cerr << fmt::format("sscs: error: --video needs frames, and scenario '{}' records none (add record.frames)\n", spec->name);
    return kInputError;
  }
  if (!video.empty() && !FrameRecorder::ffmpeg_available()) {
    std::cerr << "sscs: error: --video needs ffmpeg, which is not installed (apt-get install ffmpeg); or run without --video\n";
    return kInputError;
  }
  if (out.empty() && bundle.empty()) out = "run-" + spec->name;
  // An earlier run (perhaps of another scenario file with the same name) is never replaced
  // silently; and --force replaces only a run (a folder with summary.json, a bundle .zip) or an
  // empty folder, never a folder of something else.
  for (const std::string& target : {out, bundle}) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (target.empty() || !fs::exists(fs::symlink_status(target, ec))) continue;
    const bool folder = fs::is_directory(fs::symlink_status(target, ec));
    const bool a_run = folder ? fs::exists(fs::path(target) / "summary.json", ec) || fs::is_empty(target, ec)
                              : fs::path(target).extension() == ".zip" && target == bundle;
    if (!a_run) {
      std::cerr << fmt::format("sscs: error: '{}' exists and is not a run of sscs simulate; it is never replaced, even with "
                               "--force: choose another {}\n", target, target == bundle ? "--bundle file" : "--out folder");
      return kInputError;
    }
    if (!args.force) {
      std::cerr << fmt::format("sscs: error: '{}' exists (an earlier run?); pass --force to replace it, or choose another {}\n",
                               target, target == bundle ? "--bundle file" : "--out folder");
      return kInputError;
    }
  }
  RunInputs inputs = collect_run_inputs(*spec, ps.overrides, *wc, geometry, ps.sources);
  RunOptions run;
  run.out_dir = out;
  run.bundle = bundle;
  run.scenario_name = spec->name;
  run.inputs = &inputs;
  run.interrupted = &g_interrupted;
  if (!args.wall_limit.empty()) {
    char* end = nullptr;
    run.wall_limit = std::strtod(args.wall_limit.c_str(), &end);
    if (end != args.wall_limit.c_str() + args.wall_limit.size() || !std::isfinite(run.wall_limit) || !(run.wall_limit > 0)) {
      std::cerr << fmt::format("sscs: error: --wall-limit expects a number of seconds above 0, found '{}'\n",
                               printable(args.wall_limit));
      return kInputError;
    }
  }
  if (!common.quiet) run.progress = isatty(fileno(stderr)) ? RunOptions::Progress::Live : RunOptions::Progress::Lines;
  run.progress_to = &std::cerr;
  std::optional<InterruptGuard> interrupts(std::in_place);
  // The run is assembled here; run_simulation moves it into place (and packs the bundle) when it
  // is complete. Whatever else happens, the staging folder goes with this scope.
  StagedDir staging(out.empty() ? bundle : out);
  run.work_dir = staging.path();
  std::unique_ptr<FrameRecorder> recorder;
  std::string error;
  RunSummary summary;
  {
    if (plan->settings.frames && !no_frames) {
      RenderOptions ro;
      ro.width = plan->settings.width;
      ro.height = plan->settings.height;
      ro.shadows = args.shadows;
      recorder = std::make_unique<FrameRecorder>(*wc, geometry, ps.cameras, ro, run.work_dir + "/frames");
      if (!video.empty()) recorder->record_video(video, plan->settings.fps);
      run.frame_interval = 1.0 / plan->settings.fps;
      run.on_frame = [&](int n, double t, const ScenePose& pose) { recorder->frame(n, t, pose); };
      run.on_step_end = [&](const PlannedStep& ps, double t, const ScenePose& pose) {
        std::string who = ps.device >= 0 ? " " + wc->objects[ps.device].name : "";
        recorder->step_end(ps.index, fmt::format("{}. {}{}  t = {:.2f} s", ps.index + 1, step_kind_name(ps.kind), who, t), t, pose);
      };
      run.before_write = [&] {
        recorder->finish(run.work_dir + "/contact_sheet.png");
        return std::string();
      };
    }
    Expected<RunSummary> ran = run_simulation(*wc, geometry, *plan, run);
    if (ran) summary = std::move(*ran);
    else error = ran.error();
    recorder.reset();  // before the staging folder it writes into goes
  }
  interrupts.reset();
  if (summary.interrupted) {
    std::cerr << "sscs: interrupted; nothing written\n";
    return 128 + SIGINT;
  }
  if (!error.empty()) {
    std::cerr << "sscs: error: " << error << "\n";
    return kInternalError;
  }
  std::string where = out.empty() ? bundle : bundle.empty() ? out : fmt::format("{} and {}", out, bundle);
  // A run that stopped says why and when, and has no cycle time.
  std::string status = run_status_name(summary.status);
  if (!summary.stopped_by.empty())
    status += fmt::format(" ({} at {:g} s{}{}), no cycle time", summary.stopped_by, stable(summary.stopped_at),
                          summary.stop_message.empty() ? "" : ": ", printable(within_window(summary.stop_message)));
  else
    status += fmt::format(", cycle time {:g} s", stable(summary.cycle_time));
  std::cout << fmt::format("{}: {}, {} collisions, {} events; written to {}\n", spec->name, status, summary.collisions,
                           summary.events, where);
  return summary.status == RunStatus::Ok ? kOk : kViolations;
}

struct SweepArgs {
  std::string sweep;
  std::string out;
  unsigned jobs = 0;
  std::string shard;
  bool force = false;
  bool resume = true;
  double variant_timeout = 0;
  double variant_memory = 0;
  std::vector<std::string> merge_dirs;
};

/// "K/N" with 0 <= K < N.
bool parse_shard(const std::string& text, unsigned& k, unsigned& n) {
  auto slash = text.find('/');
  if (slash == std::string::npos) return false;
  try {
    size_t a = 0, b = 0;
    unsigned long kk = std::stoul(text.substr(0, slash), &a), nn = std::stoul(text.substr(slash + 1), &b);
    if (a != slash || b != text.size() - slash - 1 || nn == 0 || kk >= nn || nn > 100000) return false;
    k = static_cast<unsigned>(kk);
    n = static_cast<unsigned>(nn);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

int report_sweep(const SweepOutcome& o, const char* verb) {
  switch (o.end) {
    case SweepOutcome::End::InputError:
      std::cerr << "sscs: error: " << o.message << "\n";
      return kInputError;
    case SweepOutcome::End::Interrupted:
      std::cerr << "sscs: " << o.message << "\n";
      return 128 + SIGINT;
    case SweepOutcome::End::Failed:
      std::cerr << "sscs: error: " << o.message << "\n";
      return kInternalError;
    case SweepOutcome::End::OutputError:  // as every command reports a write that failed
      std::cerr << "sscs: error: " << o.message << "\n";
      return kInputError;
    case SweepOutcome::End::Done:
      break;
  }
  // The summary line is printed even with --quiet: it is the one line a job log needs.
  std::string resumed = o.resumed ? fmt::format(" ({} done before)", o.resumed) : "";
  std::cout << fmt::format("{} {} variants{}: {} pass, {} fail, {} error; results in {}/results.csv\n", verb, o.mine, resumed,
                           o.pass, o.fail, o.error, o.out);
  return o.fail + o.error > 0 ? kViolations : kOk;
}

int run_sweep_command(const Common& common, const SweepArgs& args) {
  SweepOptions options;
  if (!common.apply(options.compile, args.sweep.empty() ? std::vector<std::string>{} : std::vector<std::string>{args.sweep}))
    return kInputError;
  if (!args.shard.empty() && !parse_shard(args.shard, options.shard, options.shards)) {
    std::cerr << fmt::format("sscs: error: --shard expects K/N with 0 <= K < N (e.g. 3/8), found '{}'\n", args.shard);
    return kInputError;
  }
  if (!(args.variant_timeout >= 0) || !std::isfinite(args.variant_timeout)) {  // nan and inf too
    std::cerr << fmt::format("sscs: error: --variant-timeout must be a number of seconds, at least 0, found {}\n",
                             args.variant_timeout);
    return kInputError;
  }
  options.out = args.out;
  options.jobs = args.jobs;
  options.force = args.force;
  options.variant_timeout = args.variant_timeout;
  if (!(args.variant_memory >= 0) || !std::isfinite(args.variant_memory)) {
    std::cerr << fmt::format("sscs: error: --variant-memory must be a number of GB, at least 0, found {}\n",
                             args.variant_memory);
    return kInputError;
  }
  options.variant_memory_gb = args.variant_memory;
  options.interrupted = &g_interrupted;
  if (!common.quiet) options.progress = isatty(fileno(stderr)) ? ProgressBar::Mode::Live : ProgressBar::Mode::Lines;
  Sources sources;
  Diagnostics diag;
  SweepOutcome outcome;
  {
    InterruptGuard interrupts;
    outcome = run_sweep(args.sweep, options, sources, diag);
  }
  if (report_diagnostics(diag, sources, common)) return kInputError;
  return report_sweep(outcome, "swept");
}

int run_compare(const std::vector<std::string>& paths, const std::string& format) {
  Expected<std::vector<RunRecord>> runs = read_runs(paths);
  if (!runs) {
    std::cerr << "sscs: error: " << runs.error() << "\n";
    return kInputError;
  }
  std::cout << (format == "json" ? compare_json(*runs) : format == "csv" ? compare_csv(*runs) : compare_text(*runs));
  return kOk;
}

int run_cli(int argc, char** argv) {
  try {
    CLI::App app{"sscs: the Storage Simulation Construction Set"};
    app.set_version_flag("--version", std::string("sscs ") + SSCS_VERSION);
    app.require_subcommand(1);
    Common common;
    // The subcommands: each its options and what it runs (one of them runs).
    struct Command {
      CLI::App* app;
      std::function<int()> run;
    };
    std::vector<Command> commands;
    auto command = [&](const char* name, const char* help, std::function<int()> run) {
      commands.push_back({app.add_subcommand(name, help), std::move(run)});
      return commands.back().app;
    };

    CheckArgs check_args;
    CLI::App* check_cmd = command("check", "compile each vault and check its constraints", [&] { return run_check(common, check_args); });
    check_cmd->add_option("VAULT", check_args.vaults, "vault files")->required();
    check_cmd->add_option("--format", check_args.format,
                          "text, json, junit or sarif (default: from --out's extension .json/.xml/.sarif, else text)")
        ->check(CLI::IsMember({"text", "json", "junit", "sarif"}));
    check_cmd->add_option("--out", check_args.out, "write the report to this file (atomically)");
    check_cmd->add_flag("--strict", check_args.strict, "failed warnings fail the gate too");
    check_cmd->add_option("--baseline", check_args.baseline, "classify results against an earlier report (--format json): new failure, fixed, still failing, "
                    "unchanged; exit 1 only for new failures");
    common.add_to(check_cmd);

    std::string types_format = "text";
    CLI::App* types_cmd = command("types", "list the object types, devices and constraint kinds", [&] { return run_types(common, types_format); });
    types_cmd->add_option("--format", types_format, "text or json")->check(CLI::IsMember({"text", "json"}));
    common.add_to(types_cmd, /*with_set=*/false);  // types reads no vault: --set would do nothing

    std::string export_vault, export_out;
    CLI::App* export_cmd = command("export", "the composed workcell as one 3D file (glb, gltf, obj, stl)",
                                   [&] { return run_export(common, export_vault, export_out); });
    export_cmd->add_option("VAULT", export_vault, "vault file")->required();
    export_cmd->add_option("--out", export_out, "output file: .glb, .gltf, .obj or .stl")->required();
    common.add_to(export_cmd);

    SimulateArgs sim_args;
    CLI::App* sim_cmd = command("simulate", "run a scenario in ODE physics and write its logs", [&] { return run_simulate(common, sim_args); });
    sim_cmd->add_option("SCENARIO", sim_args.scenario, "scenario file")->required();
    sim_cmd->add_option("--out", sim_args.out, "output folder (default: run-<scenario> unless --bundle), replaced atomically");
    sim_cmd->add_option("--bundle", sim_args.bundle, "write the run as one zip archive too (or only, without --out)");
    sim_cmd->add_flag("--no-frames", sim_args.no_frames, "do not render the scenario's frames");
    sim_cmd->add_option("--video", sim_args.video, "also encode the frames as an H.264 .mp4 through ffmpeg (when installed)");
    sim_cmd->add_flag("--shadows", sim_args.shadows, "frames with shadows of the key light");
    sim_cmd->add_flag("--force", sim_args.force, "replace an existing run folder or bundle (never replaced without it)");
    sim_cmd->add_option("--wall-limit", sim_args.wall_limit, "seconds of wall-clock time the run may take; past it the run "
                        "stops as failed with a wall_limit event (default: no limit; sim.limit bounds simulated time)");
    common.add_to(sim_cmd);

    RenderArgs render_args;
    CLI::App* render_cmd = command("render", "one still image of a vault (PNG, offscreen OpenGL)", [&] { return run_render(common, render_args); });
    render_cmd->add_option("VAULT", render_args.vault, "vault file")->required();
    render_cmd->add_option("--out", render_args.out, "output .png file")->required();
    render_cmd->add_option("--eye", render_args.eye, "camera position x,y,z (m); default: a three-quarter view framing the vault");
    render_cmd->add_option("--target", render_args.target, "point looked at x,y,z (m); default: the vault's centre");
    render_cmd->add_option("--fov", render_args.fov, "vertical field of view, degrees (default 45, or the named camera's)");
    render_cmd->add_option("--camera", render_args.camera, "a named camera of the vault (its cameras: mapping)");
    render_cmd->add_flag("--shadows", render_args.shadows, "shadows of the key light");
    render_cmd->add_option("--size", render_args.size, "WIDTHxHEIGHT in pixels (default 1280x720)");
    common.add_to(render_cmd);

    ReplayArgs replay_args;
    CLI::App* replay_cmd = command("replay", "render a recorded run's frames again, from its logs", [&] { return run_replay(common, replay_args); });
    replay_cmd->add_option("RUN", replay_args.run, "run folder written by sscs simulate")->required();
    replay_cmd->add_option("--out", replay_args.out, "output folder (frames/ and index.csv)")->required();
    replay_cmd->add_option("--camera", replay_args.camera, "camera file (sscs: 1, cameras: [...]); default: the run's cameras");
    replay_cmd->add_option("--size", replay_args.size, "WIDTHxHEIGHT (default: the run's frame size)");
    replay_cmd->add_flag("--shadows", replay_args.shadows, "frames with shadows of the key light");
    common.add_to(replay_cmd);

    std::vector<std::string> compare_runs;
    std::string compare_format = "text";
    CLI::App* compare_cmd = command("compare", "summaries of simulation runs side by side", [&] { return run_compare(compare_runs, compare_format); });
    compare_cmd->add_option("RUN", compare_runs, "run folders or bundles (.zip) written by sscs simulate")->required();
    compare_cmd->add_option("--format", compare_format, "text, json or csv")->check(CLI::IsMember({"text", "json", "csv"}));

    SweepArgs sweep_args;
    std::string merge_out;
    CLI::App* merge_cmd = nullptr;
    CLI::App* sweep_cmd = command("sweep", "run a parameter study: every variant checked (and simulated), one table", [&] {
      if (merge_cmd->parsed()) return report_sweep(merge_sweep(sweep_args.merge_dirs, merge_out), "merged");
      if (sweep_args.sweep.empty()) {
        std::cerr << "sscs: error: sweep needs a sweep file (sscs sweep SWEEP) or merge (sscs sweep merge DIR... --out DIR)\n";
        return kInputError;
      }
      if (!sweep_args.resume) sweep_args.force = true;
      return run_sweep_command(common, sweep_args);
    });
    sweep_cmd->add_option("SWEEP", sweep_args.sweep, "sweep file");
    sweep_cmd->add_option("--out", sweep_args.out, "results folder (default: sweep-<name>); a rerun into it resumes");
    sweep_cmd->add_option("--jobs,-j", sweep_args.jobs, "variants at once (default: one per core)")->check(CLI::Range(1u, 4096u));
    sweep_cmd->add_option("--shard", sweep_args.shard, "K/N: run only the variants whose index % N == K (a Slurm array task)");
    sweep_cmd->add_flag("--resume,!--no-resume", sweep_args.resume, "skip variants already complete in --out (the default)");
    sweep_cmd->add_flag("--force", sweep_args.force, "redo every variant (clears --out)");
    sweep_cmd->add_option("--variant-timeout", sweep_args.variant_timeout, "seconds a variant may take before it is stopped and recorded as error (default: no limit)");
    sweep_cmd->add_option("--variant-memory", sweep_args.variant_memory, "GB of memory a variant may take before it is recorded as error (default: the machine's memory shared by the jobs, at least 1)");
    common.add_to(sweep_cmd);
    merge_cmd = sweep_cmd->add_subcommand("merge", "join shard folders into one table, as one run would have written it");
    merge_cmd->add_option("DIR", sweep_args.merge_dirs, "shard folders (--out of each sscs sweep --shard K/N)")->required();
    merge_cmd->add_option("--out", merge_out, "the merged folder")->required();

    // A word where the command goes that is no command: say so, not "A subcommand is required".
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
    if (argc > 1 && argv[1][0] != '-' && std::find(names.begin(), names.end(), argv[1]) == names.end()) {
      std::cerr << fmt::format("sscs: error: '{}' is not a command; the commands are {} (sscs --help)\n", printable(argv[1]),
                               fmt::join(names, ", "));
      return kInputError;
    }
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      int code = app.exit(e);
      return code == 0 ? kOk : kInputError;
    }
    if (std::string error = limit_environment_error(); !error.empty()) {
      std::cerr << "sscs: error: " << error << "\n";
      return kInputError;
    }
    for (const Command& c : commands)
      if (c.app->parsed()) return c.run();
    return kInputError;
  } catch (const OutputError& e) {  // a full disk, an unwritable folder: the same in every command
    std::cerr << "sscs: error: " << e.what() << "\n";
    return kInputError;
  } catch (const PluginError& e) {
    std::cerr << "sscs: error: " << e.what() << "\n";
    return kInternalError;
  } catch (const gl::RenderUnavailable& e) {
    std::cerr << "sscs: error: " << e.what() << "\n";
    return kInternalError;
  } catch (const std::exception& e) {
    std::cerr << "sscs: internal error: " << e.what() << "\n";
    return kInternalError;
  }
}

}  // namespace sscs
