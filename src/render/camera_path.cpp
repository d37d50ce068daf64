#include "render/camera_path.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "compile/values.h"
#include "core/names.h"

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

CameraPath compile_cameras(const std::vector<CameraKeySpec>& specs, const Workcell& wc, Diagnostics& diag) {
  std::vector<CameraKey> keys;
  auto vec = [&](const std::array<Scalar, 3>& v, const char* what) {
    Eigen::Vector3d out = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k)
      if (auto x = literal_si(v[k], Dim::Length, what, diag)) out[k] = *x;
    return out;
  };
  for (const CameraKeySpec& s : specs) {
    CameraKey k;
    if (s.t.present)  // a vault's named camera has no time
      if (auto t = literal_si(s.t, Dim::Time, "camera t", diag)) k.t = *t;
    if (!keys.empty() && k.t < keys.back().t)
      diag.error(s.t.mark, fmt::format("camera keyframes must be in time order: t = {} comes after t = {:g} s", s.t.text,
                                       keys.back().t));
    if (s.fov.present)
      if (auto f = literal_si(s.fov, Dim::Angle, "fov", diag)) {
        k.fov = *f * 180 / std::numbers::pi;
        if (!(k.fov > 1 && k.fov < 179)) diag.error(s.fov.mark, fmt::format("fov must lie between 1 and 179 degrees, found {}", s.fov.text));
      }
    k.orbit = s.orbit;
    if (s.orbit) {
      if (s.orbit_target.present) {
        k.orbit_object = wc.find_object(s.orbit_target.text);
        if (k.orbit_object < 0) {
          std::vector<std::string> names;
          for (const Object& o : wc.objects) names.push_back(o.name);
          diag.error(s.orbit_target.mark, fmt::format("no object named '{}' to orbit{}", s.orbit_target.text,
                                                      did_you_mean(s.orbit_target.text, names)));
        }
      } else {
        k.orbit_point = vec(s.orbit_point, "orbit target");
      }
      if (auto r = literal_si(s.radius, Dim::Length, "orbit radius", diag)) {
        k.radius = *r;
        if (!(k.radius > 0)) diag.error(s.radius.mark, fmt::format("orbit radius must be positive, found {}", s.radius.text));
      }
      if (s.azimuth.present)
        if (auto a = literal_si(s.azimuth, Dim::Angle, "azimuth", diag)) k.azimuth = *a;
      if (s.elevation.present)
        if (auto e = literal_si(s.elevation, Dim::Angle, "elevation", diag)) k.elevation = *e;
    } else {
      k.eye = vec(s.eye, "camera eye");
      k.target = vec(s.target, "camera target");
      if ((k.eye - k.target).norm() < 1e-9) diag.error(s.mark, "camera eye and target are the same point");
    }
    keys.push_back(k);
  }
  return CameraPath(std::move(keys));
}

}  // namespace sscs
