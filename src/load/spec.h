#pragma once
/// What the user wrote: vault and type files as plain structs, every node with its source mark.
/// The load stage fills these; the compile stage turns them into a Workcell. Values stay text here
/// (numbers, unit literals and expressions alike) because their meaning depends on the type.
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/diagnostics.h"
#include "core/joint_type.h"
#include "core/source.h"
#include "core/written.h"

namespace sscs {


/// `xyz`/`rpy` placement; absent components are zero.
struct PoseSpec {
  std::array<Scalar, 3> xyz;
  std::array<Scalar, 3> rpy;
};

// ---- type files ----

struct AttributeDecl {
  std::string name;
  SourceMark mark;
  AttrType type = AttrType::Number;
  Scalar default_value;
  Scalar min;
  Scalar max;
  std::vector<std::string> values;  ///< enum values
  std::string description;
};

struct BoxSpec {
  std::array<Scalar, 3> size;
};
struct CylinderSpec {
  Scalar radius;
  Scalar length;
};
struct SphereSpec {
  Scalar radius;
};
struct MeshSpec {
  Scalar file;  ///< path relative to the file that names it
  std::array<Scalar, 3> scale;
};
/// `repeat: {level: levels, bay: {count: bays, pitch: [bay_width, 0, 0]}}` of a geometry entry
/// or frame: a copy for each combination of its counters (the first outermost). Each counter runs
/// from 1 to its count, is a name the entry's values may use, and moves copy k by (k - 1) pitches.
struct RepeatSpec {
  struct Counter {
    std::string name;
    SourceMark mark;
    Scalar count;
    std::array<Scalar, 3> pitch;  ///< absent: no offset
  };
  std::vector<Counter> counters;
  SourceMark mark;
};

struct GeometrySpec {
  std::variant<BoxSpec, CylinderSpec, SphereSpec, MeshSpec> shape;
  PoseSpec pose;
  std::optional<RepeatSpec> repeat;
  SourceMark mark;
  std::string color;  ///< "#rrggbb" of this shape alone (a URDF <visual>'s material), "" for none
};

struct FrameSpec {
  std::string name;  ///< with `{counter}` in it when repeated (`slot_{level}_{bay}`)
  SourceMark mark;
  PoseSpec pose;
  std::optional<RepeatSpec> repeat;
};


struct JointSpec {
  std::string name;
  SourceMark mark;
  JointType type = JointType::Fixed;
  std::array<Scalar, 3> axis;
  PoseSpec origin;
  Scalar min, max, velocity, acceleration, effort;
  bool soft_limited = false;  ///< a URDF's <safety_controller> narrowed min/max
};

/// A part's centre of mass and inertia (kg m^2) about it: imported from URDF.
struct InertialSpec {
  PoseSpec origin;
  std::array<Scalar, 6> inertia;  ///< ixx ixy ixz iyy iyz izz
};

struct PartSpec {
  std::string name;
  SourceMark mark;
  std::string parent;
  SourceMark parent_mark;
  std::optional<JointSpec> joint;
  std::vector<GeometrySpec> geometry;
  /// What the part looks like where that differs from `geometry` (a URDF link's <visual>
  /// shapes, with their materials): drawn by render, frames and export; checks use `geometry`.
  std::vector<GeometrySpec> visual;
  Scalar mass;
  Scalar color;
  std::optional<InertialSpec> inertial;
};

struct DeviceSpec {
  std::vector<PartSpec> parts;
  std::string tool_part;
  SourceMark tool_mark;
  PoseSpec tool_pose;
  std::vector<std::pair<std::string, Scalar>> home;  ///< joint name -> value
  SourceMark home_mark;
  bool kinematic = false;  ///< `driven: kinematic`
  Scalar urdf;             ///< as written; its contents fill `parts`
  /// `joint_limits: soft` (default): a URDF joint's <safety_controller> soft limits, within its
  /// <limit>, bound it, as MoveIt and TRAC-IK take them; `hard`: its <limit> alone.
  bool hard_limits = false;
  /// Pairs of parts that may touch in any pose (the vendor's model overlaps them): never a
  /// self-collision. From `allowed_collisions: [[a, b], ...]` and the SRDF's <disable_collisions>.
  struct AllowedCollision {
    std::string a, b;
    SourceMark mark;  ///< the pair in the type file, or the element in the SRDF file
  };
  std::vector<AllowedCollision> allowed_collisions;
  Scalar srdf;  ///< as written: a MoveIt SRDF beside the URDF (its disabled collision pairs)
  /// Each mesh reference of the URDF as written (`package://acme/meshes/a.dae`) and the file it
  /// names: resolved/ rewrites the references a copy of the URDF cannot keep.
  std::vector<std::pair<std::string, std::string>> urdf_mesh_refs;
  std::string urdf_robot;  ///< the URDF's <robot name>, which its SRDF should repeat
  /// What went wrong in the URDF and SRDF imports (errors), and what they skipped (warnings:
  /// degenerate shapes): reported where the type is used.
  std::vector<Diagnostic> import_problems;
};

/// `requires:` a rule every instance of the type keeps: a condition over its attributes and what
/// it means when it does not hold ("the openings run past the wall's end").
struct RuleSpec {
  Scalar condition;
  std::string message;
  SourceMark mark;
};

struct TypeSpec {
  std::string name;
  SourceMark mark;
  std::string path;  ///< the file, for resolving mesh paths
  std::string plugin;  ///< the shared object that declared it (a plugin type), else ""
  std::string extends;
  SourceMark extends_mark;
  std::string description;
  std::vector<AttributeDecl> attributes;
  std::vector<FrameSpec> frames;
  std::vector<GeometrySpec> geometry;
  std::vector<RuleSpec> rules;
  bool has_geometry = false;
  Scalar color;
  /// The mass of an instance (kg) for the physics: a number or an expression over the type's
  /// attributes (`tare_mass + fill_mass`). Absent: a `mass` attribute, else an estimate from the
  /// bounds. Devices weigh their parts.
  Scalar mass;
  /// `container: true`: the type is a space that holds objects (a room, a shipping container):
  /// its geometry is its outline, and the physics and `reach` treat its inside as empty.
  /// Inherited by the types that extend it.
  bool container = false;
  /// `zone: true`: the type is a keep-out volume (a guard zone): checks and reach treat it as a
  /// solid, the physics as nothing but a device (or what it carries) entering it is an event.
  bool zone = false;
  std::optional<DeviceSpec> device;
};

/// Every mesh file a type file names, as written: its geometry's, then each device part's
/// geometry and visuals (frames of a rerun draw those too).
std::vector<const MeshSpec*> named_meshes(const TypeSpec& spec);

// ---- vault files ----

struct ParameterSpec {
  std::string name;
  SourceMark mark;
  Scalar value;
  std::optional<AttrType> type;
  Scalar min;
  Scalar max;
};

struct ArraySpec {
  Scalar name_pattern;
  std::vector<Scalar> count;
  std::array<Scalar, 3> pitch;
  SourceMark mark;
  /// Positions left out: 1-based index tuples, or name globs.
  struct Skip {
    SourceMark mark;
    std::vector<Scalar> index;  ///< a tuple [i, j, k] (as many as counts)
    Scalar glob;                ///< or a glob over the generated names
  };
  std::vector<Skip> skip;
};

struct AttrValue {
  std::string name;
  SourceMark key_mark;
  Scalar value;
};

/// The keys of an object in a vault that are not attributes: no attribute or joint may be named so
/// (an object could not set it).
inline constexpr std::array<const char*, 9> kObjectKeys = {"type", "name", "array", "location", "orientation", "parent",
                                                           "at", "geomodel", "color"};
inline bool is_object_key(std::string_view name) {
  for (const char* k : kObjectKeys)
    if (name == k) return true;
  return false;
}

struct ObjectSpec {
  SourceMark mark;
  std::string type;
  SourceMark type_mark;
  Scalar name;
  Scalar parent;
  /// `at: Rack_1.slot_2_1_3`: the object stands at a named frame of another, its parent; its
  /// location and orientation are then in that frame. Array placeholders {i} {j} {k} allowed.
  Scalar at;
  std::array<Scalar, 3> location;
  std::array<Scalar, 3> orientation;
  Scalar geomodel;
  Scalar color;
  std::vector<AttrValue> attributes;
  std::optional<ArraySpec> array;
};

/// A selector as written: names, globs, `*`, `type:T`, or a list of these.
struct SelectorSpec {
  std::vector<Scalar> items;
  SourceMark mark;
  bool allow_empty = false;
};

struct BoundSpec {
  Scalar lhs, rhs, lhs_tol, rhs_tol, eps;
  RelOp op = RelOp::LT;
  SourceMark op_mark;
};
struct ExprSpec {
  Scalar expr;
  bool allow_empty = false;  ///< aggregates (count, sum, ...) may select nothing
};
struct PluginSpec {
  Scalar cls;
  std::vector<Scalar> attributes;
  nlohmann::ordered_json args;
};
struct ClearanceSpec {
  std::optional<SelectorSpec> a, b;  ///< a pair: each side a name or a selector
  std::optional<SelectorSpec> objects;
  Scalar min, eps;
};
struct NoOverlapSpec {
  SelectorSpec objects;
  Scalar eps;
};
struct InsideSpec {
  SelectorSpec objects;
  Scalar container;
  Scalar min, eps;
  std::vector<Scalar> faces;  ///< `all` (default), `walls`, or a list of x- x+ y- y+ z- z+
};
struct ReachSpec {
  Scalar device;
  SelectorSpec targets;  ///< items may name a frame: `Drum_3.top`, `Drum_*.top`
  std::vector<std::pair<PoseSpec, SourceMark>> poses;  ///< targets given as world poses
  Scalar frame;
  bool match_orientation = false;
  PoseSpec offset;
  Scalar position_tol, angle_tol;
  Scalar carrying;  ///< an object held at the tool
};

/// A value kept on the heap, so that rare, large alternatives do not make every variant large
/// (a vault may hold 200,000 bounds and a handful of reach constraints).
template <class T>
class Boxed {
 public:
  Boxed(T value) : ptr_(std::make_unique<T>(std::move(value))) {}  // NOLINT: implicit on purpose
  T& operator*() const { return *ptr_; }
  T* operator->() const { return ptr_.get(); }

