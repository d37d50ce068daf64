#pragma once
/// The simulate stage: a planned scenario run in ODE physics, step by step, with events and logs.
/// Devices follow their planned trajectories through joint motors (or kinematically), grasps
/// and releases happen at their planned times, contacts become events, and the run writes
/// summary.json, events.jsonl, trajectories/<device>.csv and objects.csv into a folder that
/// appears under its final name only when complete.
#include <string>

#include "compile/workcell.h"
#include "geometry/geometry.h"
#include "simulate/plan.h"

namespace sscs {

enum class RunStatus : uint8_t { Ok, Violations, Failed };
const char* run_status_name(RunStatus s);

struct RunSummary {
  RunStatus status = RunStatus::Ok;
  double cycle_time = 0;   ///< s: when the last step ended
  double simulated = 0;    ///< s: including settling after the last step
  size_t events = 0;
  size_t collisions = 0;
};

struct RunOptions {
  std::string out_dir;          ///< written atomically: a temporary folder renamed at the end
  std::string scenario_name;
  bool progress = false;        ///< print progress lines on stderr
};

/// Runs the plan. Returns the summary; `error` is set when the output could not be written.
RunSummary run_simulation(const Workcell& wc, const GeometryModel& geometry, const Plan& plan, const RunOptions& options,
                          std::string* error);

}  // namespace sscs
