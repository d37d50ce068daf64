#pragma once
/// `sscs export`: the composed workcell as one 3D file through assimp's exporter.
#include <string>

#include "compile/workcell.h"
#include "geometry/geometry.h"

namespace sscs {

/// Triangles of one shape in the object's frame (primitives tessellated: cylinders and spheres
/// with 32 segments).
TriangleMesh tessellate(const Shape& shape);

/// Writes glb, gltf, obj or stl (chosen by the extension): one node per object named after it,
/// carrying its world transform, with its shapes as meshes and its colour as material.
/// Returns an error message, or "" on success. The file is written to a temporary name first.
std::string export_workcell(const Workcell& wc, const GeometryModel& geometry, const std::string& path);

}  // namespace sscs
