#pragma once
/// The solids of the compiled model: triangle meshes as read, and shapes (a primitive or a mesh,
/// in SI, placed in its object's or part's frame). Built by the geometry stage from a type's
/// geometry; read by collision, physics, render and export.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace sscs {

/// A triangle mesh in its file's units, before the shape's scale.
struct TriangleMesh {
  std::string path;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  /// Watertight: every edge (vertices welded by position) is run by as many triangles in one
  /// direction as in the other (two for a single solid). A closed mesh is a solid (what lies
  /// inside it overlaps it); an open one is a surface.
  bool closed = false;
  /// Per triangle, the diffuse colour the file gives its material (0x1RRGGBB), 0 for none; empty
  /// when the file gives no colours (assimp's default material is none).
  std::vector<uint32_t> triangle_rgb;
  /// The image files its textures were read from (inputs of a run, as the mesh file is).
  std::vector<std::string> images;
};

/// One primitive of an object, in SI, placed in the object's frame.
struct Shape {
  enum class Kind : uint8_t { Box, Cylinder, Sphere, Mesh } kind = Kind::Box;
  Eigen::Vector3d box_size = Eigen::Vector3d::Zero();  ///< full extents
  double radius = 0;
  double length = 0;                                    ///< cylinder, along local z
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();      ///< mesh
  std::shared_ptr<const TriangleMesh> mesh;
  Eigen::Isometry3d X_object_shape = Eigen::Isometry3d::Identity();
  int part = -1;  ///< the device part it belongs to; -1 for objects that are not devices
  std::string color;  ///< "#rrggbb" of this shape alone (a URDF visual's material), "" for its part's or object's
};

}  // namespace sscs
