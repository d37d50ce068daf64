#include "model/device.h"
#include "core/pose.h"

#include <numbers>

#include <algorithm>

namespace sscs {

double Joint::max_speed() const {
  constexpr double kRevoluteSpeed = 90 * std::numbers::pi / 180, kPrismaticSpeed = 0.5;  // docs/simulation.md
  return velocity > 0 ? velocity : type == JointType::Revolute ? kRevoluteSpeed : kPrismaticSpeed;
}

double Joint::max_acceleration() const { return acceleration > 0 ? acceleration : 2 * max_speed(); }


Eigen::Isometry3d joint_transform(const Joint& j, double value) {
  switch (j.type) {
    case JointType::Revolute: return j.origin * Eigen::AngleAxisd(value, j.axis);
    case JointType::Prismatic: return j.origin * Eigen::Translation3d(j.axis * value);
    case JointType::Fixed: break;
  }
  return j.origin;
}

int Device::find_part(std::string_view name) const {
  for (size_t i = 0; i < parts.size(); ++i)
    if (parts[i].name == name) return static_cast<int>(i);
  return -1;
}

bool Device::may_touch(int a, int b) const {
  if (adjacent(a, b)) return true;
  return std::binary_search(allowed.begin(), allowed.end(), std::pair(std::min(a, b), std::max(a, b)));
}

Eigen::VectorXd Device::joint_values(const double* attribute_values) const {
  Eigen::VectorXd q(dof());
  for (int k = 0; k < dof(); ++k) q[k] = attribute_values[joint(k).attribute];
  return q;
}

std::vector<Eigen::Isometry3d> Device::part_poses(const Eigen::VectorXd& q) const {
  std::vector<Eigen::Isometry3d> X;
  part_poses(q, X);
  return X;
}

void Device::part_poses(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>& X) const {
  X.resize(parts.size());
  for (size_t i = 0; i < parts.size(); ++i) {
    const Part& p = parts[i];
    if (p.parent < 0) {
      X[i].setIdentity();
      continue;
    }
    X[i] = compose(X[p.parent], joint_transform(p.joint, p.joint.q >= 0 ? q[p.joint.q] : 0.0));
  }
}

Eigen::Isometry3d Device::tool_pose(const Eigen::VectorXd& q) const { return part_poses(q)[tool_part] * X_part_tool; }

std::vector<char> Device::moved_parts() const {
  std::vector<char> out(parts.size(), 0);
  for (size_t p = 0; p < parts.size(); ++p)  // parents come first
    out[p] = parts[p].parent >= 0 && (out[parts[p].parent] || parts[p].joint.type != JointType::Fixed);
  return out;
}

std::vector<char> Device::tool_parts() const {
  // The tool is a rigid body: its part and every part fixed to it, up the tree too (ROS-Industrial's
  // tool0 hangs off link_6 by a fixed joint: link_6 is the flange the tool is bolted to).
  int top = tool_part;
  while (parts[top].parent >= 0 && parts[top].joint.type == JointType::Fixed) top = parts[top].parent;
  std::vector<char> out(parts.size(), 0);
  for (size_t p = 0; p < parts.size(); ++p)  // parents come first: the rigid body and what it carries
    out[p] = static_cast<int>(p) == top || (parts[p].parent >= 0 && out[parts[p].parent]);
  return out;
}

bool Device::within_limits(const Eigen::VectorXd& q, double eps) const {
  for (int k = 0; k < dof(); ++k)
    if (q[k] < joint(k).lower - eps || q[k] > joint(k).upper + eps) return false;
  return true;
}

}  // namespace sscs
