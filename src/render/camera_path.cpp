#include "render/camera_path.h"

#include <algorithm>
#include <cmath>
#include <numbers>


namespace sscs {

namespace {

Eigen::Vector3d orbit_centre(const CameraKey& k, const ScenePose& pose) {
  return k.orbit_object >= 0 ? pose.X_world_object[k.orbit_object].translation() : k.orbit_point;
}

Eigen::Vector3d orbit_eye(const Eigen::Vector3d& centre, double radius, double azimuth, double elevation) {
  return centre + radius * Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                                           std::sin(elevation));
}

Camera fixed(const CameraKey& k, const ScenePose& pose) {
  if (!k.orbit) return {k.eye, k.target, k.fov};
  Eigen::Vector3d c = orbit_centre(k, pose);
  return {orbit_eye(c, k.radius, k.azimuth, k.elevation), c, k.fov};
}

}  // namespace

double ease(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * (3 - 2 * s);
}

Camera CameraPath::at(double t, const ScenePose& pose, const Eigen::AlignedBox3d& scene_bounds, double aspect) const {
  if (keys_.empty()) return framing_camera(scene_bounds, 45, aspect);
  if (t <= keys_.front().t) return fixed(keys_.front(), pose);
  if (t >= keys_.back().t) return fixed(keys_.back(), pose);
  size_t i = 0;
  while (i + 1 < keys_.size() && keys_[i + 1].t <= t) ++i;
  const CameraKey &a = keys_[i], &b = keys_[i + 1];
  const double span = b.t - a.t;
  const double s = span > 0 ? ease((t - a.t) / span) : 1.0;
  const double fov = a.fov + s * (b.fov - a.fov);
  const bool same_centre = a.orbit && b.orbit && a.orbit_object == b.orbit_object &&
                           (a.orbit_object >= 0 || a.orbit_point == b.orbit_point);
  if (same_centre) {
    Eigen::Vector3d c = orbit_centre(a, pose);
    return {orbit_eye(c, a.radius + s * (b.radius - a.radius), a.azimuth + s * (b.azimuth - a.azimuth),
                      a.elevation + s * (b.elevation - a.elevation)),
            c, fov};
  }
  Camera ca = fixed(a, pose), cb = fixed(b, pose);
  return {ca.eye + s * (cb.eye - ca.eye), ca.target + s * (cb.target - ca.target), fov};
}

}  // namespace sscs
