// A scene: camera, lights, materials and geometry (triangle meshes, spheres,
// infinite planes), plus the acceleration structure built by commit().
//
// Objects are numbered meshes first, then spheres, then planes; that number is
// the "object id" of hits and of the object-id AOV. Primitives inside the BVH
// are numbered triangles first (mesh by mesh), then spheres; planes are
// unbounded and tested outside the BVH.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "rayscope/bvh.h"
#include "rayscope/bvh4.h"
#include "rayscope/camera.h"
#include "rayscope/intersect.h"
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
  Vec3 normal{0.0f, 1.0f, 0.0f};
  uint32_t material = 0;
};

enum class ObjectType : uint8_t { Mesh, Sphere, Plane };

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
  uint32_t prim = ~0u;  ///< Triangle index within its mesh; 0 for spheres and planes.
  uint32_t material = 0;
  Vec3 bary{0.0f};  ///< Barycentrics for triangles.
  bool has_vertex_color = false;
  Color vertex_color{0.0f};
};

/// The closest hit of a ray without any shading data: what tracing needs to
/// find, and no more (the same work as Embree's rtcIntersect1, which returns t,
/// barycentrics and ids). Scene::surface_hit() turns it into a SurfaceHit.
struct PrimHit {
  float t = kInfinity;
  float b0 = 0.0f, b1 = 0.0f, b2 = 0.0f;  ///< Barycentric weights (triangles).
  uint32_t record = ~0u;  ///< Index into Scene::prim_records() (leaf order); ~0u for a plane.
  uint32_t prim = ~0u;    ///< Global primitive index (triangles mesh by mesh, then spheres).
  int plane = -1;         ///< Index into Scene::planes when a plane was hit, else -1.
};

/// What a scene contains, found once by commit() (used to skip unneeded work).
struct SceneSummary {
  size_t triangles = 0, spheres = 0, planes = 0, lights = 0;
  size_t skipped_triangles = 0;     ///< Triangles with non-finite vertices, left out.
  size_t degenerate_triangles = 0;  ///< Zero-area triangles (edge cross product 0; never hit).
  size_t nonfinite_normals = 0;     ///< Vertex normals with a non-finite component.
  size_t nonfinite_colors = 0;      ///< Vertex colors with a non-finite component.
  /// What commit() worked around in invalid input, one sentence per problem
  /// and mesh (e.g. "mesh 'bunny': 3 triangles with non-finite vertex
  /// coordinates skipped"). Front ends print each as a warning.
  std::vector<std::string> warnings;
  /// False when the scene has so few bounded primitives (<= kBruteForceMax) that
  /// testing them all is cheaper than walking a hierarchy.
  bool bvh_used = true;
  bool reflective = false, refractive = false;
};

class Scene {
 public:
  /// Scenes with at most this many bounded primitives skip the BVH and test
  /// them all. Measured by bench_recording (default-scene spheres, one thread):
  /// 1-3 spheres render 2-8% faster without a BVH, 4 spheres 2% slower.
  static constexpr size_t kBruteForceMax = 3;

  Camera camera;
  std::vector<Material> materials{Material{}};
  std::vector<Light> lights;
  std::vector<TriangleMesh> meshes;
  std::vector<Sphere> spheres;
  std::vector<Plane> planes;
  Color background{0.0f};
  Color ambient_light{1.0f};  ///< Multiplies each material's ambient term.
  /// Let commit() skip the BVH for tiny scenes (see kBruteForceMax). Off only
  /// to measure what the skip saves.
  bool allow_brute_force = true;

  /// Validates the scene and builds the BVH. Must be called after any change to
  /// the geometry and before tracing. Throws std::invalid_argument on bad data
  /// (bad material index, non-finite sphere, zero plane normal, index out of range).
  /// Mesh data it can work around is reported in summary().warnings: triangles
  /// with non-finite vertices are left out, non-finite vertex normals and
  /// colors are not used (the geometric normal and the material color are).
  void commit(const BvhBuildConfig& config = {});

