#include "pipeline/run_scenario.h"

#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "core/archive.h"
#include "core/files.h"
#include "pipeline/resolved.h"
#include "render/frames.h"

namespace sscs {

namespace fs = std::filesystem;

std::string run_targets_refusal(const std::string& out, const std::string& bundle, bool force) {
  for (const std::string& target : {out, bundle}) {
    std::error_code ec;
    if (target.empty() || !fs::exists(fs::symlink_status(target, ec))) continue;
    const bool folder = fs::is_directory(fs::symlink_status(target, ec));
    // A bundle is a run's when it is a zip holding summary.json (any .zip was replaced).
    const bool a_run = folder ? fs::exists(fs::path(target) / "summary.json", ec) || fs::is_empty(target, ec)
                              : target == bundle && fs::path(target).extension() == ".zip" &&
                                    read_zip_entry(target, "summary.json").has_value();
    const char* what = target == bundle ? "--bundle file" : "--out folder";
    if (!a_run)
      return fmt::format("'{}' exists and is not {} of sscs simulate; it is never replaced, even with --force: choose another {}",
                         target, target == bundle ? "the bundle of a run" : "a run", what);
    if (!force) return fmt::format("'{}' exists (an earlier run?); pass --force to replace it, or choose another {}", target, what);
  }
  return "";
}

std::string run_request_refusal(const PreparedScenario& ps, const RunRequest& request) {
  if (request.video.empty()) return "";
  if (!ps.plan->settings.frames)
    return fmt::format("--video needs frames, and scenario '{}' records none (add record.frames)", ps.spec->name);
  if (!FrameRecorder::ffmpeg_available())
    return "--video needs ffmpeg, which is not installed (apt-get install ffmpeg); or run without --video";
  return "";
}

Expected<RunSummary> run_scenario(const PreparedScenario& ps, const RunRequest& request) {
  const Workcell& wc = *ps.wc;
  const Plan& plan = *ps.plan;
  RunInputs inputs = collect_run_inputs(*ps.spec, ps.overrides, wc, ps.geometry, ps.sources);
  RunOptions run;
  run.out_dir = request.out;
  run.bundle = request.bundle;
  run.scenario_name = ps.spec->name;
  run.inputs = &inputs;
  run.interrupted = request.interrupted;
  run.wall_limit = request.wall_limit;
  run.progress = request.progress;
  run.progress_to = request.progress_to;
  // run_simulation moves the run into place (and packs the bundle) when it is complete;
  // whatever else happens, the staging folder goes with this scope.
  StagedDir staging(request.out.empty() ? request.bundle : request.out);
  run.work_dir = staging.path();
  std::unique_ptr<FrameRecorder> recorder;
  if (plan.settings.frames && request.frames) {
    RenderOptions ro;
    ro.width = plan.settings.width;
    ro.height = plan.settings.height;
    ro.shadows = request.shadows;
    recorder = std::make_unique<FrameRecorder>(wc, ps.geometry, ps.cameras, ro, run.work_dir + "/frames");
    if (!request.video.empty()) recorder->record_video(request.video, plan.settings.fps);
    run.frame_interval = 1.0 / plan.settings.fps;
    run.on_frame = [&](int n, double t, const ScenePose& pose) { recorder->frame(n, t, pose); };
    run.on_step_end = [&](const PlannedStep& step, double t, const ScenePose& pose) {
      std::string who = step.device >= 0 ? " " + wc.objects[step.device].name : "";
      recorder->step_end(step.index, fmt::format("{}. {}{}  t = {:.2f} s", step.index + 1, step_kind_name(step.kind), who, t), t, pose);
    };
    run.before_write = [&] {
      recorder->finish(run.work_dir + "/contact_sheet.png");
      return std::string();
    };
  }
  Expected<RunSummary> ran = run_simulation(wc, ps.geometry, plan, run);
  recorder.reset();  // before the staging folder it writes into goes
  return ran;
}

}  // namespace sscs
