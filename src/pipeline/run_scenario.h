#pragma once
/// A prepared scenario run as `sscs simulate` runs it: into a staging folder, with its frames,
/// contact sheet and video, moved into place when complete.
#include <csignal>
#include <iosfwd>
#include <string>

#include "core/expected.h"
#include "pipeline/prepare.h"
#include "render/action_camera.h"
#include "simulate/simulate.h"

namespace sscs {

/// What a run asks beyond its scenario: where it goes, and its pictures.
struct RunRequest {
  std::string out;     ///< the run folder ("" when only a bundle is asked for)
  std::string bundle;  ///< a .zip of the same tree, or ""
  bool frames = true;  ///< render the frames the scenario records (none when it records none)
  std::string video;   ///< also an H.264 .mp4 of the frames through ffmpeg, or ""
  bool shadows = false;
  bool see_through = false;  ///< frames with the walls between the eye and the vault see-through
  double wall_limit = 0;  ///< seconds of wall-clock time, 0: none
  RunOptions::Progress progress = RunOptions::Progress::None;
  std::ostream* progress_to = nullptr;
  const volatile std::sig_atomic_t* interrupted = nullptr;
};

/// Why the run's targets may not be written, or "" when they may: an earlier run (a folder with
/// summary.json, a bundle .zip) or an empty folder is replaced only with `force`; anything else
/// (a folder of something else, a file) never, even with it.
std::string run_targets_refusal(const std::string& out, const std::string& bundle, bool force);

/// Why the request cannot be met for this scenario before anything runs ("" when it can): a
/// video needs frames, the scenario's, and ffmpeg.
std::string run_request_refusal(const PreparedScenario& ps, const RunRequest& request);

/// Runs the scenario: the run is assembled in a staging folder beside the target (its logs,
/// frames and contact sheet, its video), then moved into place and packed into the bundle.
/// Whatever happens, nothing is left under the requested names unless the run is complete.
/// An error only for what is not the input's fault (a full disk, a renderer that fails).
Expected<RunSummary> run_scenario(const PreparedScenario& ps, const RunRequest& request);

/// What the run is doing at time t, as its plan says (the action camera's focus): the devices
/// of the steps under way (else of the last step that ended), the objects carried then (from a
/// grasp's end to its release's start), and those the steps under way grasp or release.
Focus plan_focus(const Workcell& wc, const Plan& plan, double t);
/// A contact-sheet panel's focus when `step` ends at t: its device, and what is carried then or
/// what it grasped or released.
Focus step_focus(const Workcell& wc, const Plan& plan, const PlannedStep& step, double t);

}  // namespace sscs
