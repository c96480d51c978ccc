// A scene: camera, lights, materials and geometry (triangle meshes, lines
// drawn as tubes, points drawn as spheres, spheres, infinite planes), plus the
// aggregate (aggregate.h) built by commit(), which answers its ray queries.
//
// Objects are numbered meshes first, then tube sets, point sets, spheres and
// planes; that number is the "object id" of hits and of the object-id AOV.
// Bounded primitives (those an acceleration structure holds) are numbered in
// the same order: triangles (mesh by mesh), tube segments (set by set), points
// (set by set), then spheres; planes are unbounded and tested outside the
// structure. A scene without tubes and points keeps the numbers it had before
// they existed.
//
// Coordinates are scene-local: every position a Scene holds (camera, lights,
// geometry) is relative to Scene::origin, a point in world coordinates kept in
// double precision. Front ends read world coordinates in double, choose an
// origin near what is rendered and round `world - origin` to float
// (to_local), so data far from the world's origin (geospatial data sits at
// 1e5..1e7: UTM, ECEF) keeps float's precision relative to its own size and
// renders as it would at the origin. Outputs in world coordinates (ray trees,
// BVH boxes) add the origin back (to_world).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "rayscope/aggregate.h"
#include "rayscope/camera.h"
#include "rayscope/intersect.h"
#include "rayscope/intersect_capsule.h"
#include "rayscope/light.h"
#include "rayscope/material.h"

namespace rayscope {

/// Indexed triangle mesh with optional per-vertex normals and colors.
struct TriangleMesh {
  std::string name;
  std::vector<Vec3> positions;
  std::vector<glm::uvec3> triangles;
  std::vector<Vec3> normals;  ///< Empty or one per position.
  std::vector<Color> colors;  ///< Empty or one per position (replaces the material color).
  uint32_t material = 0;

  /// Whether every corner of triangle t has finite coordinates: the others
  /// cannot be placed in space and are never traced (Scene::commit).
  bool finite(const glm::uvec3& t) const {
    return all_finite(positions[t.x]) && all_finite(positions[t.y]) && all_finite(positions[t.z]);
  }
  /// How many triangles have a corner with a NaN or infinite coordinate.
  size_t nonfinite_triangles() const {
    return size_t(std::count_if(triangles.begin(), triangles.end(),
                                [&](const glm::uvec3& t) { return !finite(t); }));
  }
};

/// Lines drawn as tubes: every segment a capsule (a cylinder of the segment's
/// radius closed by half-spheres, intersect_capsule.h), so that the joints of
/// a polyline are smooth (the balls at a shared point overlap).
///
/// A segment's radius is `radius` when `radii` is empty, else the mean of its
/// two ends' radii: one radius per segment (a capsule, not a cone), which
/// keeps the mean thickness of a tube whose radius varies and is exact at
/// each segment's middle for a radius linear along the line; where the radii
/// of two segments meeting at a point differ, the tube steps there. Segments
/// with a non-finite end, or an end whose radius is not finite and > 0 (or
/// `radius`, without radii), are left out (Scene::commit reports them); a
/// segment of length 0 is a sphere.
struct TubeSet {
  std::string name;
  std::vector<Vec3> positions;
  std::vector<glm::uvec2> segments;  ///< Indices into positions.
  std::vector<float> radii;          ///< Empty (every segment has `radius`) or one per position.
  float radius = 1.0f;
  /// Empty or one per position: interpolated along the segment, replacing
  /// the material color (like TriangleMesh::colors).
  std::vector<Color> colors;
  uint32_t material = 0;

