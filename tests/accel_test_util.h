// Shared fixtures of the acceleration-structure tests (test_bvh, test_wide_bvh,
// test_aggregate): random primitive boxes, leaf functions whose primitives are
// the boxes themselves, and brute force over a committed scene.
#pragma once

#include <vector>

#include "rayscope/scene.h"
#include "test_util.h"

namespace rstest {

/// Bounds and centroids: what the BVH builder takes.
struct Prims {
  std::vector<rayscope::Bounds3> bounds;
  std::vector<rayscope::Vec3> centroids;
  void add(const rayscope::Bounds3& b) {
    bounds.push_back(b);
    centroids.push_back(b.center());
  }
};

/// How random_boxes() places boxes.
enum class BoxLayout { Uniform, Clustered, Coincident, LogUniform };

/// n random boxes: uniform in a cube, in a few tight clusters, all with the
/// same centroid, or with log-uniform coordinates and sizes over 12 decades.
inline Prims random_boxes(Rng& rng, int n, BoxLayout layout) {
  Prims p;
  for (int i = 0; i < n; ++i) {
    DVec3 c;
    switch (layout) {
      case BoxLayout::Uniform:
        c = DVec3(rng.uniform(-100, 100), rng.uniform(-100, 100), rng.uniform(-100, 100));
        break;
      case BoxLayout::Clustered: {
        const DVec3 centers[4] = {{-50, 0, 0}, {50, 10, 0}, {0, 0, 80}, {3, 3, 3}};
        c = centers[rng.integer(0, 3)] + rng.uniform(0.01, 5) * rng.in_unit_ball();
        break;
      }
      case BoxLayout::Coincident:
        c = DVec3(1, 2, 3);
        break;
      case BoxLayout::LogUniform:
        c = DVec3(rng.log_uniform_signed(1e-6, 1e6), rng.log_uniform_signed(1e-6, 1e6),
                  rng.log_uniform_signed(1e-6, 1e6));
        break;
    }
    const double s = layout == BoxLayout::LogUniform ? max_abs(c) * rng.log_uniform(1e-4, 1)
                                                     : rng.log_uniform(1e-3, 5);
    DVec3 h(s * rng.uniform(0.1, 1), s * rng.uniform(0.1, 1), s * rng.uniform(0.1, 1));
    if (layout == BoxLayout::Coincident)
      h = DVec3(rng.uniform(0.1, 1), rng.uniform(0.1, 1), rng.uniform(0.1, 1));
    p.add(rayscope::Bounds3(to_f(c - h), to_f(c + h)));
  }
  return p;
}

/// Groups of thin boxes at x = 17^j (j = -30..30): with 16 equal-width bins
/// each SAH split can only peel off one group, so the binary tree becomes a
/// chain as deep as the builder allows. A ray along +x pushes at every level.
inline Prims deep_chain_boxes(Rng& rng) {
  Prims p;
  for (int j = -30; j <= 30; ++j)
    for (int k = 0; k < 2000; ++k) {
      const float x = std::pow(17.0f, float(j)) * round_f(1.0 + 1e-3 * rng.uniform());
      p.add(
          rayscope::Bounds3(rayscope::Vec3(x, 0, 0), rayscope::Vec3(x * 1.0001f, 1e-20f, 1e-20f)));
    }
  return p;
}

/// Walks whose primitives are boxes: a box's hit distance is its entry
/// distance (intersect_box). `order` is the leaf order (Bvh::prim_indices).
struct BoxLeaves {
  const std::vector<rayscope::Bounds3>& boxes;
  const std::vector<uint32_t>& order;
  rayscope::Vec3 origin, inv_dir;
  float best = rayscope::kInfinity;  ///< Closest entry distance found.

  BoxLeaves(const Prims& p, const std::vector<uint32_t>& leaf_order, const rayscope::Ray& ray)
      : boxes(p.bounds), order(leaf_order), origin(ray.origin), inv_dir(1.0f / ray.dir) {}

  /// Closest-hit leaf function.
  auto closest() {
    return [this](uint32_t first, uint32_t count, float& t) {
      bool found = false;
      for (uint32_t k = first; k < first + count; ++k) {
        const rayscope::Bounds3& b = boxes[order[k]];
        const float tb = rayscope::intersect_box(b.lo, b.hi, origin, inv_dir, t);
        if (tb < best) best = t = tb, found = true;
      }
      return found;
    };
  }
  /// Any-hit leaf function.
  auto any() {
    return [this](uint32_t first, uint32_t count, float& t) {
      for (uint32_t k = first; k < first + count; ++k) {
        const rayscope::Bounds3& b = boxes[order[k]];
        if (rayscope::intersect_box(b.lo, b.hi, origin, inv_dir, t) != rayscope::kInfinity)
          return true;
      }
      return false;
    };
  }
  /// The closest entry distance over all boxes (brute force).
  float brute_force(float tmax) const {
    float t = rayscope::kInfinity;
    for (const rayscope::Bounds3& b : boxes)
      t = std::min(t, rayscope::intersect_box(b.lo, b.hi, origin, inv_dir, tmax));
    return t;
  }
};

/// The closest hit of a loop over every triangle, sphere and plane of a
/// committed scene in order, with the tests' own range checks: a triangle at
/// exactly the closest t so far replaces it (intersect_triangle accepts
/// t == tmax), a sphere or plane does not. That loop defines the tie rule.
struct BruteHit {
  float t = rayscope::kInfinity;
  uint32_t prim = ~0u;  ///< Global primitive index (triangles, then spheres).
  int plane = -1;
  bool tie = false;  ///< Another primitive was hit at exactly the same t.
};

inline BruteHit brute_force(const rayscope::Scene& s, const rayscope::Ray& ray) {
  using namespace rayscope;
  BruteHit best;
  float tmax = ray.tmax;
  const TrianglePrecomp pre(ray);
  uint32_t id = 0;
  for (const TriangleMesh& mesh : s.meshes)
    for (const glm::uvec3& t : mesh.triangles) {
      TriangleHit th;
      if (intersect_triangle(pre, tmax, mesh.positions[t.x], mesh.positions[t.y],
                             mesh.positions[t.z], th)) {
        best.tie |= th.t == tmax && best.prim != ~0u;
        tmax = th.t;
        best.t = th.t;
        best.prim = id;
      }
      ++id;
    }
  for (const rayscope::Sphere& sp : s.spheres) {
    float ts;
    if (intersect_sphere(ray, sp.center, sp.radius, next_float_up(tmax), ts)) {
      if (ts == tmax && best.prim != ~0u) {
        best.tie = true;
      } else if (ts < tmax) {
        tmax = ts;
        best.t = ts;
        best.prim = id;
      }
    }
    ++id;
  }
  for (size_t k = 0; k < s.planes.size(); ++k) {
    float tp;
    if (intersect_plane(ray, s.planes[k].point, s.planes[k].normal, tmax, tp)) {
      tmax = tp;
      best = BruteHit{tp, ~0u, int(k), best.tie};
    }
  }
  return best;
}

/// The bounds of every triangle of the scene's meshes (targets for random_ray).
inline std::vector<rayscope::Bounds3> triangle_boxes(const rayscope::Scene& scene) {
  std::vector<rayscope::Bounds3> boxes;
  for (const rayscope::TriangleMesh& m : scene.meshes)
    for (const glm::uvec3& t : m.triangles) {
      rayscope::Bounds3 b(m.positions[t.x]);
      b.extend(m.positions[t.y]);
      b.extend(m.positions[t.z]);
      boxes.push_back(b);
    }
  return boxes;
}

}  // namespace rstest
