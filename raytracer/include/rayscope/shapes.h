// Procedural triangle meshes: used by the default scene and by the tests.
#pragma once

#include "rayscope/scene.h"

namespace rayscope {

/// Closed icosphere: an icosahedron subdivided `levels` times and projected onto
/// the sphere; 20 * 4^levels triangles, outward winding, smooth normals.
TriangleMesh make_icosphere(const Vec3& center, float radius, int levels);

/// Closed torus around the y axis with per-vertex normals and rainbow colors.
TriangleMesh make_torus(const Vec3& center, float major_radius, float minor_radius, int segments,
                        int sides);

/// Splits every triangle into four at its edge midpoints (shared midpoints stay
/// shared, so a closed mesh stays closed). Normals and colors are interpolated.
TriangleMesh subdivide(const TriangleMesh& mesh);

/// The built-in default scene: a checkerboard plane, a mirror sphere, a glass
/// sphere, a procedural torus with vertex colors and two lights.
Scene make_default_scene();

}  // namespace rayscope
