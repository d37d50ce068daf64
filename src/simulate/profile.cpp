#include "simulate/profile.h"

#include <algorithm>
#include <cmath>

namespace sscs {

double Trapezoid::position(double t) const {
  t = std::clamp(t, 0.0, duration());
  double sign = distance < 0 ? -1.0 : 1.0;
  double s;
  if (t < ta) s = 0.5 * a * t * t;
  else if (t < ta + tc) s = 0.5 * a * ta * ta + v * (t - ta);
  else {
    double td = duration() - t;  // time left: the deceleration mirrors the acceleration
    s = std::abs(distance) - 0.5 * a * td * td;
  }
  return sign * s;
}

double Trapezoid::velocity(double t) const {
  if (t <= 0 || t >= duration()) return 0;
  double sign = distance < 0 ? -1.0 : 1.0;
  if (t < ta) return sign * a * t;
  if (t < ta + tc) return sign * v;
  return sign * a * (duration() - t);
}

double Trapezoid::acceleration(double t) const {
  if (t <= 0 || t >= duration()) return 0;
  double sign = distance < 0 ? -1.0 : 1.0;
  if (t < ta) return sign * a;
  if (t < ta + tc) return 0;
  return -sign * a;
}

Trapezoid fastest(double distance, double vmax, double amax) {
  Trapezoid p;
  p.distance = distance;
  double d = std::abs(distance);
  if (d == 0) return p;
  p.a = amax;
  if (d >= vmax * vmax / amax) {  // reaches full speed
    p.v = vmax;
    p.ta = vmax / amax;
    p.tc = (d - vmax * vmax / amax) / vmax;
  } else {  // a triangle
    p.v = std::sqrt(d * amax);
    p.ta = p.v / amax;
    p.tc = 0;
  }
  return p;
}

Trapezoid stretched(double distance, double amax, double duration) {
  Trapezoid p;
  p.distance = distance;
  double d = std::abs(distance);
  if (d == 0 || duration <= 0) return p;
  // Cruise speed v with accel a over total time T: d = v (T - v / a), so
  // v = (a T - sqrt(a^2 T^2 - 4 a d)) / 2 (the smaller root keeps 2 ta <= T).
  double disc = amax * amax * duration * duration - 4 * amax * d;
  p.a = amax;
  p.v = 0.5 * (amax * duration - std::sqrt(std::max(disc, 0.0)));
  p.ta = p.v / amax;
  p.tc = std::max(duration - 2 * p.ta, 0.0);
  return p;
}

JointMove::JointMove(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1, const Eigen::VectorXd& vmax,
                     const Eigen::VectorXd& amax)
    : q0_(q0) {
  const long n = q0.size();
  for (long k = 0; k < n; ++k) duration_ = std::max(duration_, fastest(q1[k] - q0[k], vmax[k], amax[k]).duration());
  for (long k = 0; k < n; ++k) profiles_.push_back(stretched(q1[k] - q0[k], amax[k], duration_));
}

Eigen::VectorXd JointMove::position(double t) const {
  Eigen::VectorXd q = q0_;
  for (size_t k = 0; k < profiles_.size(); ++k) q[static_cast<long>(k)] += profiles_[k].position(t);
  return q;
}

Eigen::VectorXd JointMove::velocity(double t) const {
  Eigen::VectorXd v(static_cast<long>(profiles_.size()));
  for (size_t k = 0; k < profiles_.size(); ++k) v[static_cast<long>(k)] = profiles_[k].velocity(t);
  return v;
}

}  // namespace sscs
