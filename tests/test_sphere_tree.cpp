// The hierarchy of bounding spheres (sphere_tree.h) behind the aggregate:
// the smallest sphere of a triangle (acute, right, obtuse, degenerate), the
// exact merge of two spheres, builder invariants (every node's sphere holds
// its children's and its primitives' spheres, each primitive once), bad and
// degenerate input, scene queries == brute force and == the BVH bit for bit
// on random and adversarial rays, what the observer sees, range queries ==
// brute force, the teaching view, and renders == the BVH's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "accel_test_util.h"
#include "rayscope/accel/accel_view.h"
#include "rayscope/render.h"
#include "rayscope/scene_io.h"
#include "rayscope_vtk/mesh_files.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::max_abs;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

double dist(const Vec3& a, const Vec3& b) {
  return glm::length(to_d(a) - to_d(b));
}

// Whether `outer` contains `inner`, in double from the float values.
bool contains(const BoundingSphere& outer, const BoundingSphere& inner) {
  return dist(outer.center, inner.center) + double(inner.radius) <= double(outer.radius);
}

// --- The smallest sphere of a triangle ---------------------------------------

void expect_min_sphere(const Vec3& a, const Vec3& b, const Vec3& c, double want_radius,
                       const char* what) {
  const BoundingSphere s = min_triangle_sphere(a, b, c);
  for (const Vec3& v : {a, b, c})
    EXPECT_LE(dist(s.center, v), double(s.radius)) << what << ": a vertex outside";
  EXPECT_GE(double(s.radius), want_radius) << what;
  EXPECT_LE(double(s.radius), want_radius * (1.0 + 1e-6) + 1e-30) << what << ": not minimal";
}

TEST(SphereTree, SmallestTriangleSphere) {
  // Equilateral (acute): the circumsphere, radius side / sqrt(3).
  expect_min_sphere(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, std::sqrt(3.0f), 0), 2.0 / std::sqrt(3.0),
                    "equilateral");
  // Acute, off axis and in 3D: circumradius abc / (4 area).
  {
    const Vec3 a(1, 2, 3), b(4, 2.5f, 3.5f), c(2.5f, 5, 2);
    const DVec3 A = to_d(a), B = to_d(b), C = to_d(c);
    const double la = glm::length(B - C), lb = glm::length(A - C), lc = glm::length(A - B);
    const double area = 0.5 * glm::length(glm::cross(B - A, C - A));
    ASSERT_GT(glm::dot(B - A, C - A), 0.0);
    ASSERT_GT(glm::dot(A - B, C - B), 0.0);
    ASSERT_GT(glm::dot(A - C, B - C), 0.0);
    expect_min_sphere(a, b, c, la * lb * lc / (4.0 * area), "acute 3D");
  }
  // Right angle: the hypotenuse's sphere (also the circumsphere).
  expect_min_sphere(Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(0, 4, 0), 2.5, "right");
  // Obtuse: the longest edge's sphere, smaller than the circumsphere (whose
  // radius here is about 50).
  expect_min_sphere(Vec3(-5, 0, 0), Vec3(5, 0, 0), Vec3(0, 0.25f, 0), 5.0, "obtuse");
  {
    const BoundingSphere s = min_triangle_sphere(Vec3(-5, 0, 0), Vec3(5, 0, 0), Vec3(0, 0.25f, 0));
    EXPECT_EQ(s.center, Vec3(0, 0, 0));
  }
  // Degenerate: collinear (a segment), two vertices equal, a point.
  expect_min_sphere(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(3, 3, 3), std::sqrt(27.0) / 2, "collinear");
  expect_min_sphere(Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(1, 4, 0), 2.0, "two equal vertices");
  const BoundingSphere point = min_triangle_sphere(Vec3(7, 8, 9), Vec3(7, 8, 9), Vec3(7, 8, 9));
  EXPECT_EQ(point.center, Vec3(7, 8, 9));
  EXPECT_EQ(point.radius, 0.0f);
  // Random triangles over many scales: the vertices are inside, and the
  // radius is the largest of the circumradius (acute) or half the longest
  // edge, up to rounding.
  Rng rng(61);
  for (int i = 0; i < 20000; ++i) {
    const DVec3 c(rng.log_uniform_signed(1e-3, 1e4), rng.log_uniform_signed(1e-3, 1e4),
                  rng.log_uniform_signed(1e-3, 1e4));
    const double s = rng.log_uniform(1e-4, 10);
    const Vec3 v[3] = {to_f(c + s * rng.in_unit_ball()), to_f(c + s * rng.in_unit_ball()),
                       to_f(c + s * rng.in_unit_ball())};
    const BoundingSphere sp = min_triangle_sphere(v[0], v[1], v[2]);
    double longest = 0.0;
    for (int k = 0; k < 3; ++k) {
      ASSERT_LE(dist(sp.center, v[k]), double(sp.radius)) << "triangle " << i;
      longest = std::max(longest, dist(v[k], v[(k + 1) % 3]));
    }
    // No sphere holding two points is smaller than half their distance; the
    // smallest of an acute triangle is its circumsphere, at most 2/sqrt(3)
    // times that.
    const double slack = 1e-5 * (max_abs(c) + s);
    ASSERT_GE(double(sp.radius), 0.5 * longest - slack) << "triangle " << i;
    ASSERT_LE(double(sp.radius), longest / std::sqrt(3.0) + slack) << "triangle " << i;
  }
}

