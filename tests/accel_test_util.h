// Shared fixtures of the acceleration-structure tests (test_bvh, test_wide_bvh,
// test_aggregate, test_kdtree): random primitive boxes, leaf functions whose
// primitives are the boxes themselves, brute force over a committed scene, and
// the check of a scene's queries against it.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <vector>

#include "rayscope/scene.h"
#include "rayscope/shapes.h"
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

/// Appends n random rays (rstest::random_ray) aimed at the scene's triangles
/// or through `world`.
inline void add_random_rays(Rng& rng, const rayscope::Scene& scene, const rayscope::Bounds3& world,
                            int n, std::vector<rayscope::Ray>& rays) {
  const std::vector<rayscope::Bounds3> boxes = triangle_boxes(scene);
  for (int i = 0; i < n; ++i) rays.push_back(random_ray(rng, world, boxes));
}

// An observer that is active and does nothing: the query must not change.
struct AlwaysActive : rayscope::TraversalHooks {
  static constexpr bool kActive = true;
};

inline bool same_bits(const rayscope::PrimHit& a, const rayscope::PrimHit& b) {
  return std::memcmp(&a.t, &b.t, sizeof(float)) == 0 &&
         std::memcmp(&a.b0, &b.b0, sizeof(float)) == 0 &&
         std::memcmp(&a.b1, &b.b1, sizeof(float)) == 0 &&
         std::memcmp(&a.b2, &b.b2, sizeof(float)) == 0 && a.record == b.record &&
         a.prim == b.prim && a.plane == b.plane;
}

// Every ray: closest hit equal to brute force (t bit for bit, the same
// primitive, ties resolved by the loop order), observed == plain bit for bit,
// any hit == closest hit found, the SurfaceHit query == lean query plus
// surface_hit(). Returns the hits, for comparisons across structures.
inline std::vector<rayscope::PrimHit> check_queries(const rayscope::Scene& scene,
                                                    const std::vector<rayscope::Ray>& rays,
                                                    const char* what, int min_ties) {
  int hits = 0, ties = 0;
  std::vector<rayscope::PrimHit> out;
  for (size_t i = 0; i < rays.size(); ++i) {
    const rayscope::Ray& ray = rays[i];
    const BruteHit bf = brute_force(scene, ray);
    rayscope::PrimHit plain, observed;
    const bool got = scene.intersect(ray, plain);
    EXPECT_EQ(scene.intersect(ray, observed, AlwaysActive{}), got) << what << ", ray " << i;
    EXPECT_EQ(got, bf.t != rayscope::kInfinity)
        << what << ", ray " << i << " from " << ::testing::PrintToString(ray.origin) << " along "
        << ::testing::PrintToString(ray.dir) << ", tmax " << ray.tmax << ": brute force hits prim "
        << bf.prim << " at t " << bf.t;
    EXPECT_TRUE(same_bits(plain, observed))
        << what << ", ray " << i << ": plain prim " << plain.prim << " t " << plain.t
        << ", observed prim " << observed.prim << " t " << observed.t;
    const bool occluded = scene.occluded(ray);
    uint32_t occluder = ~0u;
    EXPECT_EQ(scene.occluded(ray, AlwaysActive{}, &occluder), occluded) << what << ", ray " << i;
    EXPECT_EQ(occluded, got) << what << ", any-hit ray " << i;
    if (occluded) {
      EXPECT_LT(occluder, scene.object_count()) << what << ", ray " << i;
    }
    out.push_back(plain);
    if (::testing::Test::HasFailure()) return out;
    if (!got) continue;
    ++hits;
    ties += bf.tie;
    EXPECT_EQ(plain.t, bf.t) << what << ", ray " << i;
    EXPECT_EQ(plain.plane, bf.plane) << what << ", ray " << i;
    EXPECT_EQ(plain.prim, bf.prim) << what << ", ray " << i << (bf.tie ? " (tie)" : "");
    if (plain.plane < 0) {
      EXPECT_LT(plain.record, scene.accel().records().size());
      if (plain.record < scene.accel().records().size()) {
        EXPECT_EQ(scene.accel().records()[plain.record].id, plain.prim);
      }
    }
    rayscope::SurfaceHit sh;
    EXPECT_TRUE(scene.intersect(ray, sh));
    const rayscope::SurfaceHit ref = scene.surface_hit(ray, plain);
    EXPECT_EQ(std::memcmp(&sh.p, &ref.p, sizeof(rayscope::Vec3)), 0);
    EXPECT_EQ(std::memcmp(&sh.ns, &ref.ns, sizeof(rayscope::Vec3)), 0);
    EXPECT_EQ(sh.object, ref.object);
    EXPECT_EQ(sh.prim, ref.prim);
    if (::testing::Test::HasFailure()) return out;
  }
  std::printf("%s: %zu rays, %d hits, %d with exact ties\n", what, rays.size(), hits, ties);
  EXPECT_GT(hits, int(rays.size()) / 4) << what;
  EXPECT_GE(ties, min_ties) << what;
  return out;
}

