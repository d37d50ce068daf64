#pragma once
/// Distances, overlaps and containment between objects' geometry, through FCL.
#include <array>
#include <cstdint>
#include <memory>
#include <functional>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "geometry/geometry.h"

namespace sscs {

/// Geometries closer than this count as touching, not overlapping (m).
constexpr double kTouchTolerance = 1e-6;
/// How deep a tool may meet its target (a run's move_to, a reach target) without a collision.
constexpr double kTargetTouch = 0.001;  // m

/// Collision::other of a part that goes into the floor.
constexpr int kFloorObject = -2;

/// An interpenetration found for a device: with another object, or between two of its parts.
struct Collision {
  int other = -1;       ///< the other object, -1 for a self-collision, kFloorObject for the floor
  int part = -1;        ///< the device's part
  int other_part = -1;  ///< the other part (self-collision, or a part of another device)
  double depth = 0;     ///< penetration depth, m
  int load = -1;        ///< a load the device holds that collides (part is then -1; other may be the device)
};

/// What a device's tool holds, as a grasp holds it: the load and what rides on it, each at a
/// fixed pose in the tool's frame. Collision checks of the device then check these shapes too.
struct HeldLoad {
  std::vector<std::pair<int, Eigen::Isometry3d>> objects;  ///< object, X_tool_object
  bool empty() const { return objects.empty(); }
};

/// How close one object came to another: the nearest pair of their shapes.
struct Proximity {
  int other = -1;
  int part = -1;        ///< the moving object's part (devices), else -1
  int other_part = -1;  ///< the other object's part (devices), else -1
  double distance = 0;  ///< m; minus the penetration depth when they interpenetrate
  int shape = -1, other_shape = -1;  ///< the nearest shapes (indices into each object's shapes)
};

/// Answers of the costly pair queries (a closed mesh in contact or containing: the exact depth
/// search), remembered by everything that decides them, bit for bit: both shapes (kind, sizes,
/// scale, mesh), both placements, the query and the depth its caller needs. A hit returns what
/// the query would compute, so results do not depend on what was asked before. Holds its meshes
/// (their addresses are part of a key). Full, it starts again empty.
class ContactMemo {
 public:
  static constexpr size_t kCapacity = 20000;  ///< entries, about 8 MB
  using Key = std::array<uint64_t, 46>;
  struct KeyHash {
    size_t operator()(const Key& k) const;
  };
  std::optional<double> find(const Key& key);
  void store(const Key& key, double answer, const std::shared_ptr<const TriangleMesh>& a, const std::shared_ptr<const TriangleMesh>& b);
  size_t hits() const { return hits_; }
  size_t size() const { return answers_.size(); }

 private:
  std::unordered_map<Key, double, KeyHash> answers_;
  std::unordered_map<const TriangleMesh*, std::shared_ptr<const TriangleMesh>> meshes_;
  size_t hits_ = 0;
};

/// FCL collision objects for the shapes of a GeometryModel, built on first use per object.
/// Objects start where the model places them; a simulation moves them (`move`, `move_parts`)
/// and asks how close they come (`proximity`). Not copyable; one per check or run.
class CollisionWorld {
 public:
  explicit CollisionWorld(const GeometryModel& geometry);
  ~CollisionWorld();
  CollisionWorld(const CollisionWorld&) = delete;
  CollisionWorld& operator=(const CollisionWorld&) = delete;

  /// Signed distance between two objects' geometry: the smallest distance between any of their
  /// shapes, or minus the largest penetration depth when they interpenetrate. nullopt when one
  /// of them has no geometry. `nearest_parts`, when given, receives the device parts (-1 for
  /// other objects) of the two shapes that are nearest.
  std::optional<double> distance(int a, int b, std::pair<int, int>* nearest_parts = nullptr);
  /// How deep the point `p_world` lies inside object `object`'s solids (primitives and closed
  /// meshes, at their current placements): 0 when it is on or outside every one of them (an open
  /// mesh is a surface and holds nothing).
  double depth_inside(int object, const Eigen::Vector3d& p_world);

  /// How far the point `p_world` is from object `object`'s solids at their current placements:
  /// 0 when on or inside one (a closed mesh holds its inside). nullopt when it has no geometry.
  std::optional<double> distance_to_point(int object, const Eigen::Vector3d& p_world);
  /// Where object `object` (not a device) is placed now: its vault pose until it is moved.
  Eigen::Isometry3d placed_pose(int object);

  /// Pairs of parts of device `object` that may not touch (Device::may_touch) and interpenetrate
  /// at its instance's joint values (self-collision).
  std::vector<Collision> self_collisions(int object);

