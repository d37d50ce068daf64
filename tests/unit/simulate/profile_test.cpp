#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "simulate/profile.h"
#include "core/units.h"

namespace sscs {
namespace {


TEST(Profile, TrapezoidTakesTheAnalyticTime) {
  // 90 deg at 90 deg/s and 180 deg/s^2: 0.5 s up (22.5 deg), 0.5 s cruise (45 deg), 0.5 s down.
  Trapezoid p = fastest(90 * kRadPerDeg, 90 * kRadPerDeg, 180 * kRadPerDeg);
  EXPECT_NEAR(p.duration(), 1.5, 1e-12);
  EXPECT_NEAR(p.ta, 0.5, 1e-12);
  EXPECT_NEAR(p.position(0.5), 22.5 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(p.position(1.0), 67.5 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(p.position(1.5), 90 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(p.velocity(0.75), 90 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(p.acceleration(1.25), -180 * kRadPerDeg, 1e-12);
}

TEST(Profile, ShortMovesAreTriangles) {
  // 10 deg never reaches 90 deg/s: peak sqrt(d a), time 2 sqrt(d / a).
  Trapezoid p = fastest(-10 * kRadPerDeg, 90 * kRadPerDeg, 180 * kRadPerDeg);
  EXPECT_NEAR(p.tc, 0, 1e-12);
  EXPECT_NEAR(p.duration(), 2 * std::sqrt(10.0 / 180.0), 1e-12);
  EXPECT_NEAR(p.v, std::sqrt(10 * kRadPerDeg * 180 * kRadPerDeg), 1e-12);
  EXPECT_NEAR(p.position(p.duration()), -10 * kRadPerDeg, 1e-12);
  EXPECT_LT(p.velocity(p.ta), 0);  // moving the negative way
}

TEST(Profile, JointsFinishTogetherWithinTheirLimits) {
  Eigen::VectorXd q0(3), q1(3), v(3), a(3);
  q0 << 0, 1, -0.5;
  q1 << 1.5, 1, 0.2;  // the middle joint stays
  v << 1.0, 2.0, 0.3;
  a << 2.0, 4.0, 0.5;
  JointMove m(q0, q1, v, a);
  // The slowest joint: 0.7 at 0.3 / 0.5 -> ta 0.6 s, cruise (0.7 - 0.18) / 0.3 s.
  EXPECT_NEAR(m.duration(), 2 * 0.6 + (0.7 - 0.18) / 0.3, 1e-12);
  EXPECT_TRUE(m.position(m.duration()).isApprox(q1, 1e-12));
  EXPECT_TRUE(m.position(0).isApprox(q0, 1e-12));
  // Sampled: within speed and acceleration limits, and the velocity integrates to the position.
  const double dt = 1e-4;
  Eigen::VectorXd integrated = q0, previous_v = Eigen::VectorXd::Zero(3);
  for (double t = 0; t < m.duration(); t += dt) {
    Eigen::VectorXd vel = m.velocity(t + dt / 2);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(std::abs(vel[k]), v[k] + 1e-12);
      EXPECT_LE(std::abs(vel[k] - previous_v[k]) / dt, a[k] * 1.001 + 1e-9);
    }
    integrated += vel * std::min(dt, m.duration() - t);
    previous_v = vel;
  }
  EXPECT_TRUE(integrated.isApprox(q1, 1e-6)) << integrated.transpose();
  for (const Trapezoid& p : m.profiles())
    if (p.distance != 0) {  // a joint that stays has no profile
      EXPECT_NEAR(p.duration(), m.duration(), 1e-9);
    }
}

}  // namespace
}  // namespace sscs