  /// Segment k's radius (see above), before any check.
  float segment_radius(size_t k) const {
    if (radii.empty()) return radius;
    const glm::uvec2& s = segments[k];
    return float(0.5 * (double(radii[s.x]) + double(radii[s.y])));
  }
  /// Whether segment k is traced (see above); its indices must be in range.
  bool traced(size_t k) const {
    const glm::uvec2& s = segments[k];
    auto usable = [](float r) { return std::isfinite(r) && r > 0.0f; };
    return all_finite(positions[s.x]) && all_finite(positions[s.y]) &&
           (radii.empty() ? usable(radius) : usable(radii[s.x]) && usable(radii[s.y])) &&
           usable(segment_radius(k));
  }
};

/// Points drawn as spheres (the sphere test and records of Sphere). Points
/// with a non-finite position, or whose radius is not finite and > 0, are left
/// out (Scene::commit reports them).
struct PointSet {
  std::string name;
  std::vector<Vec3> positions;
  std::vector<float> radii;  ///< Empty (every point has `radius`) or one per position.
  float radius = 1.0f;
  std::vector<Color> colors;  ///< Empty or one per position (replaces the material color).
  uint32_t material = 0;

  float point_radius(size_t i) const { return radii.empty() ? radius : radii[i]; }
  /// Whether point i is traced (see above).
  bool traced(size_t i) const {
    const float r = point_radius(i);
    return all_finite(positions[i]) && std::isfinite(r) && r > 0.0f;
  }
};

struct Sphere {
  std::string name;
  Vec3 center{0.0f};
  float radius = 1.0f;
  uint32_t material = 0;
};

struct Plane {
  std::string name;
  Vec3 point{0.0f};
  Vec3 normal{0.0f, 1.0f, 0.0f};  ///< Any non-zero length (the aggregate keeps it unit length).
  uint32_t material = 0;
};

enum class ObjectType : uint8_t { Mesh, Tubes, Points, Sphere, Plane };

/// Everything the integrator needs to know about a ray's closest hit.
struct SurfaceHit {
  float t = kInfinity;
  Vec3 p{0.0f};  ///< Hit point.
  /// Per-axis bound on how far p may lie off the exact surface (projected on the
  /// normal, the offset spawn_ray() applies). Not a bound on the distance to the
  /// exact hit point: p may slide along the surface by more (docs/accuracy.md).
  Vec3 p_error{0.0f};
  Vec3 ng{0.0f};  ///< Unit geometric normal (outward / as wound; not face-forwarded).
  Vec3 ns{0.0f};  ///< Unit shading normal (interpolated), same side as ng.
  uint32_t object = ~0u;
  /// Triangle index within its mesh, segment index within its tube set,
  /// point index within its point set; 0 for spheres and planes.
  uint32_t prim = ~0u;
  uint32_t material = 0;
  /// Barycentrics for triangles; for tube segments (1 - s, s, 0), s the
  /// hit's place along the segment (0 at its first end, 1 at its second).
  Vec3 bary{0.0f};
  bool has_vertex_color = false;
  Color vertex_color{0.0f};
};

/// What a scene contains, found once by commit() (used to skip unneeded work).
struct SceneSummary {
  size_t triangles = 0, spheres = 0, planes = 0, lights = 0;
  size_t tube_segments = 0;  ///< Tube segments traced (those left out not counted).
  size_t points = 0;         ///< Points of point sets traced (those left out not counted).
  size_t tube_sets = 0, point_sets = 0;
  size_t skipped_triangles = 0;  ///< Triangles with non-finite vertices, left out.
  /// Tube segments and points left out: a non-finite position, or a radius
  /// that is not finite and > 0.
  size_t skipped_segments = 0, skipped_points = 0;
  size_t degenerate_triangles = 0;  ///< Zero-area triangles (edge cross product 0; never hit).
  size_t nonfinite_normals = 0;     ///< Vertex normals with a non-finite component.
  size_t nonfinite_colors = 0;      ///< Vertex colors with a non-finite component.
  /// What commit() worked around in invalid input, one sentence per problem
  /// and mesh (e.g. "mesh 'bunny': 3 triangles with non-finite vertex
  /// coordinates skipped"). Front ends print each as a warning.
  std::vector<std::string> warnings;
  /// False when queries test every bounded primitive instead of walking a
  /// structure: no structure asked for (none), or so few primitives (<=
  /// Aggregate::kBruteForceMax) that testing them all is cheaper.
  bool walks_structure = true;
  bool reflective = false, refractive = false;