  /// Closest hit along the ray within (0, ray.tmax): intersect(ray, PrimHit&)
  /// followed by surface_hit(). Observer: see Bvh::traverse.
  template <class Observer = NullTraversalObserver>
  bool intersect(const Ray& ray, SurfaceHit& hit, Observer&& obs = Observer{}) const;

  /// The closest hit without shading data (lean query for tracing only). When
  /// several primitives are hit at exactly the same t, the result is the one a
  /// brute-force loop over all triangles, then spheres, then planes reports:
  /// the triangle with the highest global index, else the sphere with the
  /// lowest, else the first plane. The answer therefore does not depend on the
  /// order in which the hierarchy is walked.
  ///
  /// Without an observer (Observer::kActive == false) the query walks the
  /// 4-wide hierarchy bvh4(); with one (ray-tree recording, statistics) it
  /// walks the binary hierarchy bvh(), so that the observer sees the nodes and
  /// box tests of the hierarchy RayScope builds, visualises and explains.
  /// Both walks cull by the same criterion and break ties by the rule above,
  /// so they return the same hit, bit for bit (recorded pixels replay exactly).
  template <class Observer = NullTraversalObserver>
  bool intersect(const Ray& ray, PrimHit& hit, Observer&& obs = Observer{}) const;

  /// Hit point, error bound, normals, ids, material and vertex color of a hit
  /// found by intersect(ray, PrimHit&) for the same ray.
  SurfaceHit surface_hit(const Ray& ray, const PrimHit& hit) const;

  /// Any hit within (0, ray.tmax) (shadow rays). Stops at the first occluder and
  /// reports it through `occluder` (object id) when not null. Walks bvh4()
  /// without an observer and bvh() with one, like intersect().
  template <class Observer = NullTraversalObserver>
  bool occluded(const Ray& ray, Observer&& obs = Observer{}, uint32_t* occluder = nullptr) const;

  /// The binary hierarchy (built by commit(); what statistics, recorded
  /// traversals and visualisations refer to).
  const Bvh& bvh() const { return bvh_; }
  /// Its 4-wide collapse, which unobserved queries walk (see intersect()).
  const Bvh4& bvh4() const { return bvh4_; }
  const SceneSummary& summary() const { return summary_; }
  size_t object_count() const { return meshes.size() + spheres.size() + planes.size(); }
  ObjectType object_type(uint32_t object) const;
  const std::string& object_name(uint32_t object) const;
  /// Global BVH primitive index -> object id.
  uint32_t prim_object(uint32_t prim) const;

  /// One BVH primitive in leaf order: a triangle's vertices, or a sphere's center
  /// and radius (in b.x). Stored inline so that leaves need no indirection.
  struct PrimRecord {
    Vec3 a;
    uint32_t id;  ///< Global primitive index.
    Vec3 b;
    uint32_t pad;
    Vec3 c;
  };
  const std::vector<PrimRecord>& prim_records() const { return prims_; }

 private:
  /// Whether primitive `a` wins an exact tie in t against primitive `b` (see
  /// intersect(ray, PrimHit&)): triangles beat spheres, a higher triangle index
  /// beats a lower one, a lower sphere index beats a higher one.
  bool wins_tie(uint32_t a, uint32_t b) const {
    return a < num_triangles_ ? (b >= num_triangles_ || a > b) : (b >= num_triangles_ && a < b);
  }

  Bvh bvh_;
  Bvh4 bvh4_;
  std::vector<PrimRecord> prims_;
  std::vector<uint32_t> tri_offsets_;  ///< Prefix sums of mesh triangle counts.
  uint32_t num_triangles_ = 0;
  bool use_bvh_ = true;
  SceneSummary summary_;
};

// ---------------------------------------------------------------------------

template <class Observer>
bool Scene::intersect(const Ray& ray, SurfaceHit& hit, Observer&& obs) const {
  PrimHit ph;
  if (!intersect(ray, ph, obs)) return false;
  hit = surface_hit(ray, ph);
  return true;
}

