#include "compile/cameras.h"

#include <numbers>

#include <fmt/format.h>

#include "compile/values.h"
#include "compile/workcell.h"
#include "core/names.h"

namespace sscs {

std::vector<CameraKey> compile_camera_keys(const std::vector<CameraKeySpec>& specs, const Workcell& wc, Diagnostics& diag) {
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
  return keys;
}


}  // namespace sscs
