#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include "core/units.h"

namespace sscs {

namespace {
}

Eigen::Matrix4d view_matrix(const Camera& c) {
  Eigen::Vector3d f = (c.target - c.eye).normalized();
  // Up is world +Z; looking straight up or down, +Y stands in.
  Eigen::Vector3d up = std::abs(f.z()) > 0.999 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  Eigen::Vector3d s = f.cross(up).normalized();
  Eigen::Vector3d u = s.cross(f);
  Eigen::Matrix4d V = Eigen::Matrix4d::Identity();
  V.block<1, 3>(0, 0) = s.transpose();
  V.block<1, 3>(1, 0) = u.transpose();
  V.block<1, 3>(2, 0) = -f.transpose();
  V(0, 3) = -s.dot(c.eye);
  V(1, 3) = -u.dot(c.eye);
  V(2, 3) = f.dot(c.eye);
  return V;
}

Eigen::Matrix4d projection_matrix(double fov_deg, double aspect, double near, double far) {
  const double t = 1 / std::tan(fov_deg * kPi / 360);
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P(0, 0) = t / aspect;
  P(1, 1) = t;
  P(2, 2) = (far + near) / (near - far);
  P(2, 3) = 2 * far * near / (near - far);
  P(3, 2) = -1;
  return P;
}

Eigen::Vector2d project_to_pixel(const Camera& camera, int width, int height, const Eigen::Vector3d& world) {
  Eigen::Vector4d clip = projection_matrix(camera.fov, double(width) / height, 0.1, 100) * view_matrix(camera) *
                         world.homogeneous();
  Eigen::Vector2d ndc = clip.head<2>() / clip.w();
  return {(ndc.x() + 1) / 2 * width, (1 - ndc.y()) / 2 * height};
}

Camera framing_camera(const Eigen::AlignedBox3d& bounds, double fov_deg, double aspect) {
  Camera c;
  c.fov = fov_deg;
  if (bounds.isEmpty()) return c;
  c.target = bounds.center();
  const double az = -125 * kPi / 180, el = 30 * kPi / 180;
  const Eigen::Vector3d back(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  // The eye at distance d along `back`: the nearest d at which every corner of the bounds lies
  // inside both half-angles of the view, plus 5 %.
  const Eigen::Vector3d f = -back, r = f.cross(Eigen::Vector3d::UnitZ()).normalized(), u = r.cross(f);
  const double ty = std::tan(fov_deg * kPi / 360), tx = ty * aspect;
  double d = 0.1;
  for (int k = 0; k < 8; ++k) {
    Eigen::Vector3d p = bounds.corner(Eigen::AlignedBox3d::CornerType(k)) - c.target;
    double z = p.dot(f);  // towards the target: a corner behind it needs the eye farther back
    d = std::max({d, z + std::abs(p.dot(r)) / tx, z + std::abs(p.dot(u)) / ty});
  }
  c.eye = c.target + 1.05 * d * back;
  return c;
}

}  // namespace sscs
