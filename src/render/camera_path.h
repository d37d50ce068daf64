#pragma once
/// A scenario's `cameras:` keyframes, compiled and interpolated: the view sequence of a run.
#include <optional>
#include <vector>

#include "compile/workcell.h"
#include "core/diagnostics.h"
#include "load/scenario.h"
#include "render/camera.h"
#include "render/renderer.h"

namespace sscs {

struct CameraKey {
  double t = 0;              ///< s
  bool orbit = false;
  Eigen::Vector3d eye = Eigen::Vector3d::Zero(), target = Eigen::Vector3d::Zero();  ///< fixed keys
  int orbit_object = -1;     ///< orbit around an object's origin (where it is at that moment) ...
  Eigen::Vector3d orbit_point = Eigen::Vector3d::Zero();  ///< ... or around a point
  double radius = 0, azimuth = 0, elevation = 0;         ///< m, rad, rad
  double fov = 45;           ///< deg
};

/// Keyframes in time order. Between two keys the view moves with an eased parameter
/// (smoothstep: it starts and stops gently at every key): two orbits around the same object or
/// point interpolate radius, azimuth and elevation (a sweep around it); otherwise eye and target
/// move on straight lines. fov follows the same easing. Before the first key and after the last
/// the camera holds. No keys: a framing three-quarter view of the whole scene.
class CameraPath {
 public:
  CameraPath() = default;
  explicit CameraPath(std::vector<CameraKey> keys) : keys_(std::move(keys)) {}
  Camera at(double t, const ScenePose& pose, const Eigen::AlignedBox3d& scene_bounds, double aspect) const;
  const std::vector<CameraKey>& keys() const { return keys_; }

 private:
  std::vector<CameraKey> keys_;
};

/// Compiles the keys (units, object names, fov in (1, 179) deg, times not decreasing). Errors go
/// to `diag` with their marks.
CameraPath compile_cameras(const std::vector<CameraKeySpec>& keys, const Workcell& wc, Diagnostics& diag);

/// The eased interpolation parameter: 3s^2 - 2s^3 of s clamped to [0, 1].
double ease(double s);

}  // namespace sscs
