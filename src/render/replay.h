#pragma once
/// A run's recorded motion read back (trajectories/<device>.csv and objects.csv), so its frames
/// can be drawn again from other cameras without simulating again (`sscs replay`).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "compile/workcell.h"
#include "core/expected.h"
#include "geometry/geometry.h"

namespace sscs {

class RecordedRun {
 public:
  /// Reads the logs in run folder `dir`, written for workcell `wc` (compiled from the run's
  /// resolved/ vault); why not when they are missing, do not match the workcell, or hold a cell
  /// that is not a finite number (file and line named), or times that go back.
  static Expected<RecordedRun> read(const std::string& dir, const Workcell& wc, const GeometryModel& geometry);
  /// Where everything was at time t: joint values and object poses interpolated between the
  /// logged rows (linear, orientations slerped); objects never logged stay where they stood.
  ScenePose at(double t) const;
  double duration() const { return duration_; }
  /// The times to draw frames at: the run's own (its frames/index.csv, as FrameRecorder wrote
  /// it) when it recorded frames, else every 1/fps of its duration. Why not when the index holds
  /// a cell that is not a finite number, or times that go back (file and line named).
  Expected<std::vector<double>> frame_times(double fps) const;

 private:
  struct Series {
    std::vector<double> t;
    std::vector<Eigen::VectorXd> values;  ///< devices: SI joint values; objects: x y z qw qx qy qz
  };
  const GeometryModel* geometry_ = nullptr;
  std::string dir_;
  std::map<int, Series> devices_, objects_;
  double duration_ = 0;
};

}  // namespace sscs