  /// The deepest collision of device `object` with its parts placed at `X_world_part` (one pose
  /// per part): against every other object except `ignore` (the caller's choice: the target,
  /// the objects in the device's parent chain), and
  /// between its own non-adjacent parts. nullopt when it is free.
  /// `target` (>= 0) is the object the tool meets: the parts marked in `tool_parts` (the tool's
  /// part and the parts it carries) may touch it, by up to kTargetTouch; the other parts may not.
  /// `stands_on`: objects the device's unmoved parts (its root and what is fixed to it) may touch
  /// (the pedestal it stands on); the parts a joint moves may not. `first`: a collision's depth
  /// need not be exact (a search rejecting a candidate): a closed mesh's depth search stops at
  /// the limit that makes it a collision, so its depth may be a lower bound.
  /// `only` (when not empty): the parts considered, the others left out.
  std::optional<Collision> device_collision(int object, const std::vector<Eigen::Isometry3d>& X_world_part,
                                            const std::vector<int>& ignore, int target = -1,
                                            const std::vector<char>& tool_parts = {}, const std::vector<int>& stands_on = {},
                                            bool first = false, const std::vector<char>& only = {});

  /// The deepest a device's parts marked in `parts`, placed at `X_world_part`, go into the floors
  /// the physics has: below the plane at `plane` (their lowest point), or into a block of
  /// `blocks` (floor_blocks; the part's exact shape over the block's footprint, clipped: a link
  /// reaching over a pit's edge into the pit does not touch the floor its bounds overlap).
  /// Deeper than kTouchTolerance only; Collision::other is kFloorObject and other_part the
  /// container whose floor it is (-1: the plane).
  std::optional<Collision> into_floors(int object, const std::vector<Eigen::Isometry3d>& X_world_part,
                                       const std::vector<char>& parts, double plane, const std::vector<FloorBlock>& blocks);

  /// The deepest collision of the objects in `held` (object, world pose: a load a device's tool
  /// holds and its riders) with everything but `ignore`, each other and device `device`'s tool
  /// parts (`tool_parts`): with the device's other parts placed at `X_world_part`, other objects
  /// where they are now (`target` may be touched by kTargetTouch), and the floors (`plane`,
  /// `blocks`, as into_floors). `first`: see device_collision.
  std::optional<Collision> held_collision(int device, const std::vector<Eigen::Isometry3d>& X_world_part,
                                          const std::vector<std::pair<int, Eigen::Isometry3d>>& held, const std::vector<int>& ignore,
                                          int target, const std::vector<char>& tool_parts, bool first, double plane,
                                          const std::vector<FloorBlock>& blocks);

  /// Places `object` at a new world pose (a carried or fallen object).
  void move(int object, const Eigen::Isometry3d& X_world_object);
  /// Places a device's parts at new world poses (one per part: its current joint values).
  void move_parts(int object, const std::vector<Eigen::Isometry3d>& X_world_part);

  /// For every object other than `object` and those in `skip`, whose bounds come within `reach`
  /// of its bounds: the distance between their nearest shapes, at their current placements.
  /// `below(other)`, when given, narrows the reach per object: a caller tracking the closest
  /// approach of each pair needs only distances below the closest seen so far. `parts`, when
  /// given, limits a device to the parts marked (e.g. those that move).
  std::vector<Proximity> proximity(int object, const std::vector<int>& skip, double reach,
                                   const std::function<double(int other)>& below = {},
                                   const std::vector<char>& parts = {});

  /// The distance of `object` (its `parts` only, when given) to `other` at their current
  /// placements, with the nearest parts: proximity() for one pair, whatever their bounds' gap.
  /// With `below`: only shapes whose boxes are nearer than it are measured (none: nullopt or a
  /// distance of at least `below`).
  std::optional<Proximity> pair_distance(int object, int other, const std::vector<char>& parts = {}, double below = INFINITY);

  /// A lower bound of the distance from `object` (its `parts` only, when given) to `other` over
  /// a motion in which the object's parts only translate, each part p by a shift in the convex
  /// hull of `shifts[p]` (one list for an object that is no device) from where it is placed
  /// now, the other standing: along the direction n from their nearest points now, the least
  /// n·y over the other's solids less the most n·x over the object's, shifted (for any unit n
  /// that bounds the distance of any two sets; a lowered drum beside another keeps its gap
  /// whole, where the travel bound takes its whole descent off). nullopt when they are not
  /// apart now or either has no solid.
  std::optional<double> slab_bound(int object, int other, const std::vector<char>& parts,
                                   const std::vector<std::vector<Eigen::Vector3d>>& shifts);

