// The hierarchy of bounding spheres (sphere_tree.h): the smallest sphere of
// a triangle (acute, right, obtuse, degenerate), the exact merge of two
// spheres, builder invariants (every node's sphere holds its children's and
// its primitives' spheres, each primitive once), bad and degenerate input,
// that it tests more than a BVH (spheres fit worse), the ball tests of
// ranges, the storage check, the teaching view and memory. What every
// structure does (queries == brute force and == the BVH, rays tangent to its
// spheres, the observer, range queries, images) is test_accel_conformance's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "accel_test_util.h"
#include "rayscope/accel/accel_view.h"

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

// --- Its own walk ---------------------------------------------------------------

TEST(SphereTree, PrunesButTestsMoreThanTheBvh) {
  // The tree prunes far below brute force, but tests more primitives than a
  // BVH built with the sphere tree's cost constants and leaf limit (the two
  // differ in their bounding volumes only): a sphere fits worse than a box.
  // (Each primitive once, nodes once, the child spheres of each node entered,
  // culls: test_accel_conformance.)
  Rng rng(67);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 3));
  scene.meshes.push_back(make_torus(Vec3(2.5f, 0.0f, 0.0f), 1.0f, 0.3f, 48, 24));
  const int n_rays = 3000;
  std::vector<Ray> rays;
  for (int i = 0; i < n_rays; ++i) {
    // From 6 away toward a point near the objects: most rays hit.
    const DVec3 o = 6.0 * rng.unit_vector(), target = DVec3(1.2, 0, 0) + 1.5 * rng.in_unit_ball();
    rays.push_back(Ray{to_f(o), to_f(target - o), kInfinity});
  }
  auto tests = [&](const AccelConfig& config) {
    scene.commit(config);
    const size_t ids = make_accel_view(scene.accel()).nodes.size();
    uint64_t n = 0;
    for (const Ray& r : rays) {
      rstest::CountingObserver obs(ids, scene.accel().records().size());
      PrimHit hit;
      scene.intersect(r, hit, obs);
      n += obs.tested().size();
    }
    return n;
  };
  AccelConfig spheres;
  spheres.kind = AccelKind::Spheres;
  AccelConfig bvh;
  bvh.bvh.traversal_cost = SphereTreeBuildConfig{}.traversal_cost;
  bvh.bvh.intersection_cost = SphereTreeBuildConfig{}.intersection_cost;
  bvh.bvh.max_leaf_size = SphereTreeBuildConfig{}.max_leaf_size;
  const uint64_t sphere_tests = tests(spheres), bvh_tests = tests(bvh);
  const size_t prims = scene.accel().records().size();
  std::printf("spheres: %.1f of %zu primitives tested per ray (BVH %.1f)\n",
              double(sphere_tests) / n_rays, prims, double(bvh_tests) / n_rays);
  EXPECT_LT(sphere_tests, uint64_t(n_rays) * prims / 10);
  EXPECT_GT(sphere_tests, bvh_tests) << "a sphere fits worse than a box";
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

// --- Storage, view, memory ------------------------------------------------------

TEST(SphereTree, StorageViewAndMemory) {
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
  ac.storage = PrimStorage::EveryCell;
  scene.commit(ac);
  const Aggregate& a = scene.accel();
  ASSERT_FALSE(a.structure_as<SphereTree>().empty());
  EXPECT_TRUE(a.structure_as<BvhWalk>().walk().empty());
  // The binary BVH is built when first asked for; from then on the
  // aggregate holds it and counts it.
  const size_t binary = a.bvh().quality().memory_bytes;
  EXPECT_EQ(a.memory_bytes(), binary + a.structure_as<SphereTree>().memory_bytes() +
                                  a.records().size() * (sizeof(PrimRecord) + sizeof(uint32_t)));
  const AccelFigures f = a.figures();
  EXPECT_EQ(f.nodes, a.structure_as<SphereTree>().nodes.size());
  EXPECT_EQ(f.refs_per_prim, 1.0);
  EXPECT_EQ(f.memory_bytes, a.structure_as<SphereTree>().memory_bytes() +
                                a.records().size() * (sizeof(PrimRecord) + sizeof(uint32_t)));
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

}  // namespace
