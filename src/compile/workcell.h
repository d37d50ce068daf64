#pragma once
/// The compiled model: an immutable Workcell of typed objects and constraints, all values in SI.
/// Later stages (check, geometry, kinematics, simulation) read only this, never the spec.
#include <array>
#include <functional>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <sscs/plugin.h>

#include "compile/cameras.h"
#include "compile/templates.h"
#include "core/expr.h"
#include "core/diagnostics.h"
#include "core/source.h"
#include "core/units.h"
#include "core/written.h"
#include "core/plugin_outcome.h"

namespace sscs {

/// One attribute of a type, with limits converted to SI.
struct AttributeDef {
  std::string name;
  AttrType type = AttrType::Number;
  Dim dim = Dim::None;
  std::optional<double> min_si, max_si;
  /// A joint's limits written as expressions over the type's other attributes (a crane's travel
  /// up to `runway_length - 2`): its bounds for each object, where min_si/max_si are unset.
  ValueRef min_expr, max_expr;
  /// Its bounds for an object whose attribute values (SI) start at `attributes_si`.
  double lower(const double* attributes_si) const {
    return min_si ? *min_si : min_expr.present ? min_expr.eval(attributes_si, NAN) : -INFINITY;
  }
  double upper(const double* attributes_si) const {
    return max_si ? *max_si : max_expr.present ? max_expr.eval(attributes_si, NAN) : INFINITY;
  }
  std::vector<std::string> values;  ///< enum values
  std::string description;
  Scalar default_value;             ///< as written in the type file (may be an expression)
  SourceMark mark;
  bool joint = false;               ///< a device joint's value
  /// A joint's home value (SI): the type's `home:` entry, else 0 (or the nearest limit).
  /// `move_joints: home` moves there.
  double home_si = 0;
};

/// A resolved type: its own and inherited attributes (ancestors' first).
struct ObjectType {
  std::string name;
  int base = -1;  ///< index of the type it extends, -1 for `object`
  std::string extends;  ///< as written ("" for `object`), also when it names no type
  std::string description;
  bool device = false;
  /// A space that holds objects (its type file, or one it extends, says `container: true`).
  bool container = false;
  /// A keep-out volume (`zone: true`, or a type it extends): a solid to checks and reach, no body
  /// to the physics, where a device's part or its load entering it is a `keep_out` event.
  bool zone = false;
  std::vector<AttributeDef> attributes;
  std::string path;    ///< its type file
  std::string plugin;  ///< the shared object that declared it (a plugin type), else ""
  /// Its geometry, frames, mass and device parts, compiled (inheritance flattened).
  TypeTemplates templates;
  /// The meshes its own file names, as written (its geometry's, then its parts' geometry and
  /// visuals): a run's resolved/ copies them. Its base's name theirs.
  std::vector<std::string> own_meshes;
  bool own_device = false;  ///< its own file describes the device (else a base's does, or none)
  /// Errors in the type file and the files it names (a typo in an expression, a mesh that cannot
  /// be read), and warnings of what its import skipped (a degenerate URDF shape): reported when a
  /// vault uses the type (or one extending it), so one broken type does not break its folder.
  std::vector<Diagnostic> problems;
  /// Its type file (or a type it extends) has errors: it is listed, but no object is built of it.
  bool broken = false;
  /// Its templates (and own_meshes, and their problems) are compiled: a vault's compile does so
  /// only for the types its objects use and those they extend (load_library's `wanted`).
  bool shaped = false;
  int find_attribute(std::string_view name) const;
};

/// The numeric slots of an object in Workcell::values: location xyz, orientation rpy, attributes.
constexpr int kLocationSlot = 0;
constexpr int kOrientationSlot = 3;
constexpr int kFirstAttributeSlot = 6;
/// The names expressions and messages give the first slots: location.x .. orientation.yaw.
inline constexpr std::array<const char*, kFirstAttributeSlot> kPoseSlotNames = {
    "location.x", "location.y", "location.z", "orientation.roll", "orientation.pitch", "orientation.yaw"};

struct Object {
  std::string name;
  int type = -1;
  int parent = -1;
  uint32_t first_slot = 0;  ///< index of location.x in Workcell::values
  SourceMark mark;
  std::string geomodel;  ///< mesh file replacing the type's geometry, resolved path
  std::string color;
  /// `at:` the named frame of its parent it stands at ("" for the parent's origin); its location
  /// and orientation are in that frame.
  std::string at;
};

/// What a constraint operand reads.
struct Operand {
  /// Aggregate: count, sum, min, max or avg (SelectionCall::Kind) of `members`, one per selected object.
  enum class Kind : uint8_t { Constant, Slot, BoundingBox, Aggregate } kind = Kind::Constant;
  uint8_t aggregate = 0;
  std::shared_ptr<const std::vector<Operand>> members;
  double constant_si = 0;
  uint32_t slot = 0;          ///< for Slot
  int object = -1;            ///< the object it belongs to (-1 for constants and parameters)
  Dim dim = Dim::None;
  std::string text;           ///< as written, for reports
};

struct BoundCheck {
  Operand lhs, rhs;
  double lhs_tol_si = 0, rhs_tol_si = 0, eps_si = 1e-9;
  RelOp op = RelOp::LT;
  Dim dim = Dim::None;
};

struct ExprCheck {
  std::string text;  ///< as written (aggregate calls and all), for reports
  std::shared_ptr<const Expression> expr;
  std::vector<Operand> inputs;  ///< one per expr->names()
  struct Side {
    std::shared_ptr<const Expression> expr;
    std::vector<Operand> inputs;
  };
  /// For a margin: comparisons with their two sides compiled, combined by && (min) and || (max).
  struct MarginNode {
    MarginTree::Op op;
    Side lhs, rhs;
    std::vector<MarginNode> children;
    /// The dimension of the compared sides (of every child's, when they share one): the margin
    /// is reported in its file unit; Dim::None for pure numbers and mixed children.
    Dim dim = Dim::None;
  };
  std::optional<MarginNode> margin;
};

/// plugin: a constraint class of a loaded plugin over the participating attributes.
struct PluginCheck {
  std::string class_name;
  /// The class's check, bound when compiled (it keeps the shared object loaded): for the
  /// constraint's name and its inputs' values in file units, with their names and units.
  std::function<PluginOutcome(const std::string& constraint, const std::vector<sscs_value>& values)> evaluate;
  std::vector<Operand> inputs;
  std::string args_json;
};

/// clearance, no_overlap and inside: evaluated on the geometry with FCL.
struct SpatialCheck {
  enum class Kind : uint8_t { ClearancePair, ClearanceSet, NoOverlap, Inside } kind = Kind::NoOverlap;
  /// Faces of an `inside` container's box (in its frame) whose distance counts.
  enum Face : uint8_t { XMin = 1, XMax = 2, YMin = 4, YMax = 8, ZMin = 16, ZMax = 32, Walls = 15, All = 63 };
  std::vector<int> objects;  ///< the selected set, or side a of a pair
  std::vector<int> others;   ///< clearance pair: side b (every pair across a and b)
  int container = -1;        ///< inside
  double min_si = 0;         ///< clearance; inside: the gap required to the faces
  double eps_si = 1e-9;      ///< comparisons at the limit hold within eps (m)
  uint8_t faces = All;       ///< inside
};

/// reach: the device's tool at every target, within limits and without collision.
struct ReachCheck {
  struct Target {
    int object = -1;       ///< -1 for a pose in the world
    std::string frame;     ///< "origin", "top" or a named frame of the object
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< the world pose when object < 0
    std::string text;      ///< as written or generated ("Drum_3.top"), for reports
  };
  int device = -1;
  std::vector<Target> targets;
  bool match_orientation = false;
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();  ///< composed with the target frame
  double position_tol_si = 1e-3;
  double angle_tol_si = 0.5 * std::numbers::pi / 180;
  /// `carrying`: the object the tool holds (-1: none), with its origin at each target and the
  /// tool at the target composed with the offset, and what moves with it (its descendants in the
  /// parent chain: drums on a carried pallet).
  int carrying = -1;
  std::vector<int> carried_with;
};

struct Constraint {
  std::string name;
  std::string description;
  SourceMark mark;
  Severity severity = Severity::Error;
  std::string kind;  ///< bound, expr, clearance, ...
  std::vector<int> subjects;  ///< objects it reads
  std::variant<BoundCheck, ExprCheck, SpatialCheck, ReachCheck, PluginCheck> body;
};

struct Parameter {
  std::string name;
  uint32_t slot = 0;
  Dim dim = Dim::None;
  AttrType type = AttrType::Number;
};

/// The compiled vault. Built by compile(); read-only afterwards.
struct Workcell {
  std::string name;
  std::string path;
  std::string description;
  std::vector<ObjectType> types;
  std::vector<Parameter> parameters;
  std::vector<Object> objects;
  std::vector<Constraint> constraints;
  std::vector<std::pair<std::string, CameraKey>> cameras;  ///< the vault's named views, compiled
  std::vector<std::string> plugin_files;      ///< the plugins' shared objects loaded to compile it
  std::vector<std::string> vault_plugin_dirs;  ///< the vault's `plugins:` folders, absolute
  std::vector<double> values;       ///< every numeric slot, SI
  std::vector<std::string> texts;   ///< string/enum slots (indexed like values)

