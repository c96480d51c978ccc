// The primitives as the structures and the aggregate keep them: bounded
// primitives (triangles, spheres, capsules) as records in leaf order, unbounded planes
// beside the structure, and the closest hit found among them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#include "rayscope/math.h"

namespace rayscope {

/// The closest hit of a ray without any shading data: what tracing needs to
/// find, and no more (the same work as Embree's rtcIntersect1, which returns t,
/// barycentrics and ids). Scene::surface_hit() turns it into a SurfaceHit.
struct PrimHit {
  float t = kInfinity;
  float b0 = 0.0f, b1 = 0.0f, b2 = 0.0f;  ///< Barycentric weights (triangles).
  uint32_t record = ~0u;  ///< Index into Aggregate::records() (leaf order); ~0u for a plane.
  uint32_t prim =
      ~0u;         ///< Global primitive index (Scene: triangles, tube segments, points, spheres).
  int plane = -1;  ///< Index of the plane hit, else -1.
};

/// What a record holds besides triangles (which are told apart by their ids:
/// below the aggregate's triangle count, whatever this says).
enum class PrimShape : uint32_t {
  Triangle = 0,
  Sphere = 1,   ///< A sphere of the scene.
  Capsule = 2,  ///< A tube segment (intersect_capsule.h).
  Point = 3,    ///< A point of a point set: a ball, tested as a sphere.
};

/// One bounded primitive in leaf order: a triangle's vertices (a, b, c), a
/// sphere's or a point's center (a) and radius (b.x), or a capsule's segment
/// (a, b) and radius (c.x). Stored inline so that leaves need no indirection.
struct PrimRecord {
  Vec3 a;
  uint32_t id;  ///< Global primitive index.
  Vec3 b;
  PrimShape shape;
  Vec3 c;
};

/// The record at position i of an order (the scene's, or a structure's leaf
/// order), made when asked for: what the builders are given instead of an
/// array, so that a structure that keeps its primitives in its own form (the
/// BVH's triangle blocks) needs no array of records in between.
using RecordSource = std::function<PrimRecord(size_t)>;

/// An unbounded plane (tested outside any structure).
struct PlaneRecord {
  Vec3 point, normal;  ///< normal: unit length.
};

}  // namespace rayscope
