#pragma once
/// Scenario files (scenario-format.md) as written: the vault they run in, simulation and
/// recording settings, cameras and the steps of device motions. Values stay text with marks,
/// like vault specs; the simulate stage resolves them against the compiled vault.
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/diagnostics.h"
#include "core/source.h"
#include "load/spec.h"

namespace sscs {


/// `move_to` target: an object or named frame (`Drum_1.top`), or a world pose.
struct TargetSpec {
  Scalar ref;                     ///< `Obj` or `Obj.frame`; absent for a pose
  std::optional<PoseSpec> pose;
  SourceMark mark;
};

struct MoveJointsSpec {
  bool home = false;
  std::vector<std::pair<std::string, Scalar>> joints;  ///< joint name -> value
  std::vector<SourceMark> joint_marks;
};
struct MoveToSpec {
  TargetSpec target;
  PoseSpec offset;
  bool linear = false;            ///< `path: linear`
};
struct GraspSpec {
  Scalar object;
};
struct ReleaseSpec {
  Scalar object;                  ///< optional: what is held, checked when given
};
struct WaitSpec {
  Scalar duration;
};
/// The action keys of a step, in the order of StepSpec::action's alternatives: the one list.

struct StepSpec;
struct ParallelSpec {
  std::vector<StepSpec> steps;
};

struct StepSpec {
  SourceMark mark;
  Scalar device;                  ///< absent for wait and parallel
  Scalar speed;                   ///< `50%` (scales limits) or a speed `0.25 m/s` for linear paths
  std::variant<MoveJointsSpec, MoveToSpec, GraspSpec, ReleaseSpec, WaitSpec, ParallelSpec> action;
  const char* kind() const { return kStepActionNames[action.index()]; }
};

/// What a scenario and a campaign file both say: their name, vault and overrides, the `sim:`
/// and `record:` settings and the cameras (campaign-format.md: "as in a scenario").
struct RunFileSpec {
  std::string name;
  SourceMark mark;
  std::string path;
  std::string description;
  Scalar vault;                   ///< relative to the file
  std::string vault_path;         ///< resolved
  std::vector<std::pair<std::string, Scalar>> set;  ///< parameter overrides
  Scalar timestep, limit;
  Scalar check_tolerance;         ///< sim.check_tolerance: spatial re-checks during the run
  Scalar mode;                    ///< sim.mode: physics (default) or fast
  Scalar seed;                    ///< sim.seed: campaigns only (random arrivals and choices)
  bool gravity = true;
  Scalar trajectory_rate;
  bool frames = false;
  Scalar fps, width, height;
  std::vector<CameraKeySpec> cameras;
};

struct ScenarioSpec : RunFileSpec {
  std::vector<StepSpec> steps;
};

/// Loads a scenario file strictly (unknown and duplicate keys, wrong kinds, names). Returns
/// nullopt when the file could not be parsed at all; otherwise the spec, every problem reported.
std::optional<ScenarioSpec> load_scenario(const std::string& path, Sources& sources, Diagnostics& diag);
/// Loads a camera file for `sscs replay --camera`: `sscs: 1` and `cameras:` keyframes as in a
/// scenario.
std::optional<std::vector<CameraKeySpec>> load_cameras(const std::string& path, Sources& sources, Diagnostics& diag);
/// Loads a scenario already registered in `sources` (tests).
std::optional<ScenarioSpec> load_scenario(uint32_t file, Sources& sources, Diagnostics& diag);

}  // namespace sscs