  /// What a structure holds: triangles, tube segments, points and spheres.
  size_t bounded() const { return triangles + tube_segments + points + spheres; }
  /// "N tube segments, M points, " for the front ends' one-line counts when
  /// the scene has tube or point sets, else "" (their lines stay as they were).
  std::string tubes_and_points_text() const {
    if (tube_sets == 0 && point_sets == 0) return "";
    return std::to_string(tube_segments) + " tube segments, " + std::to_string(points) +
           " points, ";
  }
};

/// How far (in multiples of its size) a scene's center must lie from the
/// world's origin before the scene gets a local origin: nearer, float
/// coordinates lose at most log2(16) = 4 bits against local ones (a spacing
/// of 1e-6 of the scene's size, invisible), and the scene is traced in the
/// coordinates it was given, bit for bit as before local origins existed.
inline constexpr double kLocalOriginDistance = 16.0;

/// The local origin (Scene::origin) for a scene whose content lies around
/// `center` within about `size`: `center` when it is farther than
/// kLocalOriginDistance * size from the world's origin in some axis, the
/// world's origin otherwise (and for non-finite input).
inline DVec3 choose_local_origin(const DVec3& center, double size) {
  const double far = std::max({std::abs(center.x), std::abs(center.y), std::abs(center.z)});
  if (!std::isfinite(far) || !std::isfinite(size)) return DVec3(0.0);
  return far > kLocalOriginDistance * size ? center : DVec3(0.0);
}

class Scene {
 public:
  /// World coordinates of the point all of the scene's positions are relative
  /// to (see the top of this file), chosen by choose_local_origin(): the
  /// scene parser's candidate is the camera's look_at (size: its distance to
  /// the eye), the VTK module's the center of its inputs' bounds (size: their
  /// diagonal).
  DVec3 origin{0.0};
  Camera camera;
  std::vector<Material> materials{Material{}};
  std::vector<Light> lights;
  std::vector<TriangleMesh> meshes;
  std::vector<TubeSet> tubes;
  std::vector<PointSet> points;
  std::vector<Sphere> spheres;
  std::vector<Plane> planes;
  Color background{0.0f};
  Color ambient_light{1.0f};  ///< Multiplies each material's ambient term.

  /// Validates the scene and builds the aggregate. Must be called after any
  /// change to the geometry and before tracing. Throws std::invalid_argument on
  /// bad data (bad material index, non-finite sphere, zero plane normal, index
  /// out of range, per-position arrays of the wrong size, a tube or point set's
  /// one `radius` not finite and > 0, a mesh, tube or point set with nothing
  /// left to trace). Data it can work around is reported in
  /// summary().warnings: triangles with non-finite vertices are left out, so
  /// are tube segments and points with a non-finite position or a per-position
  /// radius that is not finite and > 0 (data from files, where one bad value
  /// should not cost the picture); non-finite vertex normals and colors are
  /// not used (the geometric normal and the material color are).
  void commit(const AccelConfig& config = {});

  /// Closest hit along the ray within (0, ray.tmax): intersect(ray, PrimHit&)
  /// followed by surface_hit().
  template <class Observer = NullTraversalObserver>
  bool intersect(const Ray& ray, SurfaceHit& hit, Observer&& obs = Observer{}) const {
    PrimHit ph;
    if (!accel_.intersect(ray, ph, obs)) return false;
    hit = surface_hit(ray, ph);
    return true;
  }

  /// The closest hit without shading data (the lean query tracing needs): see
  /// Aggregate::intersect, which it is. The observer sees the walk of the
  /// chosen structure, the same walk as without one.
  template <class Observer = NullTraversalObserver>
  bool intersect(const Ray& ray, PrimHit& hit, Observer&& obs = Observer{}) const {
    return accel_.intersect(ray, hit, obs);
  }

