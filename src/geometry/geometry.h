#pragma once
/// The geometry stage: every object's shapes evaluated at its attribute values, placed in the
/// world through the `parent` chain, with world-frame bounding boxes and named frames.
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "compile/workcell.h"
#include "core/diagnostics.h"
#include "core/pose.h"
#include "model/shape.h"

namespace sscs {

/// Whether a triangle soup is watertight (see TriangleMesh::closed).
bool is_closed(const std::vector<Eigen::Vector3d>& vertices, const std::vector<Eigen::Vector3i>& triangles);

struct Device;

struct ObjectGeometry {
  Eigen::Isometry3d X_world_object = Eigen::Isometry3d::Identity();
  std::vector<Shape> shapes;
  Eigen::AlignedBox3d bbox_world;  ///< empty when the object has no shapes
  /// Named frames of the type (and its base types) in the world, in declaration order.
  /// A device's parts and its `tool` are frames too, at the instance's joint values.
  std::vector<std::pair<std::string, Eigen::Isometry3d>> frames_world;
  /// The frame of its parent it stands `at`, in the parent's frame (identity: the parent's
  /// origin): its location and orientation are in this frame.
  Eigen::Isometry3d X_parent_at = Eigen::Isometry3d::Identity();
  /// The kinematic model, for devices, and its parts' poses at the instance's joint values.
  std::shared_ptr<const Device> device;
  std::vector<Eigen::Isometry3d> X_object_part;
  /// What is drawn, when it differs from `shapes` (built with GeometryOptions::visuals): each
  /// device part's visual shapes, or its collision shapes where it has none. Empty: draw `shapes`.
  std::vector<Shape> visual_shapes;
  /// The mass its type declares (`mass:` in the type file, or a base type's) at the instance's
  /// attributes, kg; NaN when none declares one.
  double declared_mass = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Shape>& drawn_shapes() const { return visual_shapes.empty() ? shapes : visual_shapes; }
  /// The world pose of frame `name`; nullptr when the type has no such frame.
  const Eigen::Isometry3d* frame(std::string_view name) const;
  /// The world pose of a target frame: `origin`, a named frame, or `top` (the type's `top`
  /// frame, else the middle of the top of the world bounds in the object's orientation).
  /// Unknown names give the origin (compile checks them).
  Eigen::Isometry3d frame_pose(std::string_view name) const;
};

class ContactMemo;

/// Geometry of a whole workcell, indexed like Workcell::objects. Immutable once built.
struct GeometryModel {
  std::vector<ObjectGeometry> objects;
  /// Where the collision queries of this geometry remember costly answers (closed meshes in
  /// contact), to answer them again across variants; null: nothing is remembered. Not part of
  /// the model's value: a hit returns what the query computes.
  std::shared_ptr<ContactMemo> contacts;
};

/// Where everything is at one moment of a run: each object's world pose and, for devices, each
/// part's pose in the object's frame (frames and replays are drawn from these).
struct ScenePose {
  std::vector<Eigen::Isometry3d> X_world_object;
  std::vector<std::vector<Eigen::Isometry3d>> X_object_part;
  /// Per object (or empty: none), whether it is not there now: a campaign's load before it
  /// arrives. Frames do not draw it.
  std::vector<char> hidden;
  bool hides(int object) const { return static_cast<size_t>(object) < hidden.size() && hidden[object]; }
  /// The geometry's own placement.
  static ScenePose of(const GeometryModel& geometry);
};

/// Where collision queries and drawings keep an object that is not there (a campaign's load
/// before it arrives): far below everything, apart from every other.
Eigen::Isometry3d absent_pose(int object);

/// Moves an object's geometry to a new world pose and, for a device given `X_object_part`, its
/// parts to new poses (its joint values now): shapes, bounds and frames follow. For simulations
/// that re-check constraints during a motion; the object's children stay where they were.
void repose(ObjectGeometry& g, const Eigen::Isometry3d& X_world_object,
            const std::vector<Eigen::Isometry3d>* X_object_part = nullptr);

/// Per object, whether it is a container (its type says `container: true`: a room, a shipping
/// container): a space, not a solid, for the physics and for reach. Being some object's parent
/// does not make one (a drum on a pallet, an arm on a pedestal: both solid).
std::vector<char> containers(const Workcell& wc);

/// The floor the physics and reach stand things on: the bottom of the lowest container, else z = 0.
double floor_z(const Workcell& wc, const GeometryModel& geometry);

/// The floor under `object`: the bottom of the nearest container it stands in (its room: a
/// mezzanine room's floor is its own), else floor_z().
double floor_under(const Workcell& wc, const GeometryModel& geometry, int object);

/// A block of floor the physics adds above its plane at floor_z(): a box placed in the world
/// (in the frame of the container whose floor it is, so a room turned about z has its floor
/// turned with it).
struct FloorBlock {
  int container = -1;                  ///< whose floor it is
  Eigen::Isometry3d X_world_centre;    ///< the box's centre and axes
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  ///< full extents
};

/// The floors above the plane: for each container whose bottom lies above it, its footprint at
/// its bottom less the footprints (in its frame) of the other containers that open below it
/// (a pit, whichever its parent). Ground reaches down to the plane under a container that has
/// no container around it or lies no higher than the one around it (a hall beside its pit: a
/// drum that toppled in the pit rolled out under the hall); a container above the one around it
/// (a mezzanine) stands on a slab kFloorSlabThickness deep. A pit turned against its room by
/// other than a multiple of 90 degrees opens the box around it, in the room's frame.
std::vector<FloorBlock> floor_blocks(const Workcell& wc, const GeometryModel& geometry);
/// Whether container h opens into the floor of container c: it is not c or around c, its
/// bottom lies lower than c's, its top reaches c's floor, and their footprints (world bounds)
/// overlap: a pit in a hall, whichever its parent.
bool opens_into(const Workcell& wc, const GeometryModel& geometry, int c, int h);
/// How deep the floor of a container above the one around it (a mezzanine) is.
constexpr double kFloorSlabThickness = 0.2;  // m


/// World-frame axis-aligned bounds of one shape placed at X_world_shape.
Eigen::AlignedBox3d shape_bounds(const Shape& shape, const Eigen::Isometry3d& X_world_shape);

/// Builds the geometry of every object. Mesh files that cannot be read, and values that are not
/// finite or not positive, are input errors at the line that names them. `meshes`, when given,
/// keeps the meshes read for later builds (a sweep reads each mesh file once).
class MeshCache;
struct GeometryOptions {
  /// Also build what devices look like (URDF <visual> shapes, read with their meshes): for
  /// render, frames and export. Checks and sweeps leave it off and read no visual mesh.
  bool visuals = false;
  /// Remember costly collision answers here (GeometryModel::contacts): a sweep's worker passes
  /// one memo to every variant it builds, so shapes a variant did not move are not measured again.
  std::shared_ptr<ContactMemo> contacts;
};
GeometryModel build_geometry(const Workcell& wc, Diagnostics& diag, MeshCache* meshes = nullptr, const GeometryOptions& options = {});

/// A bounding-box operand's value (SI) from Operand::slot = corner * 3 + axis (corner 0 min,
/// 1 max, 2 size); NaN when the object has no geometry.
double bbox_value(const GeometryModel& geometry, int object, uint32_t corner_axis);

}  // namespace sscs
