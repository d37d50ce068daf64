#include "pipeline/run_scenario.h"

#include <algorithm>
#include <cmath>
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
  RunInputs inputs = collect_run_inputs(*ps.spec, ps.overrides, wc, ps.geometry, ps.sources, nullptr, ps.campaign ? "campaign" : "scenario");
  RunOptions run;
  run.out_dir = request.out;
  run.bundle = request.bundle;
  run.scenario_name = ps.spec->name;
  run.inputs = &inputs;
  run.interrupted = request.interrupted;
  run.wall_limit = request.wall_limit;
  run.progress = request.progress;
  run.progress_to = request.progress_to;
  if (ps.campaign)  // the vault as the campaign leaves it, naming resolved/'s library beside it
    run.final_vault = [&](const FinalState& end) { return final_vault_text(wc, ps.sources, end, "campaign " + ps.spec->name, true); };
  // run_simulation moves the run into place (and packs the bundle) when it is complete;
  // whatever else happens, the staging folder goes with this scope.
  StagedDir staging(request.out.empty() ? request.bundle : request.out);
  run.work_dir = staging.path();
  std::unique_ptr<FrameRecorder> recorder;
  const Plan* running = &plan;  // the plan being run: a campaign's again after a failure its run found
  auto make_recorder = [&] {
    RenderOptions ro;
    ro.width = plan.settings.width;
    ro.height = plan.settings.height;
    ro.shadows = request.shadows;
    ro.see_through = request.see_through;
    recorder.reset();  // (its files first: the new one writes the same names)
    std::error_code ec;
    std::filesystem::remove_all(run.work_dir + "/frames", ec);
    recorder = std::make_unique<FrameRecorder>(wc, ps.geometry, ps.cameras, ro, run.work_dir + "/frames");
    if (!request.video.empty()) recorder->record_video(request.video, plan.settings.fps);
    recorder->set_focus([&](double t) { return plan_focus(wc, *running, t); });
  };
  if (plan.settings.frames && request.frames) {
    make_recorder();
    run.frame_interval = 1.0 / plan.settings.fps;
    run.on_frame = [&](int n, double t, const ScenePose& pose) { recorder->frame(n, t, pose); };
    run.on_step_end = [&](const PlannedStep& step, double t, const ScenePose& pose) {
      std::string who = step.device >= 0 ? " " + wc.objects[step.device].name : "";
      recorder->step_end(step.index, fmt::format("{}. {}{}  t = {:.2f} s", step.index + 1, step_kind_name(step.kind), who, t), t, pose,
                         step_focus(wc, *running, step, t));
    };
    run.on_restart = [&](const Plan& again) {
      running = &again;
      make_recorder();
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

namespace {

/// The objects carried at t: each grasp's object from the grasp's end until its release starts
/// (to the end of the run when it is never released). Containers never count.
std::vector<int> carried_at(const Workcell& wc, const Plan& plan, double t) {
  // The run ends a step on a physics step, the plan at its exact time: within a step is "then".
  t += plan.settings.timestep;
  std::vector<int> out;
  for (size_t g = 0; g < plan.steps.size(); ++g) {
    const PlannedStep& grasp = plan.steps[g];
    if (grasp.kind != StepKind::Grasp || grasp.object < 0 || t < grasp.end) continue;
    if (wc.types[wc.objects[grasp.object].type].container) continue;  // a space: no load to watch
    double until = INFINITY;
    for (size_t r = g + 1; r < plan.steps.size(); ++r)
      if (plan.steps[r].kind == StepKind::Release && plan.steps[r].object == grasp.object) {
        until = plan.steps[r].start;
        break;
      }
    if (t <= until) out.push_back(grasp.object);
  }
  return out;
}

void add_once(std::vector<int>& v, int x) {
  if (x >= 0 && std::find(v.begin(), v.end(), x) == v.end()) v.push_back(x);
}

}  // namespace

Focus plan_focus(const Workcell& wc, const Plan& plan, double t) {
  Focus f;
  const PlannedStep* last = nullptr;  // the last step begun by t
  const double now = t + plan.settings.timestep;  // the run is on physics steps, the plan's times exact
  for (const PlannedStep& step : plan.steps) {
    if (step.start > now) continue;
    if (!last || step.start >= last->start) last = &step;
    if (t <= step.end + plan.settings.timestep) {
      add_once(f.devices, step.device);
      if (step.kind == StepKind::Grasp || step.kind == StepKind::Release) add_once(f.objects, step.object);
    }
  }
  if (f.devices.empty() && last) add_once(f.devices, last->device);
  if (f.devices.empty() && !plan.steps.empty()) add_once(f.devices, plan.steps.front().device);
  for (int o : carried_at(wc, plan, t)) add_once(f.objects, o);
  return f;
}

Focus step_focus(const Workcell& wc, const Plan& plan, const PlannedStep& step, double t) {
  Focus f;
  add_once(f.devices, step.device);
  for (int o : carried_at(wc, plan, t)) add_once(f.objects, o);
  if (step.kind == StepKind::Grasp || step.kind == StepKind::Release) add_once(f.objects, step.object);
  return f;
}

}  // namespace sscs