/// The axis-aligned unit cube with its lowest corner at `corner`: 12
/// triangles whose faces lie in split planes, edges and corners shared.
inline rayscope::TriangleMesh unit_cube(const rayscope::Vec3& corner) {
  rayscope::TriangleMesh cube;
  for (int i = 0; i < 8; ++i)
    cube.positions.push_back(
        corner + rayscope::Vec3(float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)));
  cube.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return cube;
}

/// Two closed meshes, a soup of 1000 random triangles, 10 spheres and a floor.
inline rayscope::Scene soup_scene(Rng& rng) {
  rayscope::Scene scene;
  scene.meshes.push_back(rayscope::make_icosphere(rayscope::Vec3(0.0f), 2.0f, 3));
  scene.meshes.push_back(
      rayscope::make_torus(rayscope::Vec3(3.0f, 0.0f, 0.0f), 1.5f, 0.4f, 32, 16));
  rayscope::TriangleMesh soup;
  for (uint32_t i = 0; i < 1000; ++i) {
    DVec3 c(rng.uniform(-6, 6), rng.uniform(-6, 6), rng.uniform(-6, 6));
    double s = rng.log_uniform(0.01, 1);
    for (int k = 0; k < 3; ++k) soup.positions.push_back(to_f(c + s * rng.in_unit_ball()));
    soup.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  scene.meshes.push_back(soup);
  for (int k = 0; k < 10; ++k)
    scene.spheres.push_back(rayscope::Sphere{
        "s", to_f(DVec3(rng.uniform(-6, 6), rng.uniform(-6, 6), rng.uniform(-6, 6))),
        rstest::round_f(rng.log_uniform(0.05, 1)), 0});
  scene.planes.push_back(
      rayscope::Plane{"floor", rayscope::Vec3(0, -5, 0), rayscope::Vec3(0, 1, 0), 0});
  return scene;
}

// --- Adversarial rays shared by the structure tests ----------------------------

/// A point uniformly inside `world`.
inline rayscope::Vec3 point_in(Rng& rng, const rayscope::Bounds3& world) {
  return to_f(to_d(world.lo) +
              to_d(world.extent()) * DVec3(rng.uniform(), rng.uniform(), rng.uniform()));
}

/// Rays aimed at every third vertex and at every other triangle's edge
/// midpoint (exact ties between the triangles sharing it), and rays lying
/// along those edges from outside them.
inline void add_mesh_rays(Rng& rng, const rayscope::Scene& scene,
                          std::vector<rayscope::Ray>& rays) {
  using namespace rayscope;
  auto aim = [&](const Vec3& target) {
    const Vec3 o = to_f(to_d(target) + 8.0 * rng.unit_vector());
    rays.push_back(Ray{o, target - o, kInfinity});
  };
  for (const TriangleMesh& m : scene.meshes) {
    for (size_t v = 0; v < m.positions.size(); v += 3) aim(m.positions[v]);
    for (size_t k = 0; k < m.triangles.size(); k += 2) {
      const glm::uvec3& t = m.triangles[k];
      const Vec3 a = m.positions[t.x], b = m.positions[t.y];
      aim(0.5f * (a + b));
      rays.push_back(Ray{to_f(to_d(a) - 0.5 * (to_d(b) - to_d(a))), b - a, kInfinity});
    }
  }
}

/// For the axis-aligned plane `axis` = `plane` of a structure: a ray lying in
/// it and one leaving it (origins inside `world`), and with `across`, one
/// axis-parallel ray crossing it from outside `world`, through `*through`
/// (default: the leaving ray's origin).
inline void add_plane_rays(Rng& rng, const rayscope::Bounds3& world, int axis, float plane,
                           std::vector<rayscope::Ray>& rays, bool across = true,
                           const rayscope::Vec3* through = nullptr) {
  using namespace rayscope;
  Vec3 o = point_in(rng, world);
  o[axis] = plane;
  Vec3 d = to_f(rng.unit_vector());
  d[axis] = rng.coin() ? 0.0f : -0.0f;
  if (d == Vec3(0.0f)) d[(axis + 1) % 3] = 1.0f;
  rays.push_back(Ray{o, d, kInfinity});                        // in the plane
  rays.push_back(Ray{o, to_f(rng.unit_vector()), kInfinity});  // leaving it
  if (!across) return;
  Vec3 p = through ? *through : o, dp(0.0f);
  dp[axis] = rng.coin() ? 1.0f : -1.0f;
  p[axis] = dp[axis] > 0.0f ? world.lo[axis] - 1.0f : world.hi[axis] + 1.0f;
  rays.push_back(Ray{p, dp, kInfinity});
}

/// n rays starting inside `world`, every other one short (tmax below 2), and
/// 20 rays tangent to each of the scene's spheres.
inline void add_inside_and_grazing_rays(Rng& rng, const rayscope::Scene& scene,
                                        const rayscope::Bounds3& world, int n,
                                        std::vector<rayscope::Ray>& rays) {
  using namespace rayscope;
  for (int i = 0; i < n; ++i) {
    const Vec3 o = point_in(rng, world);
    rays.push_back(Ray{o, to_f(rng.unit_vector()), i % 2 ? kInfinity : float(rng.uniform(0, 2))});
  }
  for (const Sphere& s : scene.spheres)
    for (int k = 0; k < 20; ++k) {
      const DVec3 nrm = rng.unit_vector();
      const DVec3 t = glm::normalize(glm::cross(nrm, rng.unit_vector()));
      const DVec3 p = to_d(s.center) + double(s.radius) * nrm;
      rays.push_back(Ray{to_f(p - 5.0 * t), to_f(t), kInfinity});
    }
}

// Counts what a walk reports (traversal.h), per node id and per primitive:
// the structure tests share it for their mailbox checks. Ids are the
// structure's node ids (the grid's cells and its box, box_id()).
struct CountingObserver : rayscope::TraversalHooks {
  static constexpr bool kActive = true;
  std::vector<int> nodes;       ///< Times entered, per id.
  std::vector<uint32_t> order;  ///< Ids entered, in order.
  std::vector<int> box_tests;   ///< Box tests, per id.
  std::vector<int> prim_tests;  ///< Tests, per primitive.
  int boxes = 0, culled = 0;
  CountingObserver(size_t ids, size_t prims) : nodes(ids), box_tests(ids), prim_tests(prims) {}
  void on_node(uint32_t n) {
    nodes.at(n)++;
    order.push_back(n);
  }
  void on_box_test(uint32_t n, bool) {
    box_tests.at(n)++;
    boxed_.push_back(n);
    ++boxes;
  }
  void on_cull(uint32_t n) {
    ASSERT_LT(n, nodes.size());
    ++culled;
  }
  void on_prim_test(uint32_t p) {
    prim_tests.at(p)++;
    tested_.push_back(p);
  }
  /// Zero again for the next query, touching only what this one counted (a
  /// fine grid has millions of ids).
  void reset() {
    for (uint32_t n : order) nodes[n] = 0;
    for (uint32_t n : boxed_) box_tests[n] = 0;
    for (uint32_t p : tested_) prim_tests[p] = 0;
    order.clear();
    boxed_.clear();
    tested_.clear();
    boxes = culled = 0;
  }
  /// The primitives tested, each as often as it was.
  const std::vector<uint32_t>& tested() const { return tested_; }
  /// The ids whose box was tested, each as often as it was.
  const std::vector<uint32_t>& boxed() const { return boxed_; }

 private:
  std::vector<uint32_t> boxed_, tested_;
};

// The mailbox tests' scene: an icosphere and 300 long thin triangles that
// straddle many cells (stored several times by every-cell, held high up by
// smallest-cell).
inline rayscope::Scene sliver_scene(Rng& rng) {
  using namespace rayscope;
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 3));
  TriangleMesh slivers;
  for (uint32_t i = 0; i < 300; ++i) {
    const DVec3 c(rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(-4, 4));
    const DVec3 along = 3.0 * rng.unit_vector(), across = 0.01 * rng.unit_vector();
    slivers.positions.push_back(to_f(c - along));
    slivers.positions.push_back(to_f(c + along));
    slivers.positions.push_back(to_f(c + across));
    slivers.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  scene.meshes.push_back(slivers);
  return scene;
}

