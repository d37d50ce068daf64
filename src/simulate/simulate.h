#pragma once
/// The simulate stage: a planned scenario run in ODE physics, step by step, with events and logs.
/// Devices follow their planned trajectories through joint motors (or kinematically), grasps
/// and releases happen at their planned times, contacts become events, and the run writes
/// summary.json, events.jsonl, trajectories/<device>.csv and objects.csv into a folder that
/// appears under its final name only when complete.
#include <csignal>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "compile/workcell.h"
#include "core/expected.h"
#include "geometry/geometry.h"
#include "simulate/plan.h"
#include "simulate/run_inputs.h"
#include "simulate/summary_file.h"

namespace sscs {

enum class RunStatus : uint8_t { Ok, Violations, Failed };
const char* run_status_name(RunStatus s);

struct RunSummary {
  RunStatus status = RunStatus::Ok;
  /// s: when the last step ended; NaN when the run failed (it stopped before its cycle was done)
  double cycle_time = 0;
  double simulated = 0;    ///< s: including settling after the last step
  size_t events = 0;
  size_t collisions = 0;
  bool interrupted = false;  ///< stopped through RunOptions::interrupted; nothing was written
  /// A failed run: the event that stopped it (time_limit, wall_limit, unreachable, ...), when
  /// (simulated s), and its message ("" for the limits).
  std::string stopped_by;
  double stopped_at = 0;
  std::string stop_message;
  /// A run whose move ended with its tool still off the target (it never arrived): what the
  /// first such move was; the run has no cycle time then.
  std::string unfinished;
  /// A campaign's figures (summary.json's `campaign` block), for a sweep's metrics.
  std::optional<RunSummaryFile::Campaign> campaign;
};

/// How a campaign's run leaves the vault (final.yaml): where each object stands at the end.
struct FinalState {
  double t = 0;                                ///< s: when the run ended
  std::vector<Eigen::Isometry3d> X_world;      ///< per object: its frame in the world
  std::vector<char> moved;                     ///< per object: not where the vault put it
  std::vector<char> gone;                      ///< per object: not there (a load that never arrived)
  /// Per object: attributes (index) with a new value, SI: a device's joints where it stopped.
  std::vector<std::vector<std::pair<int, double>>> attributes;
};

struct RunOptions {
  std::string out_dir;          ///< written atomically: a temporary folder renamed at the end ("" for none)
  std::string bundle;           ///< the same tree as one zip archive ("" for none), also atomic
  std::string scenario_name;
  /// Progress: none, a line per step (logs), or one line updated in place (a terminal).
  enum class Progress : uint8_t { None, Lines, Live } progress = Progress::None;
  /// Where progress goes (the command line passes stderr); none when null. The library writes
  /// to no terminal stream of its own.
  std::ostream* progress_to = nullptr;
  const RunInputs* inputs = nullptr;  ///< their digests go in summary.json, resolved/ in the run
  /// Set (by a signal handler) to stop the run: then nothing is written.
  const volatile std::sig_atomic_t* interrupted = nullptr;
  /// Seconds of wall-clock time the run may take (0: no limit). Past it the run stops as failed
  /// with a `wall_limit` event, and writes what it has, as at the simulated-time limit.
  double wall_limit = 0;
  /// Called for frame n at the first step at or after n * frame_interval of simulated time,
  /// with where everything is then (frame_interval 0: no frames).
  std::function<void(int n, double t, const ScenePose& pose)> on_frame;
  double frame_interval = 0;
  /// Called when a step ends (with frames: the contact sheet's thumbnails).
  std::function<void(const PlannedStep& step, double t, const ScenePose& pose)> on_step_end;
  /// Called when the simulation is over, before the outputs are written (frames flushed);
  /// returns an error message or "".
  std::function<std::string()> before_write;
  /// A campaign's run stopped at a failure it found and starts again on `plan` (planned again
  /// knowing it): what the callbacks above recorded of the stopped run is to be dropped.
  std::function<void(const Plan& plan)> on_restart;
  /// A campaign's final.yaml from how the run leaves the vault (none when unset).
  std::function<std::string(const FinalState& end)> final_vault;
  /// The folder the outputs are assembled in before they are moved into place; "" for
  /// run_work_dir(*this). A frame sink writes into it too.
  std::string work_dir;
};

/// The hidden temporary folder beside the run's target: ".NAME.tmp-PID" (a StagedDir's).
std::string run_work_dir(const RunOptions& options);

/// Runs the plan and writes its outputs. Returns the summary, or why the outputs could not be
/// written (then nothing is left under the requested names, and the work folder is removed, as
/// it is when the run is interrupted).
Expected<RunSummary> run_simulation(const Workcell& wc, const GeometryModel& geometry, const Plan& plan, const RunOptions& options);

}  // namespace sscs
