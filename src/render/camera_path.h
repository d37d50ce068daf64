#pragma once
/// Camera keyframes (compile/cameras.h) interpolated: the view sequence of a run.
#include <optional>
#include <vector>

#include "compile/cameras.h"
#include "compile/workcell.h"
#include "core/diagnostics.h"
#include "render/camera.h"
#include "render/renderer.h"

namespace sscs {

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


/// The eased interpolation parameter: 3s^2 - 2s^3 of s clamped to [0, 1].
double ease(double s);

}  // namespace sscs