  /// intersect(ray, PrimHit&) for up to kPacketRays coherent rays at once
  /// (Aggregate::intersect_packet): the same hits, bit for bit; bit k of the
  /// result set when rays[k] hit.
  /// `cost`, when not null, receives the walk's work per ray.
  unsigned intersect_packet(std::span<const Ray> rays, PrimHit* hits,
                            PacketWalkCost* cost = nullptr) const {
    return accel_.intersect_packet(rays, hits, cost);
  }
  /// occluded() for up to kPacketRays rays at once (Aggregate::occluded_packet):
  /// bit k set when rays[k] is occluded.
  unsigned occluded_packet(std::span<const Ray> rays, PacketWalkCost* cost = nullptr) const {
    return accel_.occluded_packet(rays, cost);
  }

  /// Hit point, error bound, normals, ids, material and vertex color of a hit
  /// found by intersect(ray, PrimHit&) for the same ray.
  SurfaceHit surface_hit(const Ray& ray, const PrimHit& hit) const;

  /// Any hit within (0, ray.tmax) (shadow rays): Aggregate::occluded. Stops at
  /// the first occluder and reports it through `occluder` (object id) when not
  /// null.
  template <class Observer = NullTraversalObserver>
  bool occluded(const Ray& ray, Observer&& obs = Observer{}, uint32_t* occluder = nullptr) const {
    PrimHit which;
    if (!accel_.occluded(ray, obs, occluder ? &which : nullptr)) return false;
    if (occluder)
      *occluder = which.plane >= 0 ? plane_object(uint32_t(which.plane)) : prim_object(which.prim);
    return true;
  }

  /// A world position in the scene's local coordinates, rounded to float once.
  Vec3 to_local(const DVec3& world) const { return Vec3(world - origin); }
  /// A scene-local position in world coordinates.
  DVec3 to_world(const Vec3& local) const { return DVec3(local) + origin; }

  /// The aggregate commit() built: the structure queries walk.
  const Aggregate& accel() const { return accel_; }
  /// The binary hierarchy (what statistics, recorded walks and visualisations
  /// name their nodes by), built when first asked for (Aggregate::bvh()).
  const Bvh& bvh() const { return accel_.bvh(); }
  /// The box of the bounded primitives (empty when there are none).
  Bounds3 bounds() const { return accel_.bounds(); }
  const SceneSummary& summary() const { return summary_; }
  size_t object_count() const {
    return meshes.size() + tubes.size() + points.size() + spheres.size() + planes.size();
  }
  ObjectType object_type(uint32_t object) const;
  const std::string& object_name(uint32_t object) const;
  /// The object id of plane k (Scene::planes[k]; RangeHit::plane, PrimHit::plane).
  uint32_t plane_object(uint32_t k) const {
    return uint32_t(meshes.size() + tubes.size() + points.size() + spheres.size()) + k;
  }
  /// Global primitive index -> object id.
  uint32_t prim_object(uint32_t prim) const;
  /// Global primitive index -> its index within its object: the triangle's
  /// index in its mesh, the segment's in its tube set, the point's in its
  /// point set (SurfaceHit::prim), 0 for a sphere.
  uint32_t prim_in_object(uint32_t prim) const {
    return prim < sphere_base_ ? prim - prim_offsets_[prim_object(prim)] : 0;
  }
  /// Global primitive index -> the record the aggregate is built from (as of
  /// the last commit): the shape's vertices, center or ends and radius.
  PrimRecord prim_record(uint32_t prim) const;

 private:
  Aggregate accel_;
  /// Prefix sums of the primitive counts of meshes, tube sets and point sets
  /// in object order (so that an index into it is an object id); the last
  /// entry is the first sphere's primitive index.
  std::vector<uint32_t> prim_offsets_;
  uint32_t num_triangles_ = 0;
  uint32_t sphere_base_ = 0;  ///< Global index of the first sphere.
  SceneSummary summary_;
};

}  // namespace rayscope
