#pragma once
/// `sscs export`: the composed workcell as one 3D file through assimp's exporter.
#include <string>
#include <vector>

#include "compile/workcell.h"
#include "geometry/geometry.h"

namespace sscs {

/// Triangles of one shape in the object's frame (primitives tessellated: cylinders and spheres
/// with 32 segments).
TriangleMesh tessellate(const Shape& shape);

/// Triangles with per-corner normals, as interleaved (x y z nx ny nz) floats three corners a
/// triangle: a corner takes the average of the neighbouring faces within 30 degrees of its own
/// face (smooth cylinders and spheres, crisp box edges).
std::vector<float> shaded_triangles(const TriangleMesh& m);

/// What makes two shapes the same triangles in their own frames (kind, sizes, mesh, scale):
/// the key under which the renderer and the glTF writer share one mesh among many shapes.
std::string shape_key(const Shape& shape);

/// Writes obj or stl (chosen by the extension) through assimp: one node per object named after
/// it, carrying its world transform, with its shapes as meshes and its colour as material.
/// glTF files are written by render/gltf.h (animations and cameras); write_export picks.
/// Returns an error message, or "" on success. The file is written to a temporary name first.
std::string export_workcell(const Workcell& wc, const GeometryModel& geometry, const std::string& path);

}  // namespace sscs