TEST(SphereTree, ExactMergeOfTwoSpheres) {
  const BoundingSphere a{Vec3(0, 0, 0), 1.0f}, b{Vec3(4, 0, 0), 1.0f};
  const BoundingSphere m = enclosing_sphere(a, b);
  EXPECT_TRUE(contains(m, a) && contains(m, b));
  EXPECT_NEAR(m.radius, 3.0f, 1e-6f);
  EXPECT_NEAR(m.center.x, 2.0f, 1e-6f);
  // One inside the other: the larger one, unchanged.
  const BoundingSphere big{Vec3(1, 1, 1), 5.0f}, small{Vec3(2, 1, 1), 0.5f};
  EXPECT_EQ(enclosing_sphere(big, small).radius, 5.0f);
  EXPECT_EQ(enclosing_sphere(big, big).radius, 5.0f);
  EXPECT_EQ(enclosing_sphere(small, big).center, big.center);
  Rng rng(62);
  for (int i = 0; i < 20000; ++i) {
    const BoundingSphere p{to_f(DVec3(rng.log_uniform_signed(1e-3, 1e5),
                                      rng.log_uniform_signed(1e-3, 1e5), rng.uniform(-1, 1))),
                           rstest::round_f(rng.log_uniform(1e-6, 1e3))};
    const BoundingSphere q{to_f(to_d(p.center) + rng.log_uniform(1e-6, 1e4) * rng.unit_vector()),
                           rstest::round_f(rng.log_uniform(1e-6, 1e3))};
    const BoundingSphere m2 = enclosing_sphere(p, q);
    ASSERT_TRUE(contains(m2, p) && contains(m2, q)) << "pair " << i;
    // Minimal: the merged diameter is the spread of the two along their axis.
    const double want =
        std::max({double(p.radius), double(q.radius),
                  0.5 * (dist(p.center, q.center) + double(p.radius) + double(q.radius))});
    ASSERT_LE(double(m2.radius), want * (1 + 1e-6) + 1e-6 * max_abs(to_d(p.center))) << i;
  }
}

// --- Builder invariants -------------------------------------------------------

std::vector<BoundingSphere> random_spheres(Rng& rng, int n, rstest::BoxLayout layout) {
  const rstest::Prims p = rstest::random_boxes(rng, n, layout);
  std::vector<BoundingSphere> s;
  for (const Bounds3& b : p.bounds)
    s.push_back({b.center(), rstest::round_f(0.5 * glm::length(to_d(b.extent())))});
  return s;
}