  std::vector<int> by_name;         ///< object indices sorted by name, for find_object

  /// Index of the object named `name`, or -1. O(log n).
  int find_object(std::string_view name) const;
  /// The frames object `object` offers as a target: `origin`, `top`, then sorted, its type's
  /// named frames (its bases' too; each copy of a repeated one) and, for devices, their parts and `tool`.
  std::vector<std::string> frame_names(int object) const;
  /// The pose of object `object`'s named frame `name` (its type's `frames:`, a copy of a repeated
  /// one) in the object's own frame; nullopt when it has none so named.
  std::optional<Eigen::Isometry3d> named_frame(int object, std::string_view name) const;
  /// Index of the type named `name`, or -1.
  int find_type(std::string_view name) const;
  /// The objects a selector item names, in index order: `*`, `type:T` (T and the types extending
  /// it), a glob (`Rack_*`), an object's name, `at:OBJECT.FRAME` (globs both: the objects placed
  /// `at:` one of those frames, or whose origin is within 1 mm of one) or a list `[A, B, !C]` of these (`!` removes what its item
  /// selects). nullopt when it names a type or an object that does not exist (a glob that
  /// matches nothing selects nothing).
  std::optional<std::vector<int>> select(std::string_view item) const;
  /// Object `object`'s frame in its parent's: its location and orientation, in the frame it is
  /// placed `at` when it is.
  Eigen::Isometry3d local_pose(int object) const;
  /// Object `object`'s frame in the world, from its location and orientation and its parents';
  /// `known` (one entry per object) keeps the poses already composed.
  Eigen::Isometry3d pose_in_world(int object, std::vector<std::optional<Eigen::Isometry3d>>& known) const;
  /// Whether type `t` is `ancestor` or derives from it.
  /// Type `t`, then the type it extends, and so on up to `object` (the one walk of the
  /// inheritance chain; reverse it for the root first).
  std::vector<int> lineage(int t) const;
  bool is_a(int t, int ancestor) const;
  /// Whether object `a` is `b` or one of its ancestors or descendants in the parent chain.
  bool related(int a, int b) const;
  /// Whether `no_overlap` and set-wise `clearance` leave the pair alone: one is a container (its
  /// type says `container: true`) and the other descends from it, through `parent` or `at` (a rack
  /// in its room). Any other ancestor is a solid its descendants rest on and is compared with
  /// them (a pallet on a rack, a drum run through by the beam above it).
  bool nested(int a, int b) const;
};

/// The items of a selector list `[A, B, !C]` (trimmed; `!` kept), or the selector itself.
std::vector<std::string_view> split_selector_list(std::string_view list);

}  // namespace sscs
