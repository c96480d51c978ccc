// Shared fixtures of the acceleration-structure tests (test_accel_conformance,
// test_aggregate, test_bvh, test_wide_bvh and the per-structure files): random
// primitive boxes, leaf functions whose primitives are the boxes themselves,
// brute force over a committed scene (rays and range queries), the check of a
// scene's queries against it, the test scenes, adversarial rays made from any
// structure's teaching view, and the list of structure x storage cases.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "rayscope/accel/accel_view.h"
#include "rayscope/render.h"
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

/// Whether tube segment j of `ts` and point j of `ps` are traced (Scene::commit
/// leaves the others out; test_invalid_input checks that rule).
inline bool traced_segment(const rayscope::TubeSet& ts, size_t j) {
  return ts.traced(j);
}
inline bool traced_point(const rayscope::PointSet& ps, size_t j) {
  return ps.traced(j);
}

/// The closest hit of a loop over every triangle, tube segment, point, sphere
/// and plane of a committed scene in order, with the tests' own range checks:
/// a triangle at exactly the closest t so far replaces it (intersect_triangle
/// accepts t == tmax), a segment, point, sphere or plane does not. That loop
/// defines the tie rule.
struct BruteHit {
  float t = rayscope::kInfinity;
  /// Global primitive index (triangles, tube segments, points, spheres).
  uint32_t prim = ~0u;
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
  // A segment, point or sphere hit at ts (tested up to tmax inclusive):
  // closer, or a tie that the primitive found first keeps.
  auto other = [&](bool hit, float ts) {
    if (hit) {
      if (ts == tmax && best.prim != ~0u) {
        best.tie = true;
      } else if (ts < tmax) {
        tmax = ts;
        best.t = ts;
        best.prim = id;
      }
    }
    ++id;
  };
  for (const TubeSet& tubes : s.tubes)
    for (size_t j = 0; j < tubes.segments.size(); ++j) {
      float ts = 0.0f;
      const bool hit = traced_segment(tubes, j) &&
                       intersect_capsule(ray, tubes.positions[tubes.segments[j].x],
                                         tubes.positions[tubes.segments[j].y],
                                         tubes.segment_radius(j), next_float_up(tmax), ts);
      other(hit, ts);
    }
  for (const PointSet& points : s.points)
    for (size_t j = 0; j < points.positions.size(); ++j) {
      float ts = 0.0f;
      const bool hit = traced_point(points, j) &&
                       intersect_sphere(ray, points.positions[j], points.point_radius(j),
                                        next_float_up(tmax), ts);
      other(hit, ts);
    }
  for (const rayscope::Sphere& sp : s.spheres) {
    float ts = 0.0f;
    const bool hit = intersect_sphere(ray, sp.center, sp.radius, next_float_up(tmax), ts);
    other(hit, ts);
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

/// Lines drawn as tubes and points drawn as spheres, with the ties they
/// make: a helix polyline (radii per position, colors), a soup of 300 random
/// segments of lengths 0 to 2 (some of length 0), two identical capsules (exact
/// ties between them), a cloud of 300 points (radii per position), a point
/// that is also a sphere and one at a capsule's end with its radius (exact
/// ties between a point, a sphere and a capsule's cap), around a small mesh
/// and a floor.
inline rayscope::Scene tube_scene(Rng& rng) {
  using namespace rayscope;
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f, 0.0f, 0.0f), 1.0f, 2));
  TubeSet helix;
  helix.name = "helix";
  for (int i = 0; i <= 120; ++i) {
    const double a = 0.15 * i;
    helix.positions.push_back(to_f(DVec3(2.5 * std::cos(a), -3.0 + 0.05 * i, 2.5 * std::sin(a))));
    helix.radii.push_back(float(0.1 + 0.1 * rng.uniform()));
    helix.colors.push_back(Vec3(float(rng.uniform()), 0.5f, float(rng.uniform())));
    if (i > 0) helix.segments.push_back({uint32_t(i - 1), uint32_t(i)});
  }
  scene.tubes.push_back(helix);
  TubeSet soup;
  soup.name = "segments";
  soup.radius = 0.05f;
  for (uint32_t i = 0; i < 300; ++i) {
    const DVec3 c(rng.uniform(-6, 6), rng.uniform(-6, 6), rng.uniform(-6, 6));
    const double len = i % 10 == 0 ? 0.0 : rng.log_uniform(0.01, 2);
    soup.positions.push_back(to_f(c));
    soup.positions.push_back(to_f(c + len * rng.unit_vector()));
    soup.segments.push_back({2 * i, 2 * i + 1});
  }
  // The same capsule twice: every hit on it is an exact tie.
  soup.positions.push_back(Vec3(-4, 4, -4));
  soup.positions.push_back(Vec3(-2, 4.5f, -3));
  soup.segments.push_back({600, 601});
  soup.segments.push_back({600, 601});
  scene.tubes.push_back(soup);
  PointSet cloud;
  cloud.name = "cloud";
  for (int i = 0; i < 300; ++i) {
    cloud.positions.push_back(
        to_f(DVec3(rng.uniform(-6, 6), rng.uniform(-6, 6), rng.uniform(-6, 6))));
    cloud.radii.push_back(rstest::round_f(rng.log_uniform(0.02, 0.3)));
  }
  // A point that is also a sphere, one at the twin capsules' end with their
  // radius: ties between the kinds.
  cloud.positions.push_back(Vec3(4, -4, 4));
  cloud.radii.push_back(0.5f);
  cloud.positions.push_back(Vec3(-4, 4, -4));
  cloud.radii.push_back(0.05f);
  scene.points.push_back(cloud);
  scene.spheres.push_back(Sphere{"twin", Vec3(4, -4, 4), 0.5f, 0});
  scene.planes.push_back(Plane{"floor", Vec3(0, -7, 0), Vec3(0, 1, 0), 0});
  return scene;
}

