#pragma once
/// The action camera: the default view of a run's frames and of every contact-sheet panel. It
/// looks at what the run is doing (the tools of the devices at work and the loads they carry,
/// named by the caller as a Focus), close enough to see it, from the side that shows it: each
/// view is checked with the renderer's id pass (Renderer::visibility), and when a rack, a wall
/// or the device itself hides the load, the camera moves round to a side where it shows.
#include <optional>
#include <vector>

#include "geometry/geometry.h"
#include "render/camera.h"
#include "render/renderer.h"

namespace sscs {

/// What a view must show at one moment: the devices at work (their tools) and the objects they
/// carry or act on.
struct Focus {
  std::vector<int> devices;
  std::vector<int> objects;
  bool empty() const { return devices.empty() && objects.empty(); }
};

class ActionCamera {
 public:
  explicit ActionCamera(double fov = 45) : fov_(fov) {}
  /// The view of `focus` in `pose`. Keeps the last view's side while it shows the focus (at least
  /// 60% of each object's pixels); otherwise takes the side that shows the most of it, nearest
  /// the last. An empty focus: a three-quarter view of the whole scene.
  Camera at(const Focus& focus, const ScenePose& pose, const GeometryModel& geometry, Renderer& renderer, double aspect);

 private:
  double fov_;
  std::optional<Eigen::Vector3d> side_;  ///< unit vector from the target to the eye, last chosen
};

/// The world bounds of object `o` at `pose` (its geometry's bounds moved with it; a device's
/// parts at their poses).
Eigen::AlignedBox3d bounds_at(const GeometryModel& geometry, const ScenePose& pose, int o);

/// Where a device's tool is at `pose`, in the world.
Eigen::Vector3d tool_at(const GeometryModel& geometry, const ScenePose& pose, int device);

}  // namespace sscs
