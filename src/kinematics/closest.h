#pragma once
/// The closest a chain's tip can come to a target it cannot reach: the reach margin of a failing
/// target (vault-format.md, `reach`) is minus the smallest position error over every joint
/// configuration within limits (and, with `orientation: match`, with the tool turned as the
/// target asks) that the caller accepts (free of collision). A property of the device and the
/// target, not of where a search stopped: the search is global and deterministic — a fixed
/// low-discrepancy set of starts over the whole joint box, the best of them refined by
/// bound-constrained Gauss-Newton to convergence — so mirror-image targets of a symmetric
/// device get the same margin and a target moved away never gets a better one.
#include <functional>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kinematics/ik.h"

namespace sscs {

struct ClosestReach {
  bool found = false;          ///< some configuration was accepted
  Eigen::VectorXd q;           ///< chain joint values of the closest accepted configuration
  double position_error = 0;   ///< m, at q
  double angle_error = 0;      ///< rad, at q (0 with a free orientation)
};

/// The accepted configuration of `chain` (within limits) whose tip comes closest to `target`
/// (root frame): with `orientation`, among those turned as the target is (the rotation error is
/// minimised first, weighted a thousandfold over the position), else by position alone.
/// `accept` (may be empty) rejects a configuration (a collision). `seed` is one more start.
ClosestReach closest_reach(const Chain& chain, const Eigen::Isometry3d& target, bool orientation, const Eigen::VectorXd& seed,
                           const std::function<bool(const Eigen::VectorXd&)>& accept = {});

/// The closest accepted configuration found when the closest of all collides: from the accepted
/// ones among closest_reach's starts, the best few by cost, each improved by a pattern search
/// that moves one joint at a time and keeps only accepted, better moves, down to steps of 1e-5.
/// The answer is a configuration `accept` takes, so its error is never below the true smallest
/// (a margin from it is never better than the truth); found is false when no start is accepted.
/// With `rays`, also from the first accepted configuration on each of 128 rays out of `seed`
/// (the search for a target reached only in collision, from the colliding solution: the free
/// pocket beside it). Without, for the closest of all colliding: the rays cost a store's check
/// 4x and changed none of its 210 margins.
ClosestReach closest_free(const Chain& chain, const Eigen::Isometry3d& target, bool orientation, const Eigen::VectorXd& seed,
                         const std::function<bool(const Eigen::VectorXd&)>& accept, bool rays = false);

}  // namespace sscs