/// Rays at the tube scene's ties: through the twin capsules, the point that
/// is also a sphere and the point on the capsules' end, from all around.
inline void add_tube_tie_rays(Rng& rng, std::vector<rayscope::Ray>& rays) {
  using namespace rayscope;
  const DVec3 targets[] = {{-3, 4.25, -3.5}, {4, -4, 4}, {-4, 4, -4}, {-2, 4.5, -3}};
  for (const DVec3& t : targets)
    for (int k = 0; k < 40; ++k) {
      const Vec3 o = to_f(t + 6.0 * rng.unit_vector());
      rays.push_back(Ray{o, to_f(t + 0.02 * rng.in_unit_ball() - to_d(o)), kInfinity});
    }
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

/// n rays starting inside `world`, every other one short (tmax below 2), 20
/// rays tangent to each of the scene's spheres, and 4 tangent to each of the
/// first 200 traced tube segments (their sides and caps) and points.
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
  // A ray in the tangent plane at a point of a capsule's surface (its
  // normal there is nrm), through that point.
  auto tangent_rays = [&](const DVec3& p, const DVec3& nrm, double r) {
    const DVec3 t = glm::normalize(glm::cross(nrm, rng.unit_vector()));
    rays.push_back(Ray{to_f(p - 5.0 * r * t), to_f(t), kInfinity});
  };
  int budget = 200;
  for (const TubeSet& ts : scene.tubes)
    for (size_t j = 0; j < ts.segments.size() && budget > 0; ++j) {
      if (!traced_segment(ts, j)) continue;
      --budget;
      const DVec3 a = to_d(ts.positions[ts.segments[j].x]);
      const DVec3 b = to_d(ts.positions[ts.segments[j].y]);
      const double r = ts.segment_radius(j);
      const DVec3 axis = b - a;
      for (int k = 0; k < 4; ++k) {
        DVec3 nrm = rng.unit_vector();
        DVec3 base = k < 2 ? a : b;  // caps: the ends' balls beyond their planes
        if (glm::dot(axis, axis) > 0.0) {
          const DVec3 u = glm::normalize(axis);
          if (k % 2 == 0) {  // the side: a normal across the axis, a point along it
            nrm = glm::normalize(nrm - glm::dot(nrm, u) * u);
            base = a + rng.uniform() * axis;
          } else if ((glm::dot(nrm, u) > 0.0) == (k < 2)) {
            nrm = -nrm;
          }
        }
        tangent_rays(base + r * nrm, nrm, r);
      }
    }
  for (const PointSet& ps : scene.points)
    for (size_t j = 0; j < ps.positions.size() && budget > 0; ++j) {
      if (!traced_point(ps, j)) continue;
      --budget;
      const DVec3 nrm = rng.unit_vector();
      tangent_rays(to_d(ps.positions[j]) + double(ps.point_radius(j)) * nrm, nrm,
                   ps.point_radius(j));
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
// `ids` node ids: every primitive tested at most once (with `pieces`: at most
// pieces[p] times, split storage's fragments), every node entered at most
// once. `check(obs, any_hit)` adds the structure's own checks (it
// may use gtest assertions). Callers stop on HasFatalFailure().
template <class Check>
void mailbox_rays(const rayscope::Scene& scene, Rng& rng, int n_rays, size_t ids,
                  MailboxTotals& totals, Check&& check, const std::vector<int>* pieces = nullptr) {
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
        ASSERT_LE(obs.prim_tests[p], pieces ? (*pieces)[p] : 1)
            << "ray " << i << (any ? " (any hit)" : "");
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

// --- Structure x storage: the cases every structure test runs ------------------

/// One structure with one way of storing primitives (AccelConfig::kind and
/// ::storage); every other setting at its default.
struct AccelCase {
  rayscope::AccelKind kind;
  rayscope::PrimStorage storage;
  rayscope::AccelConfig config() const {
    rayscope::AccelConfig c;
    c.kind = kind;
    c.storage = storage;
    return c;
  }
  /// "kdtree_smallest_cell": the structure and the storage, as a test name.
  std::string name() const {
    std::string n = std::string(rayscope::to_string(kind)) + "_" + rayscope::to_string(storage);
    std::replace(n.begin(), n.end(), '-', '_');
    return n;
  }
};

/// Every structure (rayscope::kAccelKinds) with every storage it takes: the
/// pairs rayscope::accel_storage_error() accepts, the product's one rule.
inline std::vector<AccelCase> accel_cases() {
  std::vector<AccelCase> out;
  for (rayscope::AccelKind kind : rayscope::kAccelKinds)
    for (rayscope::PrimStorage storage : rayscope::kPrimStorages)
      if (rayscope::accel_storage_error(kind, storage).empty()) out.push_back({kind, storage});
  return out;
}

/// Whether commit() refuses `kind` with `storage` through the one check
/// (accel_storage_error(), in build_accel()): std::invalid_argument whose
/// message is that check's line. The builders themselves take only what it
/// accepts.
inline ::testing::AssertionResult storage_refused(rayscope::AccelKind kind,
                                                  rayscope::PrimStorage storage) {
  const std::string line = rayscope::accel_storage_error(kind, storage);
  if (line.empty()) return ::testing::AssertionFailure() << "the check accepts it";
  rayscope::Scene scene;
  scene.meshes.push_back(rayscope::make_icosphere(rayscope::Vec3(0.0f), 1.0f, 1));
  rayscope::AccelConfig ac;
  ac.kind = kind;
  ac.storage = storage;
  try {
    scene.commit(ac);
  } catch (const std::invalid_argument& e) {
    if (e.what() == line) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "message \"" << e.what() << "\", not \"" << line << '"';
  }
  return ::testing::AssertionFailure() << "no exception";
}

/// Whether the structure is a spatial subdivision (it takes smallest-cell
/// storage: cells that a primitive can straddle), again by the product's rule.
inline bool subdivides_space(rayscope::AccelKind kind) {
  return rayscope::accel_storage_error(kind, rayscope::PrimStorage::SmallestCell).empty();
}

/// Whether a teaching view is a flat set of cells under one box (the grid's:
/// the cells, then their box as the root with the last id): its cells are
/// entered from the box without box tests of their own.
inline bool flat_view(const rayscope::AccelView& v) {
  return v.depth == 2 && !v.nodes.empty() && v.nodes.back().parent == -1;
}

/// The bounds of a scene's bounded primitives (finite triangle corners, traced
/// tube segments and points, spheres).
inline rayscope::Bounds3 scene_bounds(const rayscope::Scene& scene) {
  rayscope::Bounds3 b;
  for (const rayscope::TriangleMesh& m : scene.meshes)
    for (const rayscope::Vec3& p : m.positions)
      if (rayscope::all_finite(p)) b.extend(p);
  for (const rayscope::TubeSet& ts : scene.tubes)
    for (size_t j = 0; j < ts.segments.size(); ++j)
      if (traced_segment(ts, j))
        b.extend(rayscope::capsule_bounds(ts.positions[ts.segments[j].x],
                                          ts.positions[ts.segments[j].y], ts.segment_radius(j)));
  for (const rayscope::PointSet& ps : scene.points)
    for (size_t j = 0; j < ps.positions.size(); ++j)
      if (traced_point(ps, j)) {
        b.extend(ps.positions[j] - rayscope::Vec3(ps.point_radius(j)));
        b.extend(ps.positions[j] + rayscope::Vec3(ps.point_radius(j)));
      }
  for (const rayscope::Sphere& s : scene.spheres) {
    b.extend(s.center - rayscope::Vec3(s.radius));
    b.extend(s.center + rayscope::Vec3(s.radius));
  }
  return b;
}

/// Rays that stress the walk of the structure the scene was committed with,
/// made from its teaching view (so the same for every structure): for at most
/// about `max_nodes` of its nodes, rays lying in each face plane of the node's
/// box (a kD-tree's, grid's or octree's cuts; loose boxes' faces for
/// smallest-cell) and in the planes through its middle (an octree's cuts),
/// leaving them, crossing them from outside; rays through two box corners
/// (cell corners and edges); for a BSP node the plane of its polygon (lying
/// in it, leaving it, across it, grazing it); for a sphere tree node rays
/// tangent to its sphere and starting on it.
inline void add_view_rays(Rng& rng, const rayscope::Scene& scene, std::vector<rayscope::Ray>& rays,
                          size_t max_nodes = stress_scaled(2000)) {
  using namespace rayscope;
  const AccelView v = make_accel_view(scene.accel());
  Bounds3 world = scene_bounds(scene);
  for (const AccelViewNode& n : v.nodes) world.extend(n.box);
  const size_t stride = std::max<size_t>(1, v.nodes.size() / max_nodes);
  auto corner = [&](const Bounds3& b) {
    return Vec3(rng.coin() ? b.lo.x : b.hi.x, rng.coin() ? b.lo.y : b.hi.y,
                rng.coin() ? b.lo.z : b.hi.z);
  };
  for (size_t i = 0; i < v.nodes.size(); i += stride) {
    const AccelViewNode& n = v.nodes[i];
    const Bounds3& box = n.box;
    if (!(box.lo.x <= box.hi.x)) continue;  // an empty box
    const Vec3 mid = 0.5f * box.lo + 0.5f * box.hi;
    const int a = rng.integer(0, 2);
    add_plane_rays(rng, world, a, box.lo[a], rays, true, &mid);
    add_plane_rays(rng, world, a, box.hi[a], rays, false);
    add_plane_rays(rng, world, rng.integer(0, 2), mid[a], rays, true, &mid);
    const Vec3 c0 = corner(box),
               c1 = corner(v.nodes[size_t(rng.integer(0, int(v.nodes.size()) - 1))].box);
    if (c0 != c1 && all_finite(c1)) rays.push_back(Ray{c0 - 1.5f * (c1 - c0), c1 - c0, kInfinity});
    if (n.polygon_count >= 3) {
      DVec3 centre(0.0), nrm(0.0);
      for (uint32_t k = 0; k < n.polygon_count; ++k) {
        const DVec3 p = to_d(v.polygon_vertices[n.polygon_first + k]);
        const DVec3 q = to_d(v.polygon_vertices[n.polygon_first + (k + 1) % n.polygon_count]);
        centre += p;
        nrm += glm::cross(p, q);  // Newell's normal
      }
      centre /= double(n.polygon_count);
      if (glm::length(nrm) > 0.0) {
        nrm = glm::normalize(nrm);
        const DVec3 r = rng.unit_vector();
        const DVec3 in_plane = glm::normalize(r - glm::dot(r, nrm) * nrm);
        rays.push_back(Ray{to_f(centre), to_f(in_plane), kInfinity});           // lying in it
        rays.push_back(Ray{to_f(centre), to_f(rng.unit_vector()), kInfinity});  // leaving it
        rays.push_back(Ray{to_f(centre - 3.0 * nrm), to_f(nrm), kInfinity});    // across it
        rays.push_back(Ray{to_f(centre + 1e-3 * in_plane - 2.0 * in_plane + 1e-6 * nrm),
                           to_f(in_plane + 1e-7 * nrm), kInfinity});  // grazing it
      }
    }
    if (n.sphere) {
      const DVec3 nrm = rng.unit_vector();
      const DVec3 tan = glm::normalize(glm::cross(nrm, rng.unit_vector()));
      const DVec3 p = to_d(n.sphere->center) + double(n.sphere->radius) * nrm;
      rays.push_back(Ray{to_f(p - 3.0 * double(n.sphere->radius) * tan), to_f(tan), kInfinity});
      rays.push_back(Ray{to_f(p), to_f(rng.unit_vector()), kInfinity});
    }
  }
}

/// The adversarial rays of a committed scene: at vertices and edges
/// (add_mesh_rays), at the walked structure's cells, planes and spheres
/// (add_view_rays), from inside and grazing spheres.
inline std::vector<rayscope::Ray> adversarial_rays(Rng& rng, const rayscope::Scene& scene) {
  std::vector<rayscope::Ray> rays;
  add_mesh_rays(rng, scene, rays);
  add_view_rays(rng, scene, rays);
  add_inside_and_grazing_rays(rng, scene, scene_bounds(scene), int(stress_scaled(3000)), rays);
  return rays;
}

// --- Scenes -----------------------------------------------------------------

/// A closed, lumpy mesh of 20 * 4^level triangles (level 5: 20,480) that
/// stands in for a scanned one (the Stanford bunny): an icosphere pushed in
/// and out by a few waves and jittered vertex by vertex (seeded), so that its
/// triangles differ in size and shape; about 2 x 1.6 x 1.8 around the origin.
inline rayscope::TriangleMesh lumpy_mesh(int level = 5) {
  using namespace rayscope;
  TriangleMesh m = make_icosphere(Vec3(0.0f), 1.0f, level);
  m.name = "lumpy";
  m.normals.clear();
  Rng rng(2024);
  const double edge = 4.0 / double(1 << level);
  for (Vec3& p : m.positions) {
    const DVec3 u = glm::normalize(to_d(p));
    const double r = 1.0 + 0.22 * std::sin(3.0 * u.x + 1.0) * std::cos(2.0 * u.y) +
                     0.12 * std::sin(5.0 * u.z + 2.0 * u.x) + 0.05 * std::cos(9.0 * u.y);
    const DVec3 q = r * u + 0.15 * edge * rng.in_unit_ball();
    p = to_f(DVec3(1.0 * q.x, 0.8 * q.y, 0.9 * q.z));
  }
  return m;
}

/// The default scene with lumpy_mesh(level) in place of its torus (the bunny
/// scene's mix: a mesh beside a mirror and a glass sphere over a checkered,
/// reflective floor, a point and a directional light).
inline rayscope::Scene lumpy_scene(int level = 5) {
  using namespace rayscope;
  Scene s = make_default_scene();
  TriangleMesh m = lumpy_mesh(level);
  for (Vec3& p : m.positions) p = 0.8f * p + Vec3(1.9f, 0.7f, -0.9f);
  m.material = s.meshes.at(0).material;
  s.meshes = {std::move(m)};
  return s;
}

/// Whether two renders are the same bit for bit (color, depth, normals,
/// object ids); otherwise a gtest failure naming `what`.
inline ::testing::AssertionResult same_image(const rayscope::Framebuffer& a,
                                             const rayscope::Framebuffer& b) {
  auto same = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
  };
  if (!same(a.color, b.color)) return ::testing::AssertionFailure() << "colors differ";
  if (!same(a.depth, b.depth)) return ::testing::AssertionFailure() << "depths differ";
  if (!same(a.normal, b.normal)) return ::testing::AssertionFailure() << "normals differ";
  if (!same(a.object_id, b.object_id)) return ::testing::AssertionFailure() << "object ids differ";
  return ::testing::AssertionSuccess();
}

// --- Range queries against brute force ----------------------------------------
// Brute force: a loop over the scene's objects (triangles mesh by mesh, tube
// segments, points, then spheres: global primitive indices; then planes),
// with the exact tests.

inline std::vector<rayscope::RangeHit> brute_box(const rayscope::Scene& s,
                                                 const rayscope::Bounds3& bx) {
  using namespace rayscope;
  std::vector<RangeHit> out;
  uint32_t id = 0;
  for (const TriangleMesh& m : s.meshes)
    for (const glm::uvec3& t : m.triangles) {
      if (triangle_overlaps_box(m.positions[t.x], m.positions[t.y], m.positions[t.z], bx))
        out.push_back({id, -1, 0.0f});
      ++id;
    }
  for (const TubeSet& ts : s.tubes)
    for (size_t j = 0; j < ts.segments.size(); ++j, ++id)
      if (traced_segment(ts, j) &&
          capsule_overlaps_box(ts.positions[ts.segments[j].x], ts.positions[ts.segments[j].y],
                               ts.segment_radius(j), bx))
        out.push_back({id, -1, 0.0f});
  for (const PointSet& ps : s.points)
    for (size_t j = 0; j < ps.positions.size(); ++j, ++id)
      if (traced_point(ps, j) && sphere_overlaps_box(ps.positions[j], ps.point_radius(j), bx))
        out.push_back({id, -1, 0.0f});
  for (const Sphere& sp : s.spheres) {
    if (sphere_overlaps_box(sp.center, sp.radius, bx)) out.push_back({id, -1, 0.0f});
    ++id;
  }
  const std::vector<PlaneRecord>& planes = s.accel().plane_records();  // unit normals
  for (size_t k = 0; k < planes.size(); ++k)
    if (plane_overlaps_box(planes[k].point, planes[k].normal, bx))
      out.push_back({~0u, int(k), 0.0f});
  return out;
}

/// Every object with its distance from p, nearest first.
inline std::vector<rayscope::RangeHit> brute_distances(const rayscope::Scene& s,
                                                       const rayscope::Vec3& p) {
  using namespace rayscope;
  std::vector<RangeHit> out;
  uint32_t id = 0;
  for (const TriangleMesh& m : s.meshes)
    for (const glm::uvec3& t : m.triangles)
      out.push_back(
          {id++, -1,
           point_triangle_distance(p, m.positions[t.x], m.positions[t.y], m.positions[t.z])});
  for (const TubeSet& ts : s.tubes)
    for (size_t j = 0; j < ts.segments.size(); ++j, ++id)
      if (traced_segment(ts, j))
        out.push_back(
            {id, -1,
             point_capsule_distance(p, ts.positions[ts.segments[j].x],
                                    ts.positions[ts.segments[j].y], ts.segment_radius(j))});
  for (const PointSet& ps : s.points)
    for (size_t j = 0; j < ps.positions.size(); ++j, ++id)
      if (traced_point(ps, j))
        out.push_back({id, -1, point_sphere_distance(p, ps.positions[j], ps.point_radius(j))});
  for (const Sphere& sp : s.spheres)
    out.push_back({id++, -1, point_sphere_distance(p, sp.center, sp.radius)});
  const std::vector<PlaneRecord>& planes = s.accel().plane_records();  // unit normals
  for (size_t k = 0; k < planes.size(); ++k)
    out.push_back({~0u, int(k), point_plane_distance(p, planes[k].point, planes[k].normal)});
  std::sort(out.begin(), out.end(), nearer);
  return out;
}

inline std::vector<rayscope::RangeHit> brute_sphere(const rayscope::Scene& s,
                                                    const rayscope::Vec3& c, float r) {
  std::vector<rayscope::RangeHit> all = brute_distances(s, c);
  all.erase(std::find_if(all.begin(), all.end(),
                         [r](const rayscope::RangeHit& h) { return h.distance > r; }),
            all.end());
  return all;
}

inline std::vector<rayscope::RangeHit> brute_knn(const rayscope::Scene& s, const rayscope::Vec3& p,
                                                 uint32_t k) {
  std::vector<rayscope::RangeHit> all = brute_distances(s, p);
  if (all.size() > k) all.resize(k);
  return all;
}

struct RangeQueries {
  std::vector<rayscope::Bounds3> boxes;
  std::vector<std::pair<rayscope::Vec3, float>> spheres;
  std::vector<std::pair<rayscope::Vec3, uint32_t>> knn;
};

/// A point in `world` enlarged by a tenth on every side.
inline rayscope::Vec3 random_point(Rng& rng, const rayscope::Bounds3& world) {
  const DVec3 e = to_d(world.extent());
  return to_f(to_d(world.lo) - 0.1 * e +
              1.2 * e * DVec3(rng.uniform(), rng.uniform(), rng.uniform()));
}

/// Random, touching, zero-size and huge ranges about a scene: boxes of sizes
/// over four decades, points and segments, flat boxes, boxes from a vertex,
/// one box holding everything; spheres of random radius, of radius 0 at
/// vertices, inside spheres and at random points, and one holding everything;
/// k nearest for k = 1, a few, n, more than n, at random points, at vertices
/// and at sphere centers.
inline RangeQueries make_range_queries(Rng& rng, const rayscope::Scene& scene, int n) {
  using namespace rayscope;
  Bounds3 world;
  std::vector<Vec3> vertices;
  for (const TriangleMesh& m : scene.meshes)
    for (const Vec3& p : m.positions) {
      world.extend(p);
      vertices.push_back(p);
    }
  // Tube ends and points are the "vertices" of those sets: a box or range at
  // one touches the primitives there.
  for (const TubeSet& ts : scene.tubes)
    for (const Vec3& p : ts.positions)
      if (all_finite(p)) vertices.push_back(p);
  for (const PointSet& ps : scene.points)
    for (const Vec3& p : ps.positions)
      if (all_finite(p)) vertices.push_back(p);
  world.extend(scene_bounds(scene));
  for (const Sphere& s : scene.spheres) {
    world.extend(s.center - Vec3(s.radius));
    world.extend(s.center + Vec3(s.radius));
  }
  const float size = max_component(world.extent());
  auto vertex = [&] { return vertices[size_t(rng.integer(0, int(vertices.size()) - 1))]; };
  RangeQueries q;
  for (int i = 0; i < n; ++i) {
    const Vec3 c = random_point(rng, world);
    const DVec3 h = size * rng.log_uniform(1e-4, 0.3) *
                    DVec3(rng.uniform(0.1, 1), rng.uniform(0.1, 1), rng.uniform(0.1, 1));
    q.boxes.push_back(Bounds3(to_f(to_d(c) - h), to_f(to_d(c) + h)));
    q.boxes.push_back(Bounds3(random_point(rng, world)));  // a point
    Bounds3 flat(to_f(to_d(c) - h), to_f(to_d(c) + h));
    const int axis = rng.integer(0, 2);
    flat.lo[axis] = flat.hi[axis];
    q.boxes.push_back(flat);
    const Vec3 v = vertex();
    q.boxes.push_back(Bounds3(v));                          // a vertex: its triangles touch it
    q.boxes.push_back(Bounds3(v, v + Vec3(size * 0.01f)));  // a box from a vertex
    Bounds3 seg(v);
    seg.hi[axis] += size * 0.05f;
    q.boxes.push_back(seg);  // a segment
    q.spheres.push_back({c, float(size * rng.log_uniform(1e-4, 0.3))});
    q.spheres.push_back({vertex(), 0.0f});
    q.spheres.push_back({random_point(rng, world), 0.0f});
    q.knn.push_back({random_point(rng, world), 1});
    q.knn.push_back({random_point(rng, world), uint32_t(rng.integer(2, 40))});
    q.knn.push_back({vertex(), uint32_t(rng.integer(1, 8))});
  }
  for (const Sphere& s : scene.spheres) {
    q.spheres.push_back({s.center, 0.0f});  // inside: distance 0
    q.knn.push_back({s.center, 3});
    q.boxes.push_back(Bounds3(s.center));
    const Vec3 top = s.center + Vec3(0, s.radius, 0);  // a box whose face is a tangent plane
    q.boxes.push_back(Bounds3(top, top + Vec3(1)));
  }
  const float huge = 1e30f;
  Bounds3 all;
  all.lo = Vec3(-huge);
  all.hi = Vec3(huge);
  q.boxes.push_back(all);
  q.spheres.push_back({world.center(), huge});
  uint32_t objects = uint32_t(scene.spheres.size() + scene.planes.size());
  for (const TriangleMesh& m : scene.meshes) objects += uint32_t(m.triangles.size());
  q.knn.push_back({world.center(), objects});
  q.knn.push_back({random_point(rng, world), objects + 7});
  q.knn.push_back({random_point(rng, world), std::numeric_limits<uint32_t>::max()});
  return q;
}

/// Checks the range walk contract as the walk goes: a node is entered only
/// after its box was tested and overlapped (the root's included), and at
/// most once; what overlapped is entered or culled, once; each primitive is
/// tested at most once (mailboxing where a primitive is stored several times).
/// A flat view's box (the grid's) is tested and leads to its cells without
/// being entered.
struct ContractObserver : rayscope::TraversalHooks {
  static constexpr bool kActive = true;
  enum : uint8_t { kNone, kOverlapped, kEntered, kCulled };
  std::vector<uint8_t> node_state, prim_tests;
  uint32_t overlaps = 0, entered = 0, culls = 0;
  uint32_t box_only = ~0u;  ///< A box tested but never entered (flat_view()'s root).
  explicit ContractObserver(const rayscope::AccelView& v) {
    if (flat_view(v)) box_only = uint32_t(v.nodes.size() - 1);
  }
  static uint8_t& at(std::vector<uint8_t>& v, uint32_t i) {
    if (i >= v.size()) v.resize(size_t(i) * 2 + 16, 0);
    return v[i];
  }
  void on_box_test(uint32_t node, bool hit) {
    uint8_t& st = at(node_state, node);
    EXPECT_EQ(st, kNone) << "node " << node << " tested twice";
    if (hit && node == box_only)
      st = kEntered;
    else if (hit)
      st = kOverlapped, ++overlaps;
  }
  void on_node(uint32_t node) {
    uint8_t& st = at(node_state, node);
    EXPECT_EQ(st, kOverlapped) << "node " << node << " entered without an overlapping box";
    st = kEntered;
    ++entered;
  }
  void on_cull(uint32_t node) {
    uint8_t& st = at(node_state, node);
    EXPECT_EQ(st, kOverlapped) << "node " << node << " culled but not pushed";
    st = kCulled;
    ++culls;
  }
  void on_prim_test(uint32_t prim) {
    EXPECT_EQ(at(prim_tests, prim)++, 0) << "prim " << prim << " tested twice";
  }
  void finish(const std::string& what) const {
    EXPECT_EQ(entered + culls, overlaps) << what << ": overlapped nodes neither entered nor culled";
  }
};

/// The committed scene's box, sphere and k-nearest queries == brute force
/// (the same objects in the same order, distances bit for bit); observed
/// queries == plain ones and keep the walk contract (ContractObserver).
inline void check_range_queries(const rayscope::Scene& scene, const RangeQueries& q,
                                const std::string& what) {
  using namespace rayscope;
  const Aggregate& a = scene.accel();
  const AccelView view = make_accel_view(a);
  size_t found = 0;
  for (size_t i = 0; i < q.boxes.size(); ++i) {
    const std::vector<RangeHit> want = brute_box(scene, q.boxes[i]);
    ContractObserver obs(view);
    const std::vector<RangeHit> got = a.query_box(q.boxes[i], obs);
    obs.finish(what);
    ASSERT_EQ(got, want) << what << ", box " << i;
    ASSERT_EQ(a.query_box(q.boxes[i]), got) << what << ", box " << i;
    found += got.size();
  }
  for (size_t i = 0; i < q.spheres.size(); ++i) {
    const auto& [c, r] = q.spheres[i];
    const std::vector<RangeHit> want = brute_sphere(scene, c, r);
    ContractObserver obs(view);
    const std::vector<RangeHit> got = a.query_sphere(c, r, obs);
    obs.finish(what);
    EXPECT_EQ(obs.culls, 0u) << what << ": a sphere range does not shrink";
    ASSERT_EQ(got, want) << what << ", sphere " << i << " radius " << r;
    ASSERT_EQ(a.query_sphere(c, r), got) << what << ", sphere " << i;
    found += got.size();
  }
  for (size_t i = 0; i < q.knn.size(); ++i) {
    const auto& [p, k] = q.knn[i];
    const std::vector<RangeHit> want = brute_knn(scene, p, k);
    ContractObserver obs(view);
    const std::vector<RangeHit> got = a.nearest(p, k, obs);
    obs.finish(what);
    ASSERT_EQ(got, want) << what << ", knn " << i << " k " << k;
    ASSERT_EQ(a.nearest(p, k), got) << what << ", knn " << i;
  }
  std::printf("%s: %zu boxes, %zu spheres, %zu k-nearest; %zu objects found by box and sphere\n",
              what.c_str(), q.boxes.size(), q.spheres.size(), q.knn.size(), found);
  EXPECT_GT(found, q.boxes.size() + q.spheres.size()) << what;
}

// --- One structure's own settings ---------------------------------------------

/// How often a walk may test each primitive (by global id) per query: once,
/// or with split storage once per fragment (its references in the view).
inline std::vector<int> prim_pieces(const rayscope::Aggregate& a) {
  std::vector<int> pieces(a.object_count(), 1);
  if (a.storage() == rayscope::PrimStorage::Split) {
    std::fill(pieces.begin(), pieces.end(), 0);
    for (uint32_t id : rayscope::make_accel_view(a).refs) pieces.at(id)++;
  }
  return pieces;
}

/// The conformance checks (test_accel_conformance) for a setting that is one
/// structure's own (a split rule, a loose factor, a grid resolution), for
/// that structure's file: on the soup scene with a cube, random rays,
/// adversarial rays (from the structure's view, plus what `extra` adds from
/// the structure's own API) == brute force and == the BVH bit for bit; on the
/// sliver scene every primitive tested at most once per ray (once per
/// fragment for split storage) and every node entered at most once, closest
/// and any hit; range queries == brute force under the walk contract.
template <class Extra>
void check_setting(const rayscope::AccelConfig& config, const std::string& what, Rng& rng,
                   Extra&& extra) {
  using namespace rayscope;
  Scene scene = soup_scene(rng);
  scene.meshes.push_back(unit_cube(Vec3(7, 0, 0)));
  scene.commit(config);
  std::vector<Ray> rays = adversarial_rays(rng, scene);
  extra(scene, rays);
  add_random_rays(rng, scene, scene_bounds(scene), int(stress_scaled(4000)), rays);
  const std::vector<PrimHit> hits =
      check_queries(scene, rays, what.c_str(), stress_scale() < 1.0 ? 2 : 20);
  if (::testing::Test::HasFailure()) return;
  rstest::check_range_queries(scene, make_range_queries(rng, scene, 10), what);
  if (::testing::Test::HasFailure()) return;
  scene.commit();
  for (size_t i = 0; i < rays.size(); ++i) {
    PrimHit h;
    scene.intersect(rays[i], h);
    ASSERT_TRUE(same_bits(h, hits[i])) << what << ": not the BVH's hit, ray " << i;
  }
  Scene slivers = sliver_scene(rng);
  slivers.commit(config);
  const std::vector<int> pieces = prim_pieces(slivers.accel());
  MailboxTotals totals;
  mailbox_rays(
      slivers, rng, int(stress_scaled(1000)), make_accel_view(slivers.accel()).nodes.size(), totals,
      [](const CountingObserver&, bool) {}, &pieces);
}
inline void check_setting(const rayscope::AccelConfig& config, const std::string& what, Rng& rng) {
  check_setting(config, what, rng, [](const rayscope::Scene&, std::vector<rayscope::Ray>&) {});
}

}  // namespace rstest
