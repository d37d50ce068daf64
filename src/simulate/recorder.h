#pragma once
/// A run's trajectory files, one row per trajectory tick: per device its joints and its tool's
/// pose (`trajectories/<device>.csv`), and the pose of every object the physics moves
/// (`objects.csv`).
#include <string>
#include <utility>
#include <vector>

#include "compile/workcell.h"
#include "geometry/geometry.h"
#include "simulate/world.h"

namespace sscs {

class TrajectoryRecorder {
 public:
  /// Records devices `devices` (object indices) of `wc`, as `world` moves them.
  TrajectoryRecorder(const Workcell& wc, const GeometryModel& geometry, const PhysicsWorld& world, std::vector<int> devices);
  /// A row for each device and each dynamic object at simulated time `t`.
  void record(double t);
  /// The files, as (path under the run folder, contents), devices first.
  std::vector<std::pair<std::string, std::string>> files() const;

 private:
  const Workcell& wc_;
  const GeometryModel& geometry_;
  const PhysicsWorld& world_;
  std::vector<int> devices_;
  std::vector<std::string> device_csv_;  ///< per device: its header and rows, once it has a row
  std::string objects_csv_;              ///< rows only
};

}  // namespace sscs