// Totals of mailbox_rays() over its closest-hit queries.
struct MailboxTotals {
  uint64_t tests = 0;            ///< Primitive tests.
  uint64_t multi_node_rays = 0;  ///< Rays that entered more than 2 nodes.
  uint64_t culls = 0;
};

// The shared mailbox check: n_rays random rays from a sphere of radius 6,
// each as a closest-hit and an any-hit query with a CountingObserver over
// `ids` node ids: every primitive tested at most once, every node entered at
// at most once. `check(obs, any_hit)` adds the structure's own checks (it
// may use gtest assertions). Callers stop on HasFatalFailure().
template <class Check>
void mailbox_rays(const rayscope::Scene& scene, Rng& rng, int n_rays, size_t ids,
                  MailboxTotals& totals, Check&& check) {
  using namespace rayscope;
  const size_t prims = scene.accel().records().size();
  CountingObserver obs(ids, prims);
  for (int i = 0; i < n_rays; ++i) {
    const Ray ray{to_f(6.0 * rng.unit_vector()), to_f(rng.unit_vector()), kInfinity};
    for (int any = 0; any < 2; ++any) {
      obs.reset();
      PrimHit hit;
      if (any)
        scene.occluded(ray, obs);
      else
        scene.intersect(ray, hit, obs);
      if (::testing::Test::HasFatalFailure()) return;
      for (uint32_t p : obs.tested())
        ASSERT_EQ(obs.prim_tests[p], 1) << "ray " << i << (any ? " (any hit)" : "");
      for (uint32_t n : obs.order) ASSERT_EQ(obs.nodes[n], 1) << "a node entered twice, ray " << i;
      check(obs, any != 0);
      if (::testing::Test::HasFatalFailure()) return;
      if (any) continue;
      totals.tests += obs.tested().size();
      totals.multi_node_rays += obs.order.size() > 2;
      totals.culls += uint64_t(obs.culled);
    }
  }
}

