#pragma once
/// A campaign's dispatcher (campaign-format.md, "Semantics"): jobs become ready, wait in one
/// queue, and go to the first idle device that may do them whose claims are free and, for a job
/// with a slot, for which a free slot exists. Planning is kinematic and deterministic, so the
/// whole campaign is dispatched in planned time, before the run: each job's steps are planned
/// from where the planning has everything when it starts, and the run then drives the devices
/// along that plan (steps of several devices under way at once), as it drives a scenario's.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "compile/workcell.h"
#include "core/diagnostics.h"
#include "core/source.h"
#include "geometry/geometry.h"
#include "simulate/plan.h"

namespace sscs {

/// An object's frame, `Row_1.top_3`.
struct FrameRef {
  int object = -1;
  std::string frame;
};

/// How a job picks among the free frames of its slot selector.
enum class SlotChoice : uint8_t { Nearest, First, Lowest, Random };

/// A job template (one entry of `jobs:`) resolved against the vault.
struct JobTemplate {
  std::string name;
  SourceMark mark;
  std::vector<int> devices;        ///< in the file's order: a ready job goes to the first idle one
  std::vector<FrameRef> slots;     ///< the frames `slot.from` selects, in natural order of their names
  SlotChoice choose = SlotChoice::Nearest;
  std::optional<FrameRef> to;
  std::vector<int> claims;         ///< zones held exclusively while the job runs
};

/// What a job's steps are expanded with when it starts.
struct JobBinding {
  size_t job_template = 0;
  int object = -1;                 ///< {load}
  int device = -1;                 ///< {device}
  std::optional<FrameRef> place;   ///< {slot} or {to}
};

struct CampaignCommands {
  SimSettings settings;
  uint64_t seed = 0;
  bool stop_on_failure = false;
  std::vector<JobTemplate> templates;
  /// One job per object a template's `each:` selects, with when it is ready.
  struct Job {
    size_t job_template = 0;
    int object = -1;
    double ready = 0;
  };
  std::vector<Job> jobs;
  /// Loads that arrive (`loads:`, objects of the compiled vault standing at their spot): each
  /// no earlier than `scheduled`, and once its spot is free (the load before it lifted away).
  struct Arrival {
    int object = -1;
    double scheduled = 0;
    FrameRef spot;
  };
  std::vector<Arrival> arrivals;  ///< in the order of `loads:`, then of {n}
  /// Failures an earlier run found (on_failure: continue): each job ends at its step, its device
  /// out from then on.
  std::vector<FoundInRun> found;
  /// A job's steps compiled for its binding, their input errors into `diag` (named with the job).
  std::function<std::vector<StepCommand>(const JobBinding&, Diagnostics& diag)> steps;
};

/// How near a frame an object's origin must stand to occupy it (m): the spec's 5 cm.
constexpr double kSlotOccupied = 0.05;

/// Dispatches the campaign and plans every job. Returns nullopt when an input error was reported
/// (a template step that does not plan for one of its jobs is named with that job's object).
std::optional<Plan> plan_campaign(const CampaignCommands& campaign, const Workcell& wc, const GeometryModel& geometry,
                                  Diagnostics& diag);

/// The name of a campaign job's place, `Row_1.top_3`.
std::string frame_text(const Workcell& wc, const FrameRef& f);

}  // namespace sscs