template <class Observer>
bool Scene::intersect(const Ray& ray, PrimHit& hit, Observer&& obs) const {
  float tmax = ray.tmax;
  uint32_t best = ~0u, best_id = ~0u;
  TriangleHit best_tri{};
  const TrianglePrecomp pre(ray);
  const uint32_t ntri = num_triangles_;
  // intersect_triangle accepts t == tmax, intersect_sphere only t < tmax; a hit
  // at exactly the closest t so far replaces it only if it wins the tie.
  auto leaf = [&](uint32_t first, uint32_t count, float& t) {
    bool found = false;
    for (uint32_t i = first; i < first + count; ++i) {
      const PrimRecord& r = prims_[i];
      if constexpr (std::decay_t<Observer>::kActive) obs.on_prim_test(r.id);
      if (r.id < ntri) {
        TriangleHit th;
        if (intersect_triangle(pre, t, r.a, r.b, r.c, th) &&
            (th.t < t || best == ~0u || wins_tie(r.id, best_id))) {
          t = th.t;
          best = i;
          best_id = r.id;
          best_tri = th;
          found = true;
        }
      } else {
        float ts;
        if (intersect_sphere(ray, r.a, r.b.x, best == ~0u ? t : next_float_up(t), ts) &&
            (ts < t || wins_tie(r.id, best_id))) {
          t = ts;
          best = i;
          best_id = r.id;
          best_tri = TriangleHit{ts, 0.0f, 0.0f, 0.0f};
          found = true;
        }
      }
    }
    return found;
  };
  if (use_bvh_) {
    if constexpr (std::decay_t<Observer>::kActive)
      bvh_.traverse<false>(ray, tmax, leaf, obs);
    else
      bvh4_.traverse<false>(ray, tmax, leaf, obs);
  } else if (!prims_.empty())
    leaf(0, uint32_t(prims_.size()), tmax);
  int best_plane = -1;
  for (size_t k = 0; k < planes.size(); ++k) {
    float tp;
    if (intersect_plane(ray, planes[k].point, planes[k].normal, tmax, tp)) {
      tmax = tp;
      best_plane = int(k);
    }
  }
  if (best_plane >= 0) {
    hit = PrimHit{};
    hit.t = tmax;
    hit.plane = best_plane;
    return true;
  }
  if (best == ~0u) return false;
  hit.t = tmax;
  hit.b0 = best_tri.b0;
  hit.b1 = best_tri.b1;
  hit.b2 = best_tri.b2;
  hit.record = best;
  hit.prim = best_id;
  hit.plane = -1;
  return true;
}

template <class Observer>
bool Scene::occluded(const Ray& ray, Observer&& obs, uint32_t* occluder) const {
  for (size_t k = 0; k < planes.size(); ++k) {
    float tp;
    if (intersect_plane(ray, planes[k].point, planes[k].normal, ray.tmax, tp)) {
      if (occluder) *occluder = uint32_t(meshes.size() + spheres.size() + k);
      return true;
    }
  }
  float tmax = ray.tmax;
  const TrianglePrecomp pre(ray);
  const uint32_t ntri = num_triangles_;
  uint32_t hit_prim = ~0u;
  auto leaf = [&](uint32_t first, uint32_t count, float& t) {
    for (uint32_t i = first; i < first + count; ++i) {
      const PrimRecord& r = prims_[i];
      if constexpr (std::decay_t<Observer>::kActive) obs.on_prim_test(r.id);
      bool h;
      if (r.id < ntri) {
        TriangleHit th;
        h = intersect_triangle(pre, t, r.a, r.b, r.c, th);
      } else {
        float ts;
        h = intersect_sphere(ray, r.a, r.b.x, t, ts);
      }
      if (h) {
        hit_prim = r.id;
        return true;
      }
    }
    return false;
  };
  bool h;
  if (!use_bvh_)
    h = !prims_.empty() && leaf(0, uint32_t(prims_.size()), tmax);
  else if constexpr (std::decay_t<Observer>::kActive)
    h = bvh_.traverse<true>(ray, tmax, leaf, obs);
  else
    h = bvh4_.traverse<true>(ray, tmax, leaf, obs);
  if (h && occluder) *occluder = prim_object(hit_prim);
  return h;
}

}  // namespace rayscope
