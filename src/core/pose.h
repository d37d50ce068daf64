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

/// a * b of two isometries, bit for bit as Eigen's product computes it, written out for the hot
/// loops of runs: in a large source file GCC leaves Eigen's product out of line, a lazy loop of
/// about 125 instructions (a fast run of the reference store made 760,000 of them). Eigen sums
/// rows 0 and 1 as packets, (x0 + x1) + x2, and row 2 as a scalar reduction, x0 + (x1 + x2);
/// the translation is added last. (tests/unit/core/pose_test.cpp holds it to Eigen's bits.)
[[gnu::always_inline]] inline Eigen::Isometry3d compose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  const double* A = a.data();  // column-major 4 x 4: element (i, j) at A[4 j + i]
  const double* B = b.data();
  Eigen::Isometry3d out;
  double* O = out.data();
  for (int j = 0; j < 4; ++j) {
    const double b0 = B[4 * j], b1 = B[4 * j + 1], b2 = B[4 * j + 2];
    O[4 * j] = (A[0] * b0 + A[4] * b1) + A[8] * b2;
    O[4 * j + 1] = (A[1] * b0 + A[5] * b1) + A[9] * b2;
    O[4 * j + 2] = A[2] * b0 + (A[6] * b1 + A[10] * b2);
  }
  for (int i = 0; i < 3; ++i) O[12 + i] += A[12 + i];
  O[3] = O[7] = O[11] = 0;
  O[15] = 1;
  return out;
}

}  // namespace sscs
