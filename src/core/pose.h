#pragma once
/// Rigid poses as the files write them: xyz plus roll, pitch, yaw (the URDF convention).
#include <Eigen/Geometry>

namespace sscs {

/// Rotation of `orientation: [roll, pitch, yaw]` (radians): Rz(yaw) * Ry(pitch) * Rx(roll).
inline Eigen::Matrix3d rpy_to_rotation(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

/// The pose of translation xyz (m) and rotation rpy (rad).
inline Eigen::Isometry3d make_pose(const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = rpy_to_rotation(rpy.x(), rpy.y(), rpy.z());
  X.translation() = xyz;
  return X;
}

}  // namespace sscs
