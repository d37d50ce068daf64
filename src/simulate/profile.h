#pragma once
/// Joint-space motion profiles: time-optimal trapezoidal velocity profiles within each joint's
/// velocity and acceleration limits, synchronized so that every joint of a move starts and
/// finishes together (the slowest joint sets the duration; the others keep their acceleration
/// limit and cruise slower to match).
#include <vector>

#include <Eigen/Core>

namespace sscs {

/// One joint's trapezoid: accelerate for `ta`, cruise at `v` for `tc`, decelerate for `ta`.
/// A triangle when `tc` is 0. Distances are signed (the direction of the move).
struct Trapezoid {
  double distance = 0;   ///< signed
  double v = 0;          ///< peak speed reached (>= 0)
  double a = 0;          ///< acceleration used (>= 0)
  double ta = 0, tc = 0;
  double duration() const { return 2 * ta + tc; }
  /// Position offset from the start, velocity and acceleration at time t (clamped to [0, duration]).
  double position(double t) const;
  double velocity(double t) const;
  double acceleration(double t) const;
};

/// The fastest trapezoid for `distance` with speed and acceleration limits (both > 0).
Trapezoid fastest(double distance, double vmax, double amax);

/// The trapezoid covering `distance` in exactly `duration` (>= the fastest one's), with the
/// same acceleration limit: the cruise speed is lowered until the times match.
Trapezoid stretched(double distance, double amax, double duration);

/// A synchronized joint-space move from q0 to q1.
class JointMove {
 public:
  /// `vmax`/`amax` per joint (> 0), already scaled by the step's `speed`.
  JointMove(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1, const Eigen::VectorXd& vmax, const Eigen::VectorXd& amax);
  double duration() const { return duration_; }
  Eigen::VectorXd position(double t) const;
  Eigen::VectorXd velocity(double t) const;
  const std::vector<Trapezoid>& profiles() const { return profiles_; }

 private:
  Eigen::VectorXd q0_;
  std::vector<Trapezoid> profiles_;
  double duration_ = 0;
};

}  // namespace sscs