// A box range: whatever overlaps the closed box.
struct BoxRange {
  rayscope::Bounds3 box;
  rayscope::Bounds3 bounds() const { return box; }
  bool overlaps(const rayscope::Bounds3& b) const {
    return glm::all(glm::lessThanEqual(box.lo, b.hi)) && glm::all(glm::lessThanEqual(b.lo, box.hi));
  }
  float distance(const rayscope::Bounds3& b) const {
    const rayscope::Vec3 c = box.center();
    return glm::length(glm::max(glm::max(b.lo - c, c - b.hi), rayscope::Vec3(0.0f)));
  }
};

// A sphere that shrinks to the nearest box found so far (the nearest
// neighbor): a range that shrinks while it is walked.
struct NearestRange {
  rayscope::Vec3 center;
  float radius = rayscope::kInfinity;
  float distance(const rayscope::Bounds3& b) const {
    return glm::length(glm::max(glm::max(b.lo - center, center - b.hi), rayscope::Vec3(0.0f)));
  }
  bool overlaps(const rayscope::Bounds3& b) const { return distance(b) <= radius; }
  rayscope::Bounds3 bounds() const {
    rayscope::Bounds3 b;
    b.lo = center - radius;
    b.hi = center + radius;
    return b;
  }
};

// What check_range_walk() saw.
struct RangeTotals {
  uint64_t entered = 0;  ///< Nodes entered by the box ranges.
  uint64_t found = 0;    ///< Primitives the box ranges overlap.
  int culled = 0;        ///< Nodes culled by the shrinking nearest ranges.
};

