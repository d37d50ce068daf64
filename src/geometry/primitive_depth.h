#pragma once
/// The exact penetration depth of two solid convex primitives (boxes, cylinders, spheres). FCL's
/// EPA answers these pairs only approximately, and badly for containment: a drum standing inside
/// an overpack comes out as the drum's height, when the shortest way out is sideways. Here the
/// depth is the minimum over directions of the two shapes' overlapping shadows, found by
/// evaluating that overlap at every direction where its minimum can lie (face normals, and the
/// stationary points where edges and rims meet), so the answer is the global minimum, not a local
/// one, and the same on every run.
#include <Eigen/Geometry>

#include "model/shape.h"

namespace sscs {

/// Whether the exact depth below handles this shape (box, cylinder, sphere).
bool is_primitive(const Shape& s);

/// The penetration depth of two solid primitives: the length of the shortest translation of b
/// that separates them (0 when they are apart or touch), exact to 1e-9 m. Handles any
/// placement, containment included. Deterministic (no randomness).
/// The placements are the shapes' own frames in the world (X_object_shape already applied); their
/// linear parts must be rotations (a reflection is fine too). The answer is the same, bit for
/// bit, with a and b swapped. Throws std::invalid_argument for a mesh.
double primitive_penetration_depth(const Shape& a, const Eigen::Isometry3d& X_world_a, const Shape& b,
                                   const Eigen::Isometry3d& X_world_b);

}  // namespace sscs
