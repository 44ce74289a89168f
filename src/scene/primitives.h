#pragma once
// Parametric meshes (sphere, box, plane, capsule) with normals and UVs: test scenes, stand-ins for
// occluders and bodies in benchmarks, and the `primitive` form of a mesh in scene JSON.

#include "scene/scene.h"

namespace wheelpose::scene {

// Builds the arrays for a primitive spec; throws Error for an unknown type or bad size.
Mesh make_primitive(const PrimitiveSpec& spec);

Mesh make_sphere(float radius, int segments);
// Axis-aligned box centred at the origin with the given half extents.
Mesh make_box(const Eigen::Vector3f& half_extent, int segments);
// Plane in XZ facing +Y, centred at the origin, half sizes hx, hz.
Mesh make_plane(float half_x, float half_z, int segments);
// Capsule along Y: cylinder of half height `half_height` capped by hemispheres of `radius`.
Mesh make_capsule(float radius, float half_height, int segments);

}  // namespace wheelpose::scene
