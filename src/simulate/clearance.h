#pragma once
/// A run's clearance tracker: the closest approach, over the run, of each object that moves to
/// each other object within reach, with when and which parts. What a load was lifted from or set
/// on is the job, not a clearance: the summary leaves those pairs out.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "compile/workcell.h"
#include "geometry/collision.h"
#include "geometry/geometry.h"
#include "simulate/summary_file.h"

namespace sscs {

/// How a run's files name object `o`'s part `part`: `Device.part`, else `Object`; `floor` for -1.
std::string run_part_name(const Workcell& wc, const GeometryModel& geometry, int o, int part);

class ClearanceTracker {
 public:
  ClearanceTracker(const Workcell& wc, const GeometryModel& geometry);
  /// Places a device's parts, or a free object, where the motion has them now.
  void move_parts(int device, const std::vector<Eigen::Isometry3d>& X_world_part) { nearby_.move_parts(device, X_world_part); }
  void move(int object, const Eigen::Isometry3d& X_world_object) { nearby_.move(object, X_world_object); }
  /// The objects within `gap` of `object`, placed at `X_world_object` (what a load stands on when
  /// it is lifted), but `skip`.
  std::vector<int> within(int object, const Eigen::Isometry3d& X_world_object, const std::vector<int>& skip, double gap);
  /// How far `p_world` is from `object`'s solids, the object placed at `X_world_object` (where a
  /// tool is from what it is to grasp).
  double distance_to_point(int object, const Eigen::Isometry3d& X_world_object, const Eigen::Vector3d& p_world) {
    nearby_.move(object, X_world_object);
    return nearby_.distance_to_point(object, p_world).value_or(INFINITY);
  }
  /// Measures at time `t` how close `moving` (its `parts` only, when given) comes to every other
  /// object within reach but `skip`; keeps each pair's closest.
  void measure(double t, int moving, const std::vector<int>& skip, const std::vector<char>& parts = {});
  /// The closest approach of the run, leaving out the `supports` pairs (load, what it was lifted
  /// from or landed on); none when nothing came within reach.
  std::optional<RunSummaryFile::Clearance> closest(const std::set<std::pair<int, int>>& supports) const;

 private:
  struct Seen {
    double distance;
    double t;
    std::string a, b;  ///< `Object` or `Device.part`
  };
  const Workcell& wc_;
  const GeometryModel& geometry_;
  CollisionWorld nearby_;
  std::map<std::pair<int, int>, Seen> seen_;  ///< (moving, other) -> closest
};

}  // namespace sscs