  /// How far any point of `object`'s shapes (those of device part `part`; -1 for an object
  /// that is no device) can have moved when its frame (the part's) went from `from` to `to`: the
  /// frame's displacement plus the turn times the shapes' farthest reach from it. An upper bound
  /// whatever the path between, as long as the frame turned by less than half a turn.
  double travel_bound(int object, int part, const Eigen::Isometry3d& from, const Eigen::Isometry3d& to);
  /// How far any point of those shapes can have come down (towards -z) meanwhile: the frame's
  /// drop plus the turn's share across z (a turn about a vertical axis moves no point up or
  /// down) and the bulge of an arc over its chord, for a turn of a degree or so between the
  /// poses, as the glides' sub-steps are. A truck driving on the floor comes no nearer to it.
  double descent_bound(int object, int part, const Eigen::Isometry3d& from, const Eigen::Isometry3d& to);
  /// Whether every two parts of device `object` that may not touch (not adjacent) are farther
  /// apart than `gap` where it is placed now.
  bool self_clear(int object, double gap);
  /// The height of the lowest point of the boxes of `object`'s shapes (its `parts` only, when
  /// given) where it is placed now: at or below its lowest point.
  double lowest(int object, const std::vector<char>& parts = {});

  /// Pairs (a < b) of `objects` whose world bounding boxes, grown by `margin`, touch: found by a
  /// dynamic AABB tree broadphase, not by testing all pairs. Sorted.
  std::vector<std::pair<int, int>> candidate_pairs(const std::vector<int>& objects, double margin);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// How far `object` lies within `container` (one box, cylinder or closed mesh: a room's box is its
/// inside), less the gap `min`: the smallest distance from the object's geometry to the counted
/// faces of the container (`faces`: SpatialCheck::Face bits; a cylinder's walls are its round side,
/// z- and z+ its ends; a mesh counts as one face, all) minus `min` when inside, and minus the
/// largest protrusion through any face, counted or not, when not. nullopt (with `why`) when the
/// container is not such a shape, the faces do not apply to it, or the object has no geometry.
/// `through` (when given) names the face it sticks out through farthest ("its floor", "its x+
/// face", "its round side"; a box's z- face is its floor), "" for a mesh or when inside.
/// `part` (>= 0) judges only that part's shapes of a device; `uncounted` (when given) is set to
/// the least distance to a face not counted (inf: none), which fails the rule once below zero.
std::optional<double> inside_margin(const GeometryModel& geometry, int object, int container, std::string* why,
                                    uint8_t faces = SpatialCheck::All, double min = 0, std::string* through = nullptr,
                                    int part = -1, double* uncounted = nullptr);

/// How a device's configuration is judged free, the same for `reach` and for the joint values a
/// scenario's move_to plans (a run's physics has it so): containers (rooms) are spaces; what the
/// device stands on (its parent chain: a pedestal) only its unmoved parts may touch; the tool's
/// parts may touch the target object by kTargetTouch; no part a joint moves may go into the
/// floors (the plane under the lowest room, the slabs of the higher ones, pits open).
class DeviceClearance {
 public:
  DeviceClearance(const Workcell& wc, const GeometryModel& geometry, int device);
  /// The deepest collision of the device with its joints at `q` (the device's joint vector) in
  /// `world` as it is placed now, or nullopt. `target`: the object the tool meets (-1: none);
  /// `ignore`: further objects. `load`: what the tool holds, checked with the device (free of
  /// everything but the tool, which holds it). `first`: see device_collision.
  std::optional<Collision> at(CollisionWorld& world, const Eigen::VectorXd& q, int target, bool first,
                              const std::vector<int>& ignore = {}, const HeldLoad& load = {}) const;
  /// The same for the parts marked in `parts` alone (with each other and with other objects; not
  /// the floors, which only moving parts are held to): a search that moves only the other parts
  /// finds these where they are at `q` for every candidate.
  /// `load`: objects the tool holds, elsewhere now (left out).
  std::optional<Collision> of_parts(CollisionWorld& world, const Eigen::VectorXd& q, int target,
                                    const std::vector<char>& parts, const HeldLoad& load = {}) const;

 private:
  const GeometryModel& geometry_;
  int device_;
  std::vector<int> containers_, stands_on_;
  std::vector<char> tool_parts_, moved_;
  double plane_ = 0;
  std::vector<FloorBlock> blocks_;
};

}  // namespace sscs
