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
  Vec3 p{0.0f};        ///< Hit point.
  Vec3 p_error{0.0f};  ///< Bound on the absolute error of p, per axis.
  Vec3 ng{0.0f};       ///< Unit geometric normal (outward / as wound; not face-forwarded).
  Vec3 ns{0.0f};       ///< Unit shading normal (interpolated), same side as ng.
  uint32_t object = ~0u;
  uint32_t prim = ~0u;  ///< Triangle index within its mesh; 0 for spheres and planes.
  uint32_t material = 0;
  Vec3 bary{0.0f};  ///< Barycentrics for triangles.
  bool has_vertex_color = false;
  Color vertex_color{0.0f};
};

/// What a scene contains, found once by commit() (used to skip unneeded work).
struct SceneSummary {
  size_t triangles = 0, spheres = 0, planes = 0, lights = 0;
  size_t skipped_triangles = 0;  ///< Triangles with non-finite vertices, left out.
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
  void commit(const BvhBuildConfig& config = {});

  /// Closest hit along the ray within (0, ray.tmax). Observer: see Bvh::traverse.
  template <class Observer = NullTraversalObserver>
  bool intersect(const Ray& ray, SurfaceHit& hit, Observer&& obs = Observer{}) const;

  /// Any hit within (0, ray.tmax) (shadow rays). Stops at the first occluder and
  /// reports it through `occluder` (object id) when not null.
  template <class Observer = NullTraversalObserver>
  bool occluded(const Ray& ray, Observer&& obs = Observer{}, uint32_t* occluder = nullptr) const;

  const Bvh& bvh() const { return bvh_; }
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
  void fill_hit(const Ray& ray, uint32_t prim, const TriangleHit& th, float t, int plane,
                SurfaceHit& hit) const;

  Bvh bvh_;
  std::vector<PrimRecord> prims_;
  std::vector<uint32_t> tri_offsets_;  ///< Prefix sums of mesh triangle counts.
  uint32_t num_triangles_ = 0;
  bool use_bvh_ = true;
  SceneSummary summary_;
};

// ---------------------------------------------------------------------------

template <class Observer>
bool Scene::intersect(const Ray& ray, SurfaceHit& hit, Observer&& obs) const {
  float tmax = ray.tmax;
  uint32_t best = ~0u;
  TriangleHit best_tri{};
  const TrianglePrecomp pre(ray);
  const uint32_t ntri = num_triangles_;
  auto leaf = [&](uint32_t first, uint32_t count, float& t) {
    bool found = false;
    for (uint32_t i = first; i < first + count; ++i) {
      const PrimRecord& r = prims_[i];
      if constexpr (std::decay_t<Observer>::kActive) obs.on_prim_test(r.id);
      if (r.id < ntri) {
        TriangleHit th;
        if (intersect_triangle(pre, t, r.a, r.b, r.c, th)) {
          t = th.t;
          best = i;
          best_tri = th;
          found = true;
        }
      } else {
        float ts;
        if (intersect_sphere(ray, r.a, r.b.x, t, ts)) {
          t = ts;
          best = i;
          found = true;
        }
      }
    }
    return found;
  };
  if (use_bvh_)
    bvh_.traverse<false>(ray, tmax, leaf, obs);
  else if (!prims_.empty())
    leaf(0, uint32_t(prims_.size()), tmax);
  int best_plane = -1;
  for (size_t k = 0; k < planes.size(); ++k) {
    float tp;
    if (intersect_plane(ray, planes[k].point, planes[k].normal, tmax, tp)) {
      tmax = tp;
      best_plane = int(k);
    }
  }
  if (best_plane < 0 && best == ~0u) return false;
  fill_hit(ray, best, best_tri, tmax, best_plane, hit);
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
  bool h = use_bvh_ ? bvh_.traverse<true>(ray, tmax, leaf, obs)
                    : (!prims_.empty() && leaf(0, uint32_t(prims_.size()), tmax));
  if (h && occluder) *occluder = prim_object(hit_prim);
  return h;
}

}  // namespace rayscope
