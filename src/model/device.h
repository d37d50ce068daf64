#pragma once
/// A device instance's kinematic model: a tree of parts joined by joints, with every value of
/// the type file evaluated at the instance's attributes (a gantry's span, an arm's link length),
/// and its forward kinematics. The one device model: built by the geometry stage, read by
/// collision, kinematics (IK, chains), the checker, the simulator and render.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/joint_type.h"
#include "model/shape.h"

namespace sscs {

struct Joint {
  std::string name;
  JointType type = JointType::Fixed;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< in the parent part's frame, at value 0
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();              ///< unit, in the joint's frame
  double lower = -INFINITY, upper = INFINITY;                   ///< SI (rad or m)
  double velocity = 0, acceleration = 0, effort = 0;            ///< SI; 0 when not given
  int attribute = -1;                                           ///< the instance attribute holding its value
  int q = -1;                                                   ///< index in the device's joint vector

  /// How fast the planner moves it (SI): its velocity, else 90 deg/s (revolute) or 0.5 m/s.
  double max_speed() const;
  /// Its acceleration, else twice its speed per second.
  double max_acceleration() const;
};

struct Part {
  std::string name;
  int parent = -1;  ///< parts come after their parent
  Joint joint;      ///< how it hangs on its parent; Fixed for the root
  std::vector<Shape> shapes;  ///< in the part's frame
  std::vector<Shape> visual_shapes;  ///< in the part's frame: what it looks like (GeometryOptions::visuals)
  double mass = 0;
  /// Centre of mass and inertia about it, in the part's frame, when the type gives them (URDF).
  std::optional<Eigen::Vector3d> com;
  std::optional<Eigen::Matrix3d> inertia;
  std::string color;
};

/// The kinematic model of one device instance. The root part's frame is the object's frame.
struct Device {
  std::vector<Part> parts;        ///< topological order: every parent before its children
  std::vector<int> joint_parts;   ///< parts whose joint moves, in joint-vector order
  int tool_part = 0;
  Eigen::Isometry3d X_part_tool = Eigen::Isometry3d::Identity();
  bool kinematic = false;         ///< `driven: kinematic`

  int dof() const { return static_cast<int>(joint_parts.size()); }
  const Joint& joint(int q) const { return parts[joint_parts[q]].joint; }
  /// Index of the part named `name`, or -1.
  int find_part(std::string_view name) const;
  /// Joint values read from an instance's slot values (its attributes).
  Eigen::VectorXd joint_values(const double* attribute_values) const;
  /// Pose of every part in the object's frame at joint values q.
  std::vector<Eigen::Isometry3d> part_poses(const Eigen::VectorXd& q) const;
  /// The same, into `X` (its storage reused: a run's glides ask it thousands of times).
  void part_poses(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>& X) const;
  /// Pose of the tool in the object's frame at joint values q.
  Eigen::Isometry3d tool_pose(const Eigen::VectorXd& q) const;
  /// Whether parts a and b are joined directly (one is the other's parent): such parts touch by
  /// design and are not checked against each other for self-collision.
  bool adjacent(int a, int b) const { return parts[a].parent == b || parts[b].parent == a; }
  /// Pairs of parts the type allows to touch (allowed_collisions, an SRDF's disabled pairs),
  /// each (smaller index, larger), sorted.
  std::vector<std::pair<int, int>> allowed;
  /// Whether a and b may touch without a self-collision: adjacent, or an allowed pair.
  bool may_touch(int a, int b) const;
  /// Per part: whether it belongs to the tool: the tool's part, every part rigidly attached to it
  /// through fixed joints (either way: the flange a tool0 frame hangs off), and the parts those
  /// carry. These may touch what the tool holds or reaches for.
  std::vector<char> tool_parts() const;
  /// Per part, whether a joint moves it: a revolute or prismatic joint between it and the root.
  /// The others (the root, and parts fixed to it through fixed joints only) stand where the
  /// device stands.
  std::vector<char> moved_parts() const;
  /// Whether q lies within every joint's limits (within `eps`).
  bool within_limits(const Eigen::VectorXd& q, double eps = 1e-9) const;
};

/// The pose a joint adds at value `value`: its origin, then the motion about/along its axis.
Eigen::Isometry3d joint_transform(const Joint& j, double value);

}  // namespace sscs