// The shared range check of a structure built over p.bounds (walk_range
// with `ids` node ids): 300 random box ranges report every primitive they
// overlap (== brute force), each at most once, enter each node at most once;
// 300 nearest-box ranges find the brute-force nearest distance.
template <class Structure>
void check_range_walk(const Structure& s, const Prims& p, Rng& rng, const rayscope::Bounds3& world,
                      size_t ids, RangeTotals& totals) {
  using namespace rayscope;
  for (int i = 0; i < 300; ++i) {
    const Vec3 c = to_f(to_d(world.lo) +
                        to_d(world.extent()) * DVec3(rng.uniform(), rng.uniform(), rng.uniform()));
    const Vec3 h = to_f(rng.log_uniform(0.01, 0.3) * to_d(world.extent()) *
                        DVec3(rng.uniform(), rng.uniform(), rng.uniform()));
    BoxRange range{Bounds3(c - h, c + h)};
    CountingObserver obs(ids, 0);
    std::vector<int> reported(p.bounds.size(), 0);
    std::vector<uint32_t> found, want;
    s.walk_range(
        range,
        [&](uint32_t q) {
          reported.at(q)++;
          if (range.overlaps(p.bounds[q])) found.push_back(q);
        },
        obs);
    for (uint32_t q = 0; q < p.bounds.size(); ++q)
      if (range.overlaps(p.bounds[q])) want.push_back(q);
    std::sort(found.begin(), found.end());
    ASSERT_EQ(found, want) << "range " << i;
    for (int v : reported) ASSERT_LE(v, 1) << "a primitive reported twice, range " << i;
    for (size_t n = 0; n < ids; ++n) {
      ASSERT_LE(obs.nodes[n], 1) << "a node entered twice, range " << i;
      if (obs.nodes[n]) {
        ASSERT_EQ(obs.box_tests[n], 1) << "node " << n << " entered untested";
      }
    }
    for (int v : obs.nodes) totals.entered += uint64_t(v);
    totals.found += want.size();
  }
  for (int i = 0; i < 300; ++i) {
    NearestRange range{
        to_f(to_d(world.lo) +
             to_d(world.extent()) * DVec3(rng.uniform(), rng.uniform(), rng.uniform()))};
    CountingObserver obs(ids, 0);
    s.walk_range(
        range,
        [&](uint32_t q) { range.radius = std::min(range.radius, range.distance(p.bounds[q])); },
        obs);
    float want = kInfinity;
    for (const Bounds3& b : p.bounds) want = std::min(want, range.distance(b));
    ASSERT_EQ(range.radius, want) << "nearest, point " << i;
    totals.culled += obs.culled;
  }
}

}  // namespace rstest