// Structure: children after their parent, each node reached once; every
// node's sphere holds its children's; every leaf's holds its primitives'
// spheres and has 1 .. max_leaf_size of them (more only past the cost depth
// with coincident centers: never here, see DegenerateInput); each primitive
// in exactly one leaf; depth within the stack.
void check_invariants(const SphereTree& t, const std::vector<BoundingSphere>& s) {
  ASSERT_EQ(t.empty(), s.empty());
  ASSERT_EQ(t.prim_indices.size(), s.size());
  if (s.empty()) return;
  std::vector<int> seen(s.size(), 0), reached(t.nodes.size(), 0);
  reached[0] = 1;
  for (size_t i = 0; i < t.nodes.size(); ++i) {
    const SphereNode& n = t.nodes[i];
    ASSERT_TRUE(all_finite(n.center) && std::isfinite(n.radius) && n.radius >= 0.0f);
    if (n.is_leaf()) {
      ASSERT_LE(size_t(n.index) + n.count, s.size());
      for (uint32_t k = n.index; k < n.index + n.count; ++k) {
        const uint32_t p = t.prim_indices[k];
        ASSERT_LT(p, s.size());
        seen[p]++;
        ASSERT_TRUE(contains(n.sphere(), s[p])) << "leaf " << i << ", primitive " << p;
      }
    } else {
      ASSERT_GT(n.index, i);
      ASSERT_LT(size_t(n.index) + 1, t.nodes.size());
      for (uint32_t c : {n.index, n.index + 1}) {
        reached[c]++;
        ASSERT_TRUE(contains(n.sphere(), t.nodes[c].sphere()))
            << "node " << i << " (" << ::testing::PrintToString(n.center) << ", " << n.radius
            << "), child " << c << " (" << ::testing::PrintToString(t.nodes[c].center) << ", "
            << t.nodes[c].radius << ")";
      }
    }
  }
  for (int v : seen) ASSERT_EQ(v, 1) << "each primitive in exactly one leaf";
  for (int v : reached) ASSERT_EQ(v, 1);
  const SphereTreeQuality q = t.quality();
  EXPECT_LT(q.depth, uint32_t(SphereTree::kStackSize));
  EXPECT_EQ(q.nodes, 2 * q.leaves - 1);
}

TEST(SphereTree, BuildInvariantsOnRandomSpheres) {
  Rng rng(63);
  for (auto layout : {rstest::BoxLayout::Uniform, rstest::BoxLayout::Clustered,
                      rstest::BoxLayout::Coincident, rstest::BoxLayout::LogUniform})
    for (int n : {1, 2, 3, 5, 100, 3000}) {
      const std::vector<BoundingSphere> s = random_spheres(rng, n, layout);
      SphereTree t;
      t.build(s);
      check_invariants(t, s);
      if (layout != rstest::BoxLayout::Coincident) {
        const SphereTreeQuality q = t.quality();
        EXPECT_LE(q.max_leaf_prims, t.config.max_leaf_size);
      }
    }
  // Other settings: a leaf per primitive, many bins, a cost depth of 0 (the
  // object median everywhere).
  SphereTreeBuildConfig cfg;
  cfg.max_leaf_size = 1;
  cfg.bins = SphereTree::kMaxBins;
  const std::vector<BoundingSphere> s = random_spheres(rng, 2000, rstest::BoxLayout::Clustered);
  SphereTree t;
  t.build(s, cfg);
  check_invariants(t, s);
  EXPECT_EQ(t.quality().leaves, 2000u);
  cfg = {};
  cfg.max_depth = 0;
  t.build(s, cfg);
  check_invariants(t, s);
  EXPECT_LE(t.quality().depth, 12u) << "median cuts halve: depth about log2(2000 / 4)";
}

