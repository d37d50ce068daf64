#include "render/action_camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "model/device.h"

namespace sscs {

namespace {

constexpr double kShown = 0.6;  ///< of an object's pixels, for a view to show it

Eigen::Vector3d side_of(double azimuth_deg, double elevation_deg) {
  const double a = azimuth_deg * std::numbers::pi / 180, e = elevation_deg * std::numbers::pi / 180;
  return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

}  // namespace

Eigen::Vector3d tool_at(const GeometryModel& geometry, const ScenePose& pose, int device) {
  const Device& d = *geometry.objects[device].device;
  return (pose.X_world_object[device] * pose.X_object_part[device][d.tool_part] * d.X_part_tool).translation();
}

Eigen::AlignedBox3d bounds_at(const GeometryModel& geometry, const ScenePose& pose, int o) {
  const ObjectGeometry& g = geometry.objects[o];
  Eigen::AlignedBox3d out;
  if (g.bbox_world.isEmpty()) return out;
  if (g.device) {  // each part's origin and the tool: enough to frame a device at work
    for (size_t p = 0; p < g.device->parts.size(); ++p) out.extend((pose.X_world_object[o] * pose.X_object_part[o][p]).translation());
    out.extend(tool_at(geometry, pose, o));
    return out;
  }
  const Eigen::Isometry3d moved = pose.X_world_object[o] * g.X_world_object.inverse();
  for (int c = 0; c < 8; ++c) out.extend(moved * g.bbox_world.corner(Eigen::AlignedBox3d::CornerType(c)));
  return out;
}

Camera ActionCamera::at(const Focus& focus, const ScenePose& pose, const GeometryModel& geometry, Renderer& renderer, double aspect) {
  Eigen::AlignedBox3d box;
  for (int d : focus.devices) {
    const Eigen::Vector3d tool = tool_at(geometry, pose, d);
    box.extend(tool - Eigen::Vector3d::Constant(0.3));
    box.extend(tool + Eigen::Vector3d::Constant(0.3));
  }
  for (int o : focus.objects) box.extend(bounds_at(geometry, pose, o));
  if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite()) return framing_camera(renderer.bounds(), fov_, aspect);
  const Eigen::Vector3d target = box.center();
  // Close enough to see the load, far enough for what it is among (a rack's bay, the aisle).
  const double radius = std::max(0.5 * box.diagonal().norm() + 0.8, 1.5);
  const double half = std::min(fov_ * std::numbers::pi / 360, std::atan(std::tan(fov_ * std::numbers::pi / 360) * aspect));
  const double distance = radius / std::sin(half);
  std::vector<int> watched = focus.objects;
  watched.insert(watched.end(), focus.devices.begin(), focus.devices.end());
  const size_t loads = focus.objects.size();
  // A side's score: the share of each load the view shows (its pixels in front over its pixels
  // alone), and half as much for the devices; shown: every load at least kShown.
  auto look = [&](const Eigen::Vector3d& side) { return Camera{target + side * distance, target, fov_}; };
  auto score = [&](const Eigen::Vector3d& side, bool* shown) {
    const std::vector<Renderer::Visibility> v = renderer.visibility(look(side), pose, watched);
    double s = 0;
    bool all = true;
    for (size_t k = 0; k < v.size(); ++k) {
      const double f = v[k].fraction();
      s += k < loads ? f : 0.5 * f;
      if (k < loads) all = all && f >= kShown;
    }
    if (shown) *shown = all && (loads > 0 || s > 0);
    return s;
  };
  const Eigen::Vector3d preferred = side_.value_or(side_of(-120, 35));
  bool shown = false;
  const double kept = score(preferred, &shown);
  if (!shown) {
    // Round the load: twelve azimuths at three heights; the best share, nearest the last side.
    double best = kept;
    Eigen::Vector3d chosen = preferred;
    for (double elevation : {25.0, 50.0, 75.0})
      for (int k = 0; k < 12; ++k) {
        const Eigen::Vector3d side = side_of(30.0 * k, elevation);
        const double turn = std::acos(std::clamp(side.dot(preferred), -1.0, 1.0)) / std::numbers::pi;
        const double s = score(side, nullptr) - 0.15 * turn;
        if (s > best + 1e-9) {
          best = s;
          chosen = side;
        }
      }
    side_ = chosen;
  } else {
    side_ = preferred;
  }
  return look(*side_);
}

}  // namespace sscs
