#include <gtest/gtest.h>

#include <random>

#include "core/units.h"
#include "simulate/support.h"

namespace sscs::testing {
namespace {

/// A rider of mass m standing on the corners of a square `side` wide (its centre of mass
/// `height` above them), placed in the world at X.
struct Stand {
  double m = 20, side = 0.4, height = 0.3;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  std::optional<SupportPatch> patch() const {
    std::vector<Eigen::Vector3d> points, normals;
    for (double x : {-side / 2, side / 2})
      for (double y : {-side / 2, side / 2}) {
        points.push_back(X * Eigen::Vector3d(x, y, -height));
        normals.push_back(X.linear() * Eigen::Vector3d::UnitZ());
      }
    return SupportPatch::from_contacts(points, normals, X);
  }
  /// Whether the patch holds the rider while its support accelerates by `a` (rider frame) and
  /// turns it with angular acceleration `alpha` (rider frame): f = m (a - g), about the centre of
  /// mass tau = I alpha for a solid box side x side x 2 height.
  bool holds(const Eigen::Vector3d& a, const Eigen::Vector3d& alpha = Eigen::Vector3d::Zero()) const {
    const Eigen::Vector3d g(0, 0, -kStandardGravity);
    const double Ixy = m * (side * side + 4 * height * height) / 12, Iz = m * side * side / 6;
    const Eigen::Vector3d tau = Eigen::Vector3d(Ixy, Ixy, Iz).cwiseProduct(alpha);
    return patch()->holds(X.linear() * (m * (a - g)), X.linear() * tau, X.translation(), X, 0.6, 0.7);
  }
};

TEST(SupportPatch, HoldsARiderAtRestAndWhileItsCarrierAcceleratesWithinFriction) {
  Stand s;
  ASSERT_TRUE(s.patch());
  EXPECT_TRUE(s.holds(Eigen::Vector3d::Zero()));
  // Friction: 0.7 x 0.6 x g = 4.12 m/s^2 across. Tipping: the centre of pressure moves a h / g
  // = 0.0306 a from the middle, inside 0.7 x 0.2 = 0.14 m up to a = 4.58 m/s^2: friction first.
  EXPECT_TRUE(s.holds({4.0, 0, 0}));
  EXPECT_FALSE(s.holds({4.3, 0, 0}));
  EXPECT_TRUE(s.holds({0, -4.0, 0}));
  EXPECT_FALSE(s.holds({0, -4.3, 0}));
  // A tall narrow rider tips first: h = 1 m, the centre of pressure a / g m off, out of 0.14 m at
  // a = 1.37 m/s^2.
  Stand tall;
  tall.height = 1.0;
  EXPECT_TRUE(tall.holds({1.3, 0, 0}));
  EXPECT_FALSE(tall.holds({1.45, 0, 0}));
  // Falling faster than gravity: nothing pushes.
  EXPECT_FALSE(s.holds({0, 0, -10}));
  // Lifted harder: more friction.
  EXPECT_TRUE(s.holds({6.0, 0, 9.8}));
  // Spun up about the vertical: twist resisted up to 0.7 x 0.6 x N x 0.283 m.
  const double Iz = s.m * s.side * s.side / 6, twist = 0.7 * 0.6 * s.m * kStandardGravity * std::sqrt(2) * 0.2;
  EXPECT_TRUE(s.holds(Eigen::Vector3d::Zero(), {0, 0, 0.95 * twist / Iz}));
  EXPECT_FALSE(s.holds(Eigen::Vector3d::Zero(), {0, 0, 1.05 * twist / Iz}));
}

TEST(SupportPatch, ALineOfContactsOrContactsFacingApartHoldNothing) {
  // A drum lying on its side touches along a line: it rolls.
  std::vector<Eigen::Vector3d> line, up(4, Eigen::Vector3d::UnitZ());
  for (int k = 0; k < 4; ++k) line.emplace_back(0.2 * k, 0.002 * (k % 2), 0);
  EXPECT_FALSE(SupportPatch::from_contacts(line, up, Eigen::Isometry3d::Identity()));
  // Held at its sides (normals 90 degrees apart): no patch to stand on.
  std::vector<Eigen::Vector3d> square = {{0, 0, 0}, {0.3, 0, 0}, {0.3, 0.3, 0}, {0, 0.3, 0}};
  std::vector<Eigen::Vector3d> sides = {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX()};
  EXPECT_FALSE(SupportPatch::from_contacts(square, sides, Eigen::Isometry3d::Identity()));
  EXPECT_TRUE(SupportPatch::from_contacts(square, up, Eigen::Isometry3d::Identity()));
  EXPECT_FALSE(SupportPatch::from_contacts({{0, 0, 0}, {1, 0, 0}}, {up[0], up[0]}, Eigen::Isometry3d::Identity()));
}

TEST(SupportPatch, TheVerdictDoesNotDependOnWhereTheRiderIsOrHowHardItIsHeld) {
  // Over random placements (rotations, mirror images of the patch, translations), random
  // accelerations and random patches: the same rider on the same patch gets the same verdict
  // anywhere, and scaling force and torque together (a heavier rider of the same shape) changes
  // nothing.
  std::mt19937 rng(36);
  std::uniform_real_distribution<double> u(-1, 1);
  int held = 0, let_go = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<Eigen::Vector3d> points, normals;
    const int n = 3 + static_cast<int>(rng() % 6);
    for (int k = 0; k < n; ++k) {
      points.emplace_back(0.3 * u(rng), 0.3 * u(rng), -0.3 + 0.001 * u(rng));
      normals.push_back(Eigen::Vector3d::UnitZ());
    }
    const Eigen::Vector3d f(60 * u(rng), 60 * u(rng), 200 + 100 * u(rng)), tau(20 * u(rng), 20 * u(rng), 10 * u(rng));
    auto here = SupportPatch::from_contacts(points, normals, Eigen::Isometry3d::Identity());
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = Eigen::AngleAxisd(3 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
    X.translation() = 10 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    const bool mirror = trial % 2;  // the mirror image through the x-z plane, forces mirrored with it
    const Eigen::Matrix3d M = mirror ? Eigen::Vector3d(1, -1, 1).asDiagonal().toDenseMatrix() : Eigen::Matrix3d::Identity();
    std::vector<Eigen::Vector3d> moved_points, moved_normals;
    for (const Eigen::Vector3d& p : points) moved_points.push_back(X * (M * p));
    for (const Eigen::Vector3d& m : normals) moved_normals.push_back(X.linear() * (M * m));
    auto there = SupportPatch::from_contacts(moved_points, moved_normals, X);
    ASSERT_EQ(here.has_value(), there.has_value()) << trial;
    if (!here) continue;
    // A torque is an axial vector: mirrored, it turns the other way (det M = -1).
    const Eigen::Vector3d tau_m = (mirror ? -1.0 : 1.0) * (M * tau);
    const bool a = here->holds(f, tau, Eigen::Vector3d::Zero(), Eigen::Isometry3d::Identity(), 0.6, 0.7);
    const bool b = there->holds(X.linear() * (M * f), X.linear() * tau_m, X.translation(), X, 0.6, 0.7);
    EXPECT_EQ(a, b) << trial;
    EXPECT_EQ(a, here->holds(7.5 * f, 7.5 * tau, Eigen::Vector3d::Zero(), Eigen::Isometry3d::Identity(), 0.6, 0.7)) << trial;
    (a ? held : let_go)++;
  }
  EXPECT_GT(held, 100);
  EXPECT_GT(let_go, 100);
}

}  // namespace
}  // namespace sscs::testing