TEST(SphereTree, BadInputIsRefused) {
  SphereTree t;
  const float nan = std::nan("");
  for (const BoundingSphere& bad :
       {BoundingSphere{Vec3(nan, 0, 0), 1.0f}, BoundingSphere{Vec3(0, 0, 0), nan},
        BoundingSphere{Vec3(0, kInfinity, 0), 1.0f}, BoundingSphere{Vec3(0, 0, 0), kInfinity},
        BoundingSphere{Vec3(0, 0, 0), -1.0f}}) {
    const std::vector<BoundingSphere> s = {{Vec3(1, 2, 3), 1.0f}, bad};
    try {
      t.build(s);
      FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("primitive 1"), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
  SphereTreeBuildConfig cfg;
  cfg.bins = 1;
  EXPECT_THROW(t.build({}, cfg), std::invalid_argument);
  cfg = {};
  cfg.max_leaf_size = 0;
  EXPECT_THROW(t.build({}, cfg), std::invalid_argument);
}

TEST(SphereTree, DegenerateInput) {
  SphereTree t;
  t.build({});
  EXPECT_TRUE(t.empty());
  float tmax = kInfinity;
  NullTraversalObserver obs;
  EXPECT_FALSE(t.traverse<false>(
      Ray{Vec3(0), Vec3(1, 0, 0), kInfinity}, tmax, [](uint32_t, float&) { return true; }, obs));
  // All primitives at one point with radius 0, and all with one center: no
  // plane separates them, the object median does (no leaf over the limit).
  for (float r : {0.0f, 2.0f}) {
    const std::vector<BoundingSphere> s(1000, BoundingSphere{Vec3(1, 2, 3), r});
    t.build(s);
    check_invariants(t, s);
    EXPECT_LE(t.quality().max_leaf_prims, t.config.max_leaf_size);
    EXPECT_EQ(t.sphere().center, Vec3(1, 2, 3));
    EXPECT_EQ(t.sphere().radius, r) << "the merge of equal spheres is that sphere";
  }
  // Zero-size spheres on a line, and exponentially spread ones (a chain).
  std::vector<BoundingSphere> line;
  for (int i = 0; i < 500; ++i) line.push_back({Vec3(float(i), 0, 0), 0.0f});
  for (int j = -30; j <= 30; ++j)
    for (int k = 0; k < 200; ++k)
      line.push_back({Vec3(std::pow(17.0f, float(j)) * (1.0f + 1e-3f * float(k)), 0, 0), 1e-20f});
  t.build(line);
  check_invariants(t, line);
}

// --- Queries through the aggregate ------------------------------------------

void commit_spheres(Scene& scene) {
  AccelConfig ac;
  ac.kind = AccelKind::Spheres;
  scene.commit(ac);
  ASSERT_EQ(scene.accel().kind(), AccelKind::Spheres);
  ASSERT_TRUE(scene.accel().walks_structure());
  ASSERT_FALSE(scene.accel().structure_as<SphereTree>().empty());
}

TEST(SphereTree, RandomRaysMatchBruteForce) {
  Rng rng(64);
  Scene scene = rstest::soup_scene(rng);
  commit_spheres(scene);
  std::vector<Ray> rays;
  rstest::add_random_rays(rng, scene, scene.bvh().bounds(), 20000, rays);
  rstest::check_queries(scene, rays, "spheres: meshes + soup + spheres + plane", 0);
}

// Rays that stress the walk: through vertices and edge midpoints (exact ties),
// along mesh edges, tangent to node spheres (and starting on them), axis
// parallel through node centers, starting inside, and grazing the spheres.
std::vector<Ray> adversarial_rays(Rng& rng, const Scene& scene) {
  std::vector<Ray> rays;
  rstest::add_mesh_rays(rng, scene, rays);
  const SphereTree& t = scene.accel().structure_as<SphereTree>();
  const Bounds3 world = t.sphere().box();
  for (size_t i = 0; i < t.nodes.size() && rays.size() < 40000; i += 3) {
    const SphereNode& n = t.nodes[i];
    const DVec3 nrm = rng.unit_vector();
    const DVec3 tan = glm::normalize(glm::cross(nrm, rng.unit_vector()));
    const DVec3 p = to_d(n.center) + double(n.radius) * nrm;
    rays.push_back(Ray{to_f(p - 3.0 * double(n.radius) * tan), to_f(tan), kInfinity});
    rays.push_back(Ray{to_f(p), to_f(rng.unit_vector()), kInfinity});
    for (int a = 0; a < 3; ++a)
      rstest::add_plane_rays(rng, world, a, n.center[a], rays, true, &n.center);
  }
  rstest::add_inside_and_grazing_rays(rng, scene, world, 3000, rays);
  return rays;
}

TEST(SphereTree, AdversarialRaysMatchBruteForce) {
  Rng rng(65);
  Scene scene = rstest::soup_scene(rng);
  scene.meshes.push_back(rstest::unit_cube(Vec3(7, 0, 0)));
  commit_spheres(scene);
  const std::vector<Ray> rays = adversarial_rays(rng, scene);
  rstest::check_queries(scene, rays, "spheres: adversarial rays", 20);
}

TEST(SphereTree, SameHitsAsTheBvhBitForBit) {
  Rng rng(66);
  Scene scene = rstest::soup_scene(rng);
  scene.meshes.push_back(rstest::unit_cube(Vec3(7, 0, 0)));
  commit_spheres(scene);
  std::vector<Ray> rays = adversarial_rays(rng, scene);
  scene.commit();
  rstest::add_random_rays(rng, scene, scene.bvh().bounds(), 5000, rays);
  std::vector<PrimHit> bvh(rays.size());
  std::vector<uint8_t> bvh_occluded(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    scene.intersect(rays[i], bvh[i]);
    bvh_occluded[i] = scene.occluded(rays[i]);
  }
  commit_spheres(scene);
  for (size_t i = 0; i < rays.size(); ++i) {
    PrimHit h;
    scene.intersect(rays[i], h);
    ASSERT_TRUE(rstest::same_bits(h, bvh[i])) << "ray " << i;
    ASSERT_EQ(scene.occluded(rays[i]), bool(bvh_occluded[i])) << "ray " << i;
  }
}

TEST(SphereTree, EachPrimitiveTestedOncePerRayAndTheObserverSeesTheWalk) {
  // Every ray tests each primitive at most once, enters each node at most
  // once, tests the root's sphere and both children's spheres of every inner
  // node entered; early termination culls; the tree prunes far below brute
  // force, but tests more than the BVH (spheres fit worse than boxes).
  Rng rng(67);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 3));
  scene.meshes.push_back(make_torus(Vec3(2.5f, 0.0f, 0.0f), 1.0f, 0.3f, 48, 24));
  commit_spheres(scene);
  const SphereTree& t = scene.accel().structure_as<SphereTree>();
  const size_t prims = scene.accel().records().size();
  uint64_t tests = 0, culls = 0, bvh_tests = 0;
  const int n_rays = 3000;
  std::vector<Ray> rays;
  for (int i = 0; i < n_rays; ++i) {
    // From 6 away toward a point near the objects: most rays hit.
    const DVec3 o = 6.0 * rng.unit_vector(), target = DVec3(1.2, 0, 0) + 1.5 * rng.in_unit_ball();
    rays.push_back(Ray{to_f(o), to_f(target - o), kInfinity});
  }
  for (int i = 0; i < n_rays; ++i) {
    for (int any = 0; any < 2; ++any) {
      rstest::CountingObserver obs(t.nodes.size(), prims);
      PrimHit hit;
      if (any)
        scene.occluded(rays[i], obs);
      else
        scene.intersect(rays[i], hit, obs);
      for (int v : obs.prim_tests) ASSERT_LE(v, 1) << "ray " << i << (any ? " (any hit)" : "");
      for (int v : obs.nodes) ASSERT_LE(v, 1) << "a node entered twice, ray " << i;
      if (any) continue;
      for (int v : obs.prim_tests) tests += uint64_t(v);
      culls += uint64_t(obs.culled);
      int want = 1;
      for (size_t n = 0; n < obs.nodes.size(); ++n)
        if (obs.nodes[n] && !t.nodes[n].is_leaf()) want += 2;
      EXPECT_EQ(obs.boxes, want);
      for (size_t n = 0; n < obs.nodes.size(); ++n) {
        ASSERT_LE(obs.box_tests[n], 1);
        if (obs.nodes[n]) {
          ASSERT_EQ(obs.box_tests[n], 1) << "node " << n << " entered untested";
        }
      }
    }
  }
  // The BVH, for comparison, built with the sphere tree's cost constants and
  // leaf limit, so that the two differ in their bounding volumes only.
  AccelConfig bvh_config;
  bvh_config.bvh.traversal_cost = SphereTreeBuildConfig{}.traversal_cost;
  bvh_config.bvh.intersection_cost = SphereTreeBuildConfig{}.intersection_cost;
  bvh_config.bvh.max_leaf_size = SphereTreeBuildConfig{}.max_leaf_size;
  scene.commit(bvh_config);
  for (const Ray& r : rays) {
    rstest::CountingObserver obs(scene.bvh().nodes.size() + 8, prims);
    PrimHit hit;
    scene.intersect(r, hit, obs);
    for (int v : obs.prim_tests) bvh_tests += uint64_t(v);
  }
  std::printf("spheres: %.1f of %zu primitives tested per ray (BVH %.1f), %llu culls\n",
              double(tests) / n_rays, prims, double(bvh_tests) / n_rays, (unsigned long long)culls);
  EXPECT_LT(tests, uint64_t(n_rays) * prims / 10);
  EXPECT_GT(tests, bvh_tests) << "a sphere fits worse than a box";
  EXPECT_GT(culls, 0u);
}

