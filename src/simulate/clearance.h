#pragma once
/// A run's clearance tracker: the closest approach, over the run, of each object that moves to
/// each other object within reach, with when and which parts. Lifting a load off what it stands
/// on and setting it down on what it lands on are the job, not a clearance: the moves that do it
/// are excused for that pair alone (the move after the grasp, the move that ended at the
/// release), never for the run, and never a penetration deeper than a contact (a drum lowered
/// through the drum it then landed on is -0.57 m, not the 0.02 m of some other pair).
#include <map>
#include <optional>
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
  /// Deeper than this into each other is no contact but a penetration, never excused (m).
  static constexpr double kContact = 0.005;

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
  /// The signed distance of two objects where they are now (minus the depth when they
  /// interpenetrate); nullopt when one has no solid.
  std::optional<double> distance(int a, int b) { return nearby_.distance(a, b); }

  /// Measures at time `t` how close `moving` (its `parts` only, when given) comes to every other
  /// object within reach but `skip`; keeps each pair's closest approaches.
  void measure(double t, int moving, const std::vector<int>& skip, const std::vector<char>& parts = {});
  /// Measures at time `t` how deep `a` goes into `b` (a device into the load it takes or let
  /// go, which it may touch): only a penetration deeper than a contact is kept.
  void measure_penetration(double t, int a, int b);
  /// The pair's approaches from `from` to `to` are the job (a load's set-down on what it landed
  /// on, its lift off what it stood on): not counted, but for penetrations. `to` may lie ahead.
  void excuse(int a, int b, double from, double to);

  /// The closest approach of the run: the smallest distance of any pair outside the moves
  /// excused, negative for the deepest penetration; none when nothing came within reach.
  std::optional<RunSummaryFile::Clearance> closest() const;

 private:
  struct Seen {
    double distance = INFINITY;
    double t = 0;
    std::string a, b;  ///< `Object` or `Device.part`
  };
  struct Pair {
    /// Each sample closer than every earlier one still counted, in time order: excusing a
    /// stretch of time drops its records and leaves the closest before it.
    std::vector<Seen> records;
    std::vector<std::pair<double, double>> excused;  ///< (from, to) stretches ahead or under way
    double closest() const { return records.empty() ? INFINITY : records.back().distance; }
    bool is_excused(double t) const;
  };
  using Key = std::pair<int, int>;  ///< (lower object, higher object)
  static Key key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }
  void keep(Pair& pair, Seen seen);

  const Workcell& wc_;
  const GeometryModel& geometry_;
  CollisionWorld nearby_;
  std::map<Key, Pair> pairs_;
};

}  // namespace sscs
