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
#include <string_view>
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
  /// An entry of `attributes` at or above this is a repeat counter (kCounter + its index).
  static constexpr int kCounter = 1 << 24;
  bool present = false;
  double constant = NAN;                   ///< SI, when it is no expression
  std::shared_ptr<const Expression> expr;  ///< over attributes (and the counters of a repeat)
  std::vector<int> attributes;             ///< the attribute index of each of expr->names()
  std::string text;                        ///< as written, for messages
  SourceMark mark;
  /// Its value for an object whose attribute values (SI) start at `attributes_si`; `fallback`
  /// when the type file does not give it; `counters`, a repeated entry's copy (its counters' values).
  double eval(const double* attributes_si, double fallback, const double* counters = nullptr) const;
};

/// Three values (a size, a scale, an axis).
struct VectorRef {
  std::array<ValueRef, 3> v;
  Eigen::Vector3d eval(const double* attributes_si, double fallback, const double* counters = nullptr) const;
};

/// `xyz`/`rpy`: a placement in the frame of what it belongs to.
struct PoseRef {
  VectorRef xyz, rpy;
  Eigen::Isometry3d eval(const double* attributes_si, const double* counters = nullptr) const;
};

/// `repeat:` of a geometry entry or frame: a copy for each combination of its counters, the
/// first outermost, each running from 1 to its count (over the object's attributes).
struct RepeatTemplate {
  /// The most copies one entry makes for one object (a rack of 15 levels x 60 bays is 900; 10,000
  /// small boxes in each of two objects already take a minute to compare in full).
  static constexpr double kMaxCopies = 10000;
  struct Counter {
    std::string name;
    ValueRef count;
    VectorRef pitch;  ///< copy k moves by (k - 1) pitches; absent: 0
  };
  std::vector<Counter> counters;
  SourceMark mark;

  /// What is wrong with the counts for an object ("" when nothing): each a whole number from 0,
  /// all of them together at most kMaxCopies copies.
  std::string problem(const double* attributes_si) const;
  /// Calls `f(counters)` for each copy, `counters` holding each counter's value; nothing when
  /// problem() is not empty.
  template <class F>
  void each(const double* attributes_si, F&& f) const {
    if (!problem(attributes_si).empty()) return;
    std::vector<double> count(counters.size()), at(counters.size(), 1);
    for (size_t k = 0; k < counters.size(); ++k) {
      count[k] = counters[k].count.eval(attributes_si, 0);
      if (count[k] < 1) return;
    }
    while (true) {
      f(static_cast<const double*>(at.data()));
      size_t k = counters.size();
      while (k > 0 && at[k - 1] >= count[k - 1]) at[--k] = 1;
      if (k == 0) return;
      at[k - 1] += 1;
    }
  }
  /// How far copy `at` moves from the first: the sum of its counters' pitches.
  Eigen::Vector3d offset(const double* attributes_si, const double* at) const;
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
  std::shared_ptr<const RepeatTemplate> repeat;  ///< copies of it, or null
};

struct FrameTemplate {
  std::string name;  ///< with `{counter}` for each counter of a repeated frame
  PoseRef pose;
  std::shared_ptr<const RepeatTemplate> repeat;  ///< copies of it, or null
  SourceMark mark;   ///< where its type file writes it (an editor's "go to definition")
  /// The frame's name and pose (in the object's frame) for each copy.
  template <class F>
  void each(const double* attributes_si, F&& f) const {
    if (!repeat) return f(name, pose.eval(attributes_si));
    repeat->each(attributes_si, [&](const double* at) {
      Eigen::Isometry3d X = pose.eval(attributes_si, at);
      X.translation() += repeat->offset(attributes_si, at);
      f(name_of(at), X);
    });
  }
  /// The name of copy `at`: each `{counter}` replaced by its value.
  std::string name_of(const double* at) const;
  /// The pose of its copy named `copy`, if it has one; only that copy's pose is evaluated (143
  /// drums placed at a rack's slots evaluated every slot's pose for each drum).
  std::optional<Eigen::Isometry3d> find(const double* attributes_si, std::string_view copy) const;
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
/// A rule every instance keeps (`requires:`): a condition over the attributes, true when not 0.
struct RuleTemplate {
  ValueRef condition;
  std::string message;
  std::string type;  ///< the type that states it
};

struct TypeTemplates {
  std::vector<ShapeTemplate> geometry;           ///< its own, else the nearest base's that has some
  std::vector<RuleTemplate> rules;               ///< bases' first, then its own
  std::vector<FrameTemplate> frames;             ///< bases' first; one of the same name replaces its base's
  ValueRef mass;                                 ///< declared: its own, else the nearest base's
  std::string mass_type;                         ///< the type that declares it
  std::shared_ptr<const DeviceTemplate> device;  ///< its parts, else the nearest base's
  bool has_color = false;                        ///< its own `color:` (a colour is not inherited), checked per object
  std::string color;
  SourceMark color_mark;
};

}  // namespace sscs