TEST(SphereTree, RangeQueriesMatchBruteForce) {
  // Box, sphere and k-nearest queries through the sphere tree give what the
  // brute-force aggregate (none) gives, in the same order, and the walk
  // enters only part of the tree.
  Rng rng(68);
  Scene scene = rstest::soup_scene(rng);
  AccelConfig none;
  none.kind = AccelKind::None;
  scene.commit(none);
  const Bounds3 world = scene.bvh().bounds();
  struct Query {
    int kind;
    Bounds3 box;
    Vec3 p;
    float r;
    uint32_t k;
  };
  std::vector<Query> queries;
  for (int i = 0; i < 600; ++i) {
    const Vec3 c = rstest::point_in(rng, world);
    const Vec3 h = to_f(rng.log_uniform(0.01, 0.3) * to_d(world.extent()) *
                        DVec3(rng.uniform(), rng.uniform(), rng.uniform()));
    queries.push_back({i % 3, Bounds3(c - h, c + h), c, rstest::round_f(rng.log_uniform(0.01, 3)),
                       uint32_t(rng.integer(1, 20))});
  }
  // Queries touching primitives exactly: a point on a triangle vertex, a
  // box whose face is a sphere's tangent plane.
  const TriangleMesh& m = scene.meshes[0];
  for (size_t v = 0; v < m.positions.size(); v += 37) {
    queries.push_back({1, {}, m.positions[v], 0.0f, 1});
    queries.push_back({0, Bounds3(m.positions[v]), {}, 0.0f, 1});
  }
  for (const Sphere& s : scene.spheres) {
    const Vec3 top = s.center + Vec3(0, s.radius, 0);
    queries.push_back({0, Bounds3(top, top + Vec3(1)), {}, 0.0f, 1});
  }
  auto run = [&](const Query& q, auto& obs) {
    return q.kind == 0   ? scene.accel().query_box(q.box, obs)
           : q.kind == 1 ? scene.accel().query_sphere(q.p, q.r, obs)
                         : scene.accel().nearest(q.p, q.k, obs);
  };
  std::vector<std::vector<RangeHit>> want;
  for (const Query& q : queries) {
    NullTraversalObserver obs;
    want.push_back(run(q, obs));
  }
  commit_spheres(scene);
  const SphereTree& t = scene.accel().structure_as<SphereTree>();
  uint64_t entered = 0, found = 0, culled = 0;
  for (size_t i = 0; i < queries.size(); ++i) {
    rstest::CountingObserver obs(t.nodes.size(), scene.accel().records().size());
    const std::vector<RangeHit> got = run(queries[i], obs);
    ASSERT_EQ(got, want[i]) << "query " << i << " (kind " << queries[i].kind << ")";
    for (int v : obs.prim_tests) ASSERT_LE(v, 1);
    for (int v : obs.nodes) entered += uint64_t(v);
    found += got.size();
    culled += uint64_t(obs.culled);
  }
  EXPECT_GT(found, queries.size());
  EXPECT_LT(entered, queries.size() * t.nodes.size() / 4);
  EXPECT_GT(culled, 0u) << "k nearest: nodes pushed before the range shrank are skipped";
}

