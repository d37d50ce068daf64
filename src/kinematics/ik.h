#pragma once
/// Forward and inverse kinematics of a serial chain: the path of joints from a device's root part
/// to its tool. The inverse solver is damped least squares (Levenberg–Marquardt with the damping
/// of Sugihara 2011) inside joint limits, with restarts from deterministic pseudo-random seeds.
/// It never hangs: every solve is bounded by an iteration budget and a wall-clock limit.
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "model/device.h"

namespace sscs {

/// The joints from the root to a tip frame, as a flat list for fast evaluation.
class Chain {
 public:
  /// The chain of `device` from its root to its tool (or to `tip_part` at `X_part_tip`).
  explicit Chain(const Device& device);
  Chain(const Device& device, int tip_part, const Eigen::Isometry3d& X_part_tip);

  int size() const { return static_cast<int>(links_.size()); }  ///< moving joints on the chain
  double lower(int k) const { return links_[k].lower; }
  double upper(int k) const { return links_[k].upper; }
  bool revolute(int k) const { return links_[k].revolute; }
  /// The device joint-vector index of chain joint k.
  int device_index(int k) const { return links_[k].q; }
  /// Chain joint values taken from / written into a device joint vector.
  Eigen::VectorXd from_device(const Eigen::VectorXd& device_q) const;
  void to_device(const Eigen::VectorXd& chain_q, Eigen::VectorXd& device_q) const;

  /// Tip pose in the device's root frame at chain joint values q.
  Eigen::Isometry3d forward(const Eigen::VectorXd& q) const;
  /// Tip pose and its geometric Jacobian (rows: linear then angular velocity, root frame).
  Eigen::Isometry3d forward(const Eigen::VectorXd& q, Eigen::Matrix<double, 6, Eigen::Dynamic>& jacobian) const;
  /// An upper bound of the distance from the chain's first moving joint to the tip, and that
  /// joint's position at q (for rejecting targets that are plainly out of reach).
  double reach_bound() const { return reach_bound_; }
  Eigen::Vector3d base_point() const { return base_point_; }

 private:
  struct Link {
    Eigen::Isometry3d before;  ///< fixed transform from the previous moving joint (or the root)
    Eigen::Vector3d axis;
    bool revolute = true;
    double lower, upper;
    int q;
  };
  std::vector<Link> links_;
  Eigen::Isometry3d tip_ = Eigen::Isometry3d::Identity();  ///< after the last moving joint
  double reach_bound_ = 0;
  Eigen::Vector3d base_point_ = Eigen::Vector3d::Zero();
};

struct IkOptions {
  bool orientation = true;        ///< full pose; false: the tip's position only
  double position_tol = 1e-5;     ///< m, per axis
  double angle_tol = 1e-5;        ///< rad, per axis of the rotation error
  int iterations_per_attempt = 60;
  int max_attempts = 200;         ///< the seed, then restarts
  double time_limit = 0.05;       ///< s; a backstop, the iteration budget normally ends a solve; INFINITY: none
  uint64_t random_seed = 1;       ///< restarts are deterministic for a given seed
  /// After the first solution, further attempts looking for one nearer the seed (0: stop at the first).
  int extra_attempts = 0;
};

struct IkResult {
  enum class Status : uint8_t { Reached, Unreachable, Rejected } status = Status::Unreachable;
  Eigen::VectorXd q;              ///< the solution, or the best configuration found
  double position_error = 0;      ///< m, Euclidean, at q
  double angle_error = 0;         ///< rad, at q (0 in position-only mode)
  int iterations = 0;
  int attempts = 0;
  /// The time backstop, not the iteration budget, ended the search: a target not reached may
  /// still be reachable, so no verdict rests on it.
  bool timed_out = false;
  bool ok() const { return status == Status::Reached; }
};

/// Finds chain joint values within limits that put the tip at `target` (root frame), starting
/// from `seed` and returning the solution nearest to it among those found. `accept` may reject
/// a solution (a collision): the solver then keeps looking, and reports Rejected if every
/// solution it found was rejected.
IkResult solve_ik(const Chain& chain, const Eigen::Isometry3d& target, const Eigen::VectorXd& seed,
                  const IkOptions& options, const std::function<bool(const Eigen::VectorXd&)>& accept = {});

/// The 6-vector pose error (position, then rotation vector) from `current` to `target`.
Eigen::Matrix<double, 6, 1> pose_error(const Eigen::Isometry3d& current, const Eigen::Isometry3d& target);

}  // namespace sscs
