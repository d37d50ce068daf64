#pragma once
/// Rigid poses as the files write them: xyz plus roll, pitch, yaw (the URDF convention).
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace sscs {

/// Rotation of `orientation: [roll, pitch, yaw]` (radians): Rz(yaw) * Ry(pitch) * Rx(roll).
inline Eigen::Matrix3d rpy_to_rotation(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

/// The roll, pitch, yaw (rad) of a rotation: the inverse of rpy_to_rotation (pitch in ±pi/2).
inline Eigen::Vector3d rotation_to_rpy(const Eigen::Matrix3d& R) {
  return {std::atan2(R(2, 1), R(2, 2)), std::asin(std::clamp(-R(2, 0), -1.0, 1.0)), std::atan2(R(1, 0), R(0, 0))};
}

/// The pose of translation xyz (m) and rotation rpy (rad).
inline Eigen::Isometry3d make_pose(const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = rpy_to_rotation(rpy.x(), rpy.y(), rpy.z());
  X.translation() = xyz;
  return X;
}

}  // namespace sscs
