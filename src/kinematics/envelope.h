#pragma once
/// A device's reach envelope: the bounding box of its tool's positions over the joint ranges.
#include <vector>

#include <Eigen/Geometry>

#include "model/device.h"

namespace sscs {

/// The axis-aligned box (in the object's frame) of the tool's origin over the ranges of the joints
/// on the root-to-tool chain (other joints at `q`). Exact for chains of prismatic joints (their
/// corners); for revolute joints a deterministic sample: every corner of the limit box when there
/// are at most 7 joints, a grid over the ranges as fine as 50,000 configurations allow (21 values
/// per joint up to 3 joints, 9 for 4 ...), and 20,000 seeded random configurations beyond 3. An unlimited revolute joint spans a turn; an unlimited prismatic joint makes
/// the envelope unbounded along its axis (infinite bounds).
Eigen::AlignedBox3d reach_envelope(const Device& device, const Eigen::VectorXd& q);

/// `count` points the tool's origin reaches (in the object's frame), at seeded random values of
/// the chain's joints over their ranges (other joints at `q`; an unlimited prismatic joint stays
/// at 0): the HTML report's picture of where a device reaches, collisions and orientation aside.
std::vector<Eigen::Vector3d> reach_points(const Device& device, const Eigen::VectorXd& q, int count);

}  // namespace sscs