 private:
  std::unique_ptr<T> ptr_;
};

using ConstraintKind = std::variant<BoundSpec, ExprSpec, Boxed<PluginSpec>, Boxed<ClearanceSpec>, Boxed<NoOverlapSpec>,
                                    Boxed<InsideSpec>, Boxed<ReachSpec>>;
/// The constraint kinds as type files write them, in ConstraintKind's order: the one list.
inline constexpr std::array<const char*, 7> kConstraintKindNames = {"bound", "expr", "plugin", "clearance", "no_overlap", "inside", "reach"};
static_assert(kConstraintKindNames.size() == std::variant_size_v<ConstraintKind>);
const char* constraint_kind_name(const ConstraintKind& kind);

struct ConstraintSpec {
  std::string name;
  SourceMark mark;
  std::string description;
  Severity severity = Severity::Error;
  ConstraintKind kind;
};

/// A camera: a keyframe of a scenario's `cameras:` (with `t`), or a named camera of a vault.
struct CameraKeySpec {
  SourceMark mark;
  Scalar t;
  std::array<Scalar, 3> eye, target;  ///< world points (absent with `orbit`)
  Scalar fov;
  bool orbit = false;
  Scalar orbit_target;                ///< an object name, or absent with orbit_point
  std::array<Scalar, 3> orbit_point;
  Scalar radius, azimuth, elevation;
};

struct VaultSpec {
  std::string name;
  SourceMark mark;
  std::string path;
  std::string description;
  std::vector<Scalar> library;  ///< extra type folders, relative to the vault file
  /// false in the vaults a run writes into resolved/: they carry every type they use.
  bool standard_library = true;
  std::vector<Scalar> plugins;
  std::vector<ParameterSpec> parameters;
  std::vector<ObjectSpec> objects;
  std::vector<ConstraintSpec> constraints;
  std::vector<std::pair<std::string, CameraKeySpec>> cameras;  ///< named views for `sscs render --camera`
};

}  // namespace sscs
