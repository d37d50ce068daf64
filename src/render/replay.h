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

/// Why `out` may not receive a replay's frames, or "" when it may: a folder that does not exist,
/// an empty one, or (with `force`) an earlier replay (frames/ and contact_sheet.png only).
/// Anything else (a run, a folder of other files, a file) is never replaced.
std::string replay_target_refusal(const std::string& out, bool force);

class RecordedRun {
 public:
  /// Reads the logs in run folder `dir`, written for workcell `wc` (compiled from the run's
  /// resolved/ vault); why not when they are missing, do not match the workcell, or hold a cell
  /// that is not a finite number (file and line named), or times that go back.
  /// `driven`: the devices the run's plan moved, each of which must have its log.
  static Expected<RecordedRun> read(const std::string& dir, const Workcell& wc, const GeometryModel& geometry,
                                    const std::vector<int>& driven);
  /// Where everything was at time t: joint values and object poses interpolated between the
  /// logged rows (linear, orientations slerped); objects never logged stay where they stood.
  ScenePose at(double t) const;
  double duration() const { return duration_; }
  /// A campaign's arriving loads and when each arrived (the plan's; infinity: never): before
  /// that, at() hides them and keeps them far below everything (a glTF's animation too).
  void set_arrivals(const std::vector<std::pair<int, double>>& arrivals) { arrivals_ = arrivals; }
  /// Every time a log has a row at (devices' trajectories, objects.csv), increasing, each one
  /// once; 0 first. Times closer than a 32-bit float tells apart (glTF's) are kept once.
  std::vector<double> log_times() const;
  /// The objects the logs move (devices with a trajectory, objects in objects.csv), in order.
  std::vector<int> logged_objects() const;
  /// The times to draw frames at: the run's own (its frames/index.csv, as FrameRecorder wrote
  /// it) when it recorded frames, else every 1/fps of its duration. Why not (file and line
  /// named) when the index is not as FrameRecorder writes it: its header, rows of frame number
  /// (0, 1, 2, ...), time (finite, never going back, within the run) and file name; none at all.
  Expected<std::vector<double>> frame_times(double fps) const;

 private:
  struct Series {
    std::vector<double> t;
    std::vector<Eigen::VectorXd> values;  ///< devices: SI joint values; objects: x y z qw qx qy qz
  };
  const GeometryModel* geometry_ = nullptr;
  std::string dir_;
  std::map<int, Series> devices_, objects_;
  std::vector<std::pair<int, double>> arrivals_;
  double duration_ = 0;
};

}  // namespace sscs
