#pragma once
/// The check stage: evaluate every constraint of a Workcell into results with margins.
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "compile/workcell.h"
#include "geometry/geometry.h"

namespace sscs {

enum class Status : uint8_t { Pass, Fail, Error };
const char* status_name(Status s);

/// Where a device came closest to a reach target it does not reach (the "why can't it reach"
/// picture of the HTML report): the pose its margin is measured at, or for a target reached only
/// in collision, the pose that reaches it and collides.
struct ClosestPose {
  struct Joint {
    std::string name;
    bool revolute;
    double value;  ///< SI: rad or m
  };
  std::vector<Joint> joints;  ///< the device's, in its joint order
  struct Part {
    std::string name;
    Eigen::Isometry3d X_object_part;  ///< in the device's frame
  };
  std::vector<Part> parts;
  Eigen::Vector3d tool = Eigen::Vector3d::Zero(), target = Eigen::Vector3d::Zero();  ///< world points
};

/// One check: a constraint, or one member (object, pair) of a constraint over a set.
struct CheckResult {
  int constraint = -1;
  Status status = Status::Pass;
  std::vector<int> subjects;
  std::optional<double> lhs, rhs;  ///< in file units of `dim`
  std::optional<double> margin;    ///< in file units of `dim`; positive when satisfied
  Dim dim = Dim::None;
  std::string unit;  ///< the margin's unit when it is no dimension's (a plugin's "sr"), else ""
  std::string message;
  std::shared_ptr<const ClosestPose> closest;  ///< a failed reach target's, else none
  /// The unit the margin is in: `unit`, else the file unit of `dim`.
  const char* margin_unit() const { return unit.empty() ? file_unit(dim) : unit.c_str(); }
};

struct CheckReport {
  std::vector<CheckResult> results;
  size_t passed = 0;
  /// Error-severity checks that failed, and checks of any severity that could not be evaluated
  /// (a value that is not a number is never a pass, nor a mere warning).
  size_t failed = 0;
  size_t unevaluated = 0;  ///< of `failed`: the checks that could not be evaluated
  size_t warnings = 0;     ///< warning-severity checks that failed
  /// Violations for the exit status: failures, and warnings too when strict.
  bool violated(bool strict) const { return failed > 0 || (strict && warnings > 0); }
};

struct CheckOptions {
  /// Write a message for passing results too. A text report prints only failures, so it turns
  /// this off: on a vault of 200,000 constraints the messages are a third of the check stage.
  bool describe_passes = true;
  /// When not empty: check only the constraints marked here (indexed like Workcell::constraints).
  std::vector<char> only;
  /// Spatial comparisons (clearance, inside) hold within the larger of each constraint's eps and
  /// this (m): a run's re-checks see ODE contacts sink by micrometres.
  double spatial_tolerance = 0;
  /// Called with each reach solution accepted: the constraint's index, the target's index in its
  /// list, the device's joint vector (all its joints, in its order). What a report could draw;
  /// what the tests replay in the physics.
  std::function<void(int constraint, int target, const Eigen::VectorXd& q)> on_reach_solution;
  /// When set and it turns true: the check stops (throws CheckCancelled) at its next constraint
  /// or reach target. `sscs serve` and `sscs lsp` set it when a newer save or edit supersedes it.
  const std::atomic<bool>* cancel = nullptr;
};

/// A check stopped by CheckOptions::cancel: it has no result.
struct CheckCancelled {};

/// Checks every constraint at the workcell's values and geometry.
/// The value (SI) of a compiled operand in workcell values `values`: a slot, a bounding box
/// of `geometry`, an aggregate of its members (NaN for min, max or avg of none).
double operand_value(const Operand& op, const std::vector<double>& values, const GeometryModel& geometry);

CheckReport check(const Workcell& wc, const GeometryModel& geometry, const CheckOptions& options = {});

/// Checks with another set of slot values (same layout as wc.values), e.g. during a motion.
CheckReport check(const Workcell& wc, const GeometryModel& geometry, const std::vector<double>& values,
                  const CheckOptions& options = {});

}  // namespace sscs