TEST(SphereTree, BallTestsOfRanges) {
  // A ball touching a box face, just off it, containing it, around a corner.
  const Bounds3 box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  EXPECT_TRUE(ball_overlaps_box({Vec3(2, 0.5f, 0.5f), 1.0f}, box));
  EXPECT_FALSE(ball_overlaps_box({Vec3(2.01f, 0.5f, 0.5f), 1.0f}, box));
  EXPECT_TRUE(ball_overlaps_box({Vec3(0.5f), 0.01f}, box));
  EXPECT_FALSE(ball_overlaps_box({Vec3(2, 2, 2), 1.7f}, box));  // corner at sqrt(3) = 1.732
  EXPECT_TRUE(ball_overlaps_box({Vec3(2, 2, 2), 1.74f}, box));
  EXPECT_EQ(point_ball_distance(Vec3(0.5f), {Vec3(0), 1.0f}), 0.0f);
  EXPECT_NEAR(point_ball_distance(Vec3(3, 4, 0), {Vec3(0), 1.0f}), 4.0f, 1e-5f);
  EXPECT_LE(point_ball_distance(Vec3(3, 4, 0), {Vec3(0), 1.0f}), 4.0f) << "never above";
}

// --- Names, storage, view, renders --------------------------------------------

TEST(SphereTree, KindStorageViewAndMemory) {
  AccelKind k = AccelKind::Bvh;
  ASSERT_TRUE(parse_accel_kind("spheres", k));
  EXPECT_EQ(k, AccelKind::Spheres);
  EXPECT_STREQ(to_string(AccelKind::Spheres), "spheres");
  EXPECT_EQ(accel_storage_error(AccelKind::Spheres, PrimStorage::EveryCell), "");
  for (PrimStorage s : {PrimStorage::SmallestCell, PrimStorage::Split}) {
    const std::string e = accel_storage_error(AccelKind::Spheres, s);
    EXPECT_NE(e.find("spheres"), std::string::npos) << e;
    EXPECT_NE(e.find("once"), std::string::npos) << e;
  }
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 3));
  scene.spheres.push_back(Sphere{"s", Vec3(3, 0, 0), 0.5f, 0});
  AccelConfig ac;
  ac.kind = AccelKind::Spheres;
  ac.storage = PrimStorage::SmallestCell;
  EXPECT_THROW(scene.commit(ac), std::invalid_argument);
  commit_spheres(scene);
  const Aggregate& a = scene.accel();
  EXPECT_TRUE(a.structure_as<BvhWalk>().walk().empty());
  EXPECT_EQ(a.memory_bytes(), a.bvh().quality().memory_bytes +
                                  a.structure_as<SphereTree>().memory_bytes() +
                                  a.records().size() * sizeof(PrimRecord));
  const AccelFigures f = a.figures();
  EXPECT_EQ(f.nodes, a.structure_as<SphereTree>().nodes.size());
  EXPECT_EQ(f.refs_per_prim, 1.0);
  EXPECT_EQ(f.memory_bytes,
            a.structure_as<SphereTree>().memory_bytes() + a.records().size() * sizeof(PrimRecord));
  // The view: one node per tree node, with its sphere and the sphere's box;
  // the primitives each leaf holds by global id, each once.
  const AccelView v = make_accel_view(a);
  EXPECT_STREQ(v.structure, "spheres");
  ASSERT_EQ(v.nodes.size(), a.structure_as<SphereTree>().nodes.size());
  std::vector<int> seen(a.records().size(), 0);
  for (size_t i = 0; i < v.nodes.size(); ++i) {
    const AccelViewNode& n = v.nodes[i];
    ASSERT_TRUE(n.sphere.has_value());
    EXPECT_EQ(n.sphere->center, a.structure_as<SphereTree>().nodes[i].center);
    EXPECT_TRUE(n.box.contains(n.sphere->center + Vec3(n.sphere->radius)));
    EXPECT_TRUE(n.box.contains(n.sphere->center - Vec3(n.sphere->radius)));
    EXPECT_EQ(n.leaf, a.structure_as<SphereTree>().nodes[i].is_leaf());
    for (uint32_t r = n.first; r < n.first + n.count; ++r) seen.at(v.refs.at(r))++;
  }
  for (int s : seen) EXPECT_EQ(s, 1);
  EXPECT_EQ(v.depth, int(a.structure_as<SphereTree>().quality().depth) + 1);
}

void expect_same_render(Scene scene, const RenderSettings& rs) {
  scene.commit();
  const Framebuffer bvh = render(scene, rs);
  commit_spheres(scene);
  const Framebuffer sp = render(scene, rs);
  auto same = [](const auto& a, const auto& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
  };
  EXPECT_TRUE(same(sp.color, bvh.color));
  EXPECT_TRUE(same(sp.depth, bvh.depth));
  EXPECT_TRUE(same(sp.normal, bvh.normal));
  EXPECT_TRUE(same(sp.object_id, bvh.object_id));
}

TEST(SphereTree, DefaultSceneRendersLikeTheBvh) {
  expect_same_render(make_default_scene(), rstest::small_render(160, 120, 2));
}

TEST(SphereTree, BunnySceneRendersLikeTheBvh) {
  const std::filesystem::path file =
      std::filesystem::path(RAYSCOPE_SOURCE_DIR) / "data/scenes/bunny.json";
  LoadedScene ls = load_scene(file.string(), rayscope_vtk::load_mesh);
  expect_same_render(std::move(ls.scene), rstest::small_render(160, 120, 2));
}

}  // namespace
