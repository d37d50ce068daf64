#pragma once
/// A type's templates: the geometry, frames, mass and device parts its type file writes,
/// compiled once when the type is resolved (inheritance flattened) into values over an object's
/// attributes. The geometry stage evaluates them for each object; no later stage reads a type
/// file's text.
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/expr.h"
#include "core/joint_type.h"
#include "core/source.h"

namespace sscs {

/// One value of a type file, compiled: a constant in SI, or an expression over the type's
/// attributes. A subtype lists its base's attributes first and in the same order, so a base's
/// template reads an object of the subtype too.
struct ValueRef {
  bool present = false;
  double constant = NAN;                   ///< SI, when it is no expression
  std::shared_ptr<const Expression> expr;  ///< over attributes
  std::vector<int> attributes;             ///< the attribute index of each of expr->names()
  std::string text;                        ///< as written, for messages
  SourceMark mark;
  /// Its value for an object whose attribute values (SI) start at `attributes_si`; `fallback`
  /// when the type file does not give it.
  double eval(const double* attributes_si, double fallback) const;
};

/// Three values (a size, a scale, an axis).
struct VectorRef {
  std::array<ValueRef, 3> v;
  Eigen::Vector3d eval(const double* attributes_si, double fallback) const;
};

/// `xyz`/`rpy`: a placement in the frame of what it belongs to.
struct PoseRef {
  VectorRef xyz, rpy;
  Eigen::Isometry3d eval(const double* attributes_si) const;
};

struct ShapeTemplate {
  enum class Kind : uint8_t { Box, Cylinder, Sphere, Mesh } kind = Kind::Box;
  PoseRef pose;
  VectorRef size;           ///< box: full extents
  ValueRef radius, length;  ///< cylinder (along z); sphere: radius
  VectorRef scale;          ///< mesh; absent: 1
  std::string mesh_file;    ///< mesh: the file, resolved against the file that names it
  std::string mesh_text;    ///< mesh: as written
  SourceMark mesh_mark;
  std::string color;        ///< "#rrggbb" of this shape alone (a URDF visual's material), or ""
};

struct FrameTemplate {
  std::string name;
  PoseRef pose;
};

struct JointTemplate {
  std::string name;
  JointType type = JointType::Fixed;
  PoseRef origin;  ///< in the parent part's frame, at value 0
  VectorRef axis;
  ValueRef velocity, acceleration, effort;
};

struct PartTemplate {
  std::string name;
  int parent = -1;  ///< the index of its parent part, -1 for the root
  std::optional<JointTemplate> joint;
  std::vector<ShapeTemplate> shapes;         ///< what it collides with
  std::vector<ShapeTemplate> visual_shapes;  ///< what it looks like, where that differs
  ValueRef mass;
  std::string color;
  struct Inertial {
    PoseRef origin;
    std::array<ValueRef, 6> inertia;  ///< ixx ixy ixz iyy iyz izz
  };
  std::optional<Inertial> inertial;
};

/// A device's parts, their joints and its tool.
struct DeviceTemplate {
  std::vector<PartTemplate> parts;              ///< in the type file's order
  std::vector<int> build_order;                 ///< parents before children, from the root
  std::vector<int> joint_parts;                 ///< the parts whose joint moves, in the type file's order (the joint vector)
  std::vector<std::pair<int, int>> allowed;     ///< parts that may touch in any pose (a < b)
  int tool_part = -1;                           ///< the part the type names, else -1: the end of the longest chain
  PoseRef tool_pose;                            ///< in the tool part's frame
  bool kinematic = false;                       ///< `driven: kinematic`
  bool from_urdf = false;                       ///< imported: its part masses were checked by the import
  // As the type file writes them, for listings and run bundles.
  std::string urdf, srdf;                       ///< as written, or ""
  bool hard_limits = false;                     ///< `joint_limits: hard`
  std::vector<std::pair<std::string, std::string>> allowed_names;  ///< as listed
  /// Each mesh reference of the URDF as written and the file it names (bundles rewrite them).
  std::vector<std::pair<std::string, std::string>> urdf_mesh_refs;
};

/// What later stages build an object of a type from, inheritance flattened.
struct TypeTemplates {
  std::vector<ShapeTemplate> geometry;           ///< its own, else the nearest base's that has some
  std::vector<FrameTemplate> frames;             ///< bases' first; one of the same name replaces its base's
  ValueRef mass;                                 ///< declared: its own, else the nearest base's
  std::string mass_type;                         ///< the type that declares it
  std::shared_ptr<const DeviceTemplate> device;  ///< its parts, else the nearest base's
  bool has_color = false;                        ///< its own `color:` (a colour is not inherited), checked per object
  std::string color;
  SourceMark color_mark;
};

}  // namespace sscs
