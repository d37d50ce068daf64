#pragma once
/// Cameras: where the eye is, what it looks at, and the vertical field of view; image up is
/// world +Z projected (scenario-format.md). The matrices follow OpenGL's conventions.
#include <Eigen/Geometry>

namespace sscs {

struct Camera {
  Eigen::Vector3d eye = Eigen::Vector3d(10, -10, 8);
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  double fov = 45;  ///< vertical, degrees
};

/// World -> camera (looking down -z, +y up on the image).
Eigen::Matrix4d view_matrix(const Camera& camera);
/// Camera -> clip space for a width/height aspect and depth range [near, far].
Eigen::Matrix4d projection_matrix(double fov_deg, double aspect, double near, double far);
/// The pixel (x from the left, y from the top, pixel centres at .5) where a world point lands.
Eigen::Vector2d project_to_pixel(const Camera& camera, int width, int height, const Eigen::Vector3d& world);
/// A three-quarter view of `bounds` (from the -y, -x side, 30 degrees up) that fits it in view.
Camera framing_camera(const Eigen::AlignedBox3d& bounds, double fov_deg, double aspect);

}  // namespace sscs
