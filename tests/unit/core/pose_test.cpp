#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "core/pose.h"

namespace sscs {
namespace {

/// compose() stands in for Eigen's product in the runs' hot loops: it must give the same bits,
/// or a run's numbers would depend on which of the two a loop uses.
TEST(Pose, ComposeIsEigensProductBitForBit) {
  std::mt19937_64 rng(36);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> exponent(-8, 4);
  auto random_pose = [&] {
    Eigen::Quaterniond q(unit(rng), unit(rng), unit(rng), unit(rng));
    q.normalize();
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = q.toRotationMatrix();
    for (int k = 0; k < 3; ++k) X.translation()[k] = unit(rng) * std::ldexp(1.0, exponent(rng));
    return X;
  };
  for (int i = 0; i < 100000; ++i) {
    const Eigen::Isometry3d a = i % 7 == 0 ? Eigen::Isometry3d::Identity() : random_pose(), b = random_pose();
    const Eigen::Isometry3d mine = compose(a, b), eigens = a * b;
    ASSERT_EQ(std::memcmp(mine.data(), eigens.data(), sizeof(double) * 16), 0) << "case " << i << "\n"
                                                                              << mine.matrix() << "\n" << eigens.matrix();
  }
}

}  // namespace
}  // namespace sscs
