// The conformance suite of the acceleration structures: every structure
// (rayscope::kAccelKinds) with every way of storing primitives it takes
// (rayscope::accel_storage_error() decides), driven through the public
// Scene / Aggregate API with AccelConfig{kind, storage} and nothing else, runs
// the same tests:
//
//  - closest hit == brute force over all primitives (t bit for bit, the same
//    primitive, exact ties resolved by the loop order), any hit == closest
//    hit found, observed == plain, on random rays and on rays made to stress
//    the walk (in and across the structure's own planes, cells, polygons and
//    spheres, read from its teaching view; at vertices and along edges);
//  - exactly the BVH's hits, bit for bit, and exactly the BVH's images;
//  - the observer sees the walk: nodes entered once, after their box was
//    hit, each primitive tested once (once per fragment for split storage)
//    and held by a node entered, the hit held by the node entered last, the
//    last hit reported is the answer; the structure prunes and culls;
//  - mailboxing: primitives stored many times are still tested once per ray;
//  - range queries (box, sphere, k nearest) == brute force, ties included,
//    under the walk contract; shrinking ranges cull, walks prune;
//  - bad input: non-finite primitives refused or skipped as the scene says,
//    the rest answered; a bad loose factor refused with one line.
//
// A new structure needs no line here: it joins kAccelKinds, and the cases
// follow. What is one structure's own (its builder's invariants, split rules,
// grid resolutions, loose factors, fragments, sphere merges) stays in its file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "accel_test_util.h"
#include "rayscope/accel/accel_view.h"
#include "rayscope/render.h"
#include "rayscope/scene.h"
#include "rayscope/shapes.h"

namespace {

using namespace rayscope;
using rstest::AccelCase;
using rstest::DVec3;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

class AccelConformance : public ::testing::TestWithParam<AccelCase> {
 protected:
  // Commits `scene` with the case's structure and storage.
  void commit(Scene& scene) const {
    scene.commit(GetParam().config());
    ASSERT_EQ(scene.accel().kind(), GetParam().kind);
    ASSERT_EQ(scene.accel().storage(), GetParam().storage);
    ASSERT_EQ(scene.accel().walks_structure(), GetParam().kind != AccelKind::None);
  }
  std::string name() const { return GetParam().name(); }
  // The split storage cuts primitives into fragments that are tested one by
  // one (no mailbox); every other storage tests a primitive at most once per
  // query.
  bool fragments() const { return GetParam().storage == PrimStorage::Split; }
};

INSTANTIATE_TEST_SUITE_P(Conformance, AccelConformance, ::testing::ValuesIn(rstest::accel_cases()),
                         [](const auto& info) { return info.param.name(); });

// --- Rays against brute force ---------------------------------------------------
// Ray counts scale by rstest::stress_scale() (0.1 in sanitizer and unoptimised
// builds, where tracing is 10-50x slower); every check stays the same.

TEST_P(AccelConformance, RandomRaysMatchBruteForce) {
  Rng rng(15);
  Scene scene = rstest::soup_scene(rng);
  commit(scene);
  std::vector<Ray> rays;
  rstest::add_random_rays(rng, scene, rstest::scene_bounds(scene),
                          int(rstest::stress_scaled(20000)), rays);
  rstest::check_queries(scene, rays, (name() + ": meshes + soup + spheres + plane").c_str(), 0);
}

TEST_P(AccelConformance, AdversarialRaysMatchBruteForce) {
  Rng rng(43);
  Scene scene = rstest::soup_scene(rng);
  scene.meshes.push_back(rstest::unit_cube(Vec3(7, 0, 0)));
  commit(scene);
  const std::vector<Ray> rays = rstest::adversarial_rays(rng, scene);
  rstest::check_queries(scene, rays, (name() + ": adversarial rays").c_str(),
                        rstest::stress_scale() < 1.0 ? 2 : 20);
}

TEST_P(AccelConformance, TiesAtVerticesAndEdgesResolveLikeBruteForce) {
  // Rays through the vertices and edge midpoints of closed meshes, and along
  // the axes through an axis-aligned cube's faces, edges and corners: several
  // triangles are hit at exactly the same t, and the winner must not depend
  // on the structure or its walk. Rays lying exactly in a cube face's plane
  // hit the edge of the perpendicular face; the walk must not cull the cell
  // they touch.
  Rng rng(16);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 2));
  scene.meshes.push_back(rstest::unit_cube(Vec3(3, 0, 0)));
  scene.meshes.push_back(make_torus(Vec3(-3.0f, 0.0f, 0.0f), 1.0f, 0.3f, 24, 12));
  scene.spheres.push_back(rayscope::Sphere{"s", Vec3(0, 3, 0), 0.5f, 0});
  commit(scene);
  std::vector<Ray> rays;
  for (const TriangleMesh& m : scene.meshes) {
    for (const Vec3& v : m.positions)
      for (int k = 0; k < 2; ++k) {
        Vec3 o = to_f(to_d(v) + 8.0 * rng.unit_vector());
        rays.push_back(Ray{o, v - o, kInfinity});
      }
    for (const glm::uvec3& t : m.triangles) {
      Vec3 mid = 0.5f * (m.positions[t.x] + m.positions[t.y]);
      Vec3 o = to_f(to_d(mid) + 8.0 * rng.unit_vector());
      rays.push_back(Ray{o, mid - o, kInfinity});
    }
  }
  for (float a : {0.0f, 0.5f, 1.0f})
    for (float b : {0.0f, 0.5f, 1.0f}) {
      rays.push_back(Ray{Vec3(3.0f + a, b, -5.0f), Vec3(0, 0, 1), kInfinity});
      rays.push_back(Ray{Vec3(3.0f + a, b, 6.0f), Vec3(0, 0, -1), kInfinity});
      rays.push_back(Ray{Vec3(3.0f + a, -5.0f, b), Vec3(0, 1, 0), kInfinity});
      rays.push_back(Ray{Vec3(-1.0f, a, b), Vec3(1, 0, 0), kInfinity});
      rays.push_back(Ray{Vec3(3.0f + a, b, -5.0f), Vec3(0.0f, 0.0f, 2.0f), 2.5f});
    }
  rstest::check_queries(scene, rays, (name() + ": vertex, edge and face-plane rays").c_str(), 20);
}

TEST_P(AccelConformance, SameHitsAsTheBvhBitForBit) {
  // The BVH's hits (t, barycentrics, record, primitive, plane) and any-hit
  // answers, for random rays and for the rays that stress this structure.
  Rng rng(44);
  Scene scene = rstest::soup_scene(rng);
  scene.meshes.push_back(rstest::unit_cube(Vec3(7, 0, 0)));
  commit(scene);
  std::vector<Ray> rays = rstest::adversarial_rays(rng, scene);
  rstest::add_random_rays(rng, scene, rstest::scene_bounds(scene), int(rstest::stress_scaled(5000)),
                          rays);
  scene.commit();
  ASSERT_EQ(scene.accel().kind(), AccelKind::Bvh);
  std::vector<PrimHit> bvh(rays.size());
  std::vector<uint8_t> bvh_occluded(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    scene.intersect(rays[i], bvh[i]);
    bvh_occluded[i] = scene.occluded(rays[i]);
  }
  commit(scene);
  for (size_t i = 0; i < rays.size(); ++i) {
    PrimHit h;
    scene.intersect(rays[i], h);
    ASSERT_TRUE(rstest::same_bits(h, bvh[i]))
        << name() << ", ray " << i << ": prim " << h.prim << " t " << h.t << ", the BVH's prim "
        << bvh[i].prim << " t " << bvh[i].t;
    ASSERT_EQ(scene.occluded(rays[i]), bool(bvh_occluded[i])) << name() << ", ray " << i;
  }
}

// --- What the observer sees -------------------------------------------------------

// Logs one query's walk against the structure's teaching view and checks the
// observer contract (traversal.h) as it goes.
struct WalkLog : TraversalHooks {
  static constexpr bool kActive = true;
  const AccelView& view;
  const std::vector<std::vector<uint32_t>>& holders;  // per primitive: the nodes holding it
  const std::vector<int>& pieces;                     // per primitive: references in the view
  bool flat;
  std::vector<int> entered, boxes_tested, box_hit;  // per node
  std::vector<int> tests;                           // per primitive
  std::vector<uint32_t> order, boxed, tested;       // to reset only what was touched
  uint32_t last_hit = ~0u - 1;
  int box_tests = 0, culls = 0, hits_elsewhere = 0;

  WalkLog(const AccelView& v, const std::vector<std::vector<uint32_t>>& h,
          const std::vector<int>& p)
      : view(v),
        holders(h),
        pieces(p),
        flat(rstest::flat_view(v)),
        entered(v.nodes.size()),
        boxes_tested(v.nodes.size()),
        box_hit(v.nodes.size()),
        tests(h.size()) {}
  void reset() {
    for (uint32_t n : order) entered[n] = 0;
    for (uint32_t n : boxed) boxes_tested[n] = box_hit[n] = 0;
    for (uint32_t p : tested) tests[p] = 0;
    order.clear();
    boxed.clear();
    tested.clear();
    last_hit = ~0u - 1;
    box_tests = culls = hits_elsewhere = 0;
  }
  bool holds(uint32_t node, uint32_t prim) const {
    const std::vector<uint32_t>& h = holders[prim];
    return std::find(h.begin(), h.end(), node) != h.end();
  }
  // Held by a node whose box was hit but that is never entered: the loose
  // grid's big list, held by the grid's box.
  bool held_by_a_box_only(uint32_t prim) const {
    for (uint32_t n : holders[prim])
      if (box_hit[n] && !entered[n]) return true;
    return false;
  }
  // Whether the walk may enter or cull node n: its box was hit (a flat
  // view's cells: their grid's box was).
  bool reached(uint32_t n) const {
    const int32_t parent = view.nodes[n].parent;
    return box_hit[n] || (flat && parent >= 0 && box_hit[size_t(parent)]);
  }
  void on_node(uint32_t n) {
    ASSERT_LT(n, view.nodes.size());
    ASSERT_EQ(entered[n]++, 0) << "node " << n << " entered twice";
    order.push_back(n);
    ASSERT_TRUE(reached(n)) << "node " << n << " entered without its box hit";
  }
  void on_box_test(uint32_t n, bool hit) {
    ASSERT_LT(n, view.nodes.size());
    ASSERT_EQ(boxes_tested[n]++, 0) << "the box of node " << n << " tested twice";
    boxed.push_back(n);
    box_hit[n] = hit;
    ++box_tests;
  }
  void on_cull(uint32_t n) {
    ASSERT_LT(n, view.nodes.size());
    ASSERT_TRUE(reached(n)) << "node " << n << " culled but its box was not hit";
    ASSERT_EQ(entered[n], 0) << "node " << n << " culled after it was entered";
    ++culls;
  }
  void on_prim_test(uint32_t p) {
    ASSERT_LT(p, tests.size());
    ASSERT_LT(tests[p], std::max(1, pieces[p])) << "primitive " << p << " tested too often";
    if (tests[p]++ == 0) tested.push_back(p);
  }
  void on_prim_hit(uint32_t p) {
    last_hit = p;
    if (p == kPrimOutsideStructure || order.empty()) return;
    // The leaf that holds it is the node entered last.
    if (!holds(order.back(), p)) {
      ASSERT_TRUE(held_by_a_box_only(p)) << "primitive " << p << " hit, but the node entered last ("
                                         << order.back() << ") does not hold it";
      ++hits_elsewhere;
    }
  }
};

TEST_P(AccelConformance, TheObserverSeesTheWalk) {
  // Rays from all around toward two closed meshes (most hit), each as a
  // closest-hit and an any-hit query with the walk logged against the
  // structure's teaching view.
  Rng rng(67);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 3));
  scene.meshes.push_back(make_torus(Vec3(2.5f, 0.0f, 0.0f), 1.0f, 0.3f, 48, 24));
  commit(scene);
  const Aggregate& a = scene.accel();
  const AccelView view = make_accel_view(a);
  const size_t prims = a.records().size();
  std::vector<std::vector<uint32_t>> holders(prims);
  for (uint32_t n = 0; n < view.nodes.size(); ++n)
    for (uint32_t r = view.nodes[n].first; r < view.nodes[n].first + view.nodes[n].count; ++r)
      holders.at(view.refs[r]).push_back(n);
  const std::vector<int> pieces = rstest::prim_pieces(a);
  std::vector<int> children(view.nodes.size(), 0);
  for (const AccelViewNode& n : view.nodes)
    if (n.parent >= 0) children[size_t(n.parent)]++;
  // The 8-wide BVH enters the tops of its wide nodes only (test_aggregate
  // checks that rule); every other walk with a hierarchy enters each inner
  // node it passes through and tests the boxes of all its children.
  const bool tree_walk =
      a.walks_structure() && !rstest::flat_view(view) && GetParam().kind != AccelKind::Bvh;
  WalkLog log(view, holders, pieces);
  const int n_rays = int(rstest::stress_scaled(2000));
  uint64_t tests = 0, culls = 0, repeated = 0;
  for (int i = 0; i < n_rays; ++i) {
    const DVec3 o = 6.0 * rng.unit_vector(), target = DVec3(1.2, 0, 0) + 1.5 * rng.in_unit_ball();
    const Ray ray{to_f(o), to_f(target - o), kInfinity};
    for (int any = 0; any < 2; ++any) {
      SCOPED_TRACE(::testing::Message() << name() << ", ray " << i << (any ? " (any hit)" : ""));
      log.reset();
      PrimHit hit;
      const bool found = any ? a.occluded(ray, log, &hit) : a.intersect(ray, hit, log);
      if (HasFatalFailure()) return;
      // The last primitive reported hit is the answer.
      if (found) {
        ASSERT_EQ(log.last_hit, hit.plane >= 0 ? kPrimOutsideStructure : hit.prim);
      }
      // Every primitive tested is held by a node entered (or by a box that
      // leads to cells, the loose grid's big list).
      for (uint32_t p : log.tested) {
        bool held = false;
        for (uint32_t n : holders[p]) held |= log.entered[n] > 0 || log.box_hit[n] > 0;
        ASSERT_TRUE(held || !a.walks_structure())
            << "primitive " << p << " tested, held by no node entered";
        repeated += log.tests[p] > 1;
      }
      if (!a.walks_structure()) {  // every primitive, no node
        ASSERT_TRUE(log.order.empty());
        ASSERT_EQ(log.box_tests, 0);
        ASSERT_EQ(log.culls, 0);
        if (!any) {
          ASSERT_EQ(log.tested.size(), prims);
        }
      }
      if (tree_walk && !any) {
        // The root's box, then the box of each child of each inner node entered.
        int want = 1;
        for (uint32_t n : log.order)
          if (!view.nodes[n].leaf) want += children[n];
        ASSERT_EQ(log.box_tests, want) << "box tests";
      }
      if (any) continue;
      tests += log.tested.size();
      culls += uint64_t(log.culls);
    }
  }
  std::printf("%s: %.1f of %zu primitives tested per ray, %llu culls, %llu repeated tests\n",
              name().c_str(), double(tests) / n_rays, prims, (unsigned long long)culls,
              (unsigned long long)repeated);
  if (a.walks_structure()) {
    // A hierarchy tests less than a fifth of the primitives per ray; a flat
    // grid fewer than all (the loose grid's big list holds most of these
    // meshes' triangles at its automatic resolution: the lesson of
    // docs/acceleration.md; test_grid checks its pruning on its own scenes).
    EXPECT_LT(tests, uint64_t(n_rays) * prims / (rstest::flat_view(view) ? 1 : 5))
        << "the structure prunes";
    EXPECT_GT(culls, 0u) << "early termination culls nodes pushed before a closer hit";
  }
  if (fragments()) {
    EXPECT_GT(repeated, 0u) << "fragments cost repeated tests (the test needs cut triangles)";
  }
}

TEST_P(AccelConformance, MailboxTestsEachPrimitiveOncePerRay) {
  // Long thin triangles that straddle many cells: a spatial subdivision
  // stores them many times (every-cell) or keeps them in inner nodes
  // (smallest-cell). Every ray still tests each at most once (once per
  // fragment for split storage), closest and any hit, enters each node at
  // most once, and the structure prunes below brute force.
  Rng rng(45);
  Scene scene = rstest::sliver_scene(rng);
  commit(scene);
  const Aggregate& a = scene.accel();
  const AccelView view = make_accel_view(a);
  const AccelFigures f = a.figures();
  if (rstest::subdivides_space(GetParam().kind)) {
    if (GetParam().storage == PrimStorage::EveryCell) {
      EXPECT_GT(f.refs_per_prim, 1.5) << "the test needs primitives stored several times";
    }
    if (GetParam().storage == PrimStorage::SmallestCell) {
      size_t held_above = 0;
      for (const AccelViewNode& n : view.nodes) held_above += n.leaf ? 0 : n.count;
      EXPECT_GT(held_above, 100u) << "the test needs straddlers held above the leaves";
    }
  }
  const std::vector<int> pieces = rstest::prim_pieces(a);
  const size_t prims = a.records().size();
  // Not scaled down under sanitizers: the counts below (culls above all) need
  // this many rays, and the sliver scene is small.
  const int n_rays = 3000;
  rstest::MailboxTotals t;
  rstest::mailbox_rays(
      scene, rng, n_rays, view.nodes.size(), t, [](const rstest::CountingObserver&, bool) {},
      &pieces);
  if (HasFatalFailure()) return;
  std::printf("%s: %.1f of %zu primitives tested per ray, %.2f references per primitive\n",
              name().c_str(), double(t.tests) / n_rays, prims, f.refs_per_prim);
  if (a.walks_structure()) {
    EXPECT_LT(t.tests, uint64_t(n_rays) * prims / 2) << name();
    EXPECT_GT(t.multi_node_rays, uint64_t(n_rays) / 2) << name();
    EXPECT_GT(t.culls, 0u) << name();
  } else {
    EXPECT_EQ(t.tests, uint64_t(n_rays) * prims) << name();
  }
}

// --- Range queries ----------------------------------------------------------------

TEST_P(AccelConformance, RangeQueriesMatchBruteForce) {
  for (uint32_t seed : {51u, 52u}) {
    Rng rng(seed);
    Scene scene = rstest::soup_scene(rng);
    scene.meshes.push_back(rstest::unit_cube(Vec3(7, 0, 0)));
    commit(scene);
    rstest::check_range_queries(scene, rstest::make_range_queries(rng, scene, 40),
                                name() + ", soup scene");
    if (HasFatalFailure()) return;
  }
}

TEST_P(AccelConformance, TubesAndPointsMatchBruteForce) {
  // Capsules (tube segments) and balls (points) beside triangles, spheres and
  // a plane: every structure finds brute force's hit bit for bit, ties
  // between capsules, points and spheres included, and the BVH's.
  Rng rng(57);
  Scene scene = rstest::tube_scene(rng);
  commit(scene);
  std::vector<Ray> rays = rstest::adversarial_rays(rng, scene);
  rstest::add_tube_tie_rays(rng, rays);
  rstest::add_random_rays(rng, scene, rstest::scene_bounds(scene),
                          int(rstest::stress_scaled(10000)), rays);
  const std::vector<PrimHit> hits =
      rstest::check_queries(scene, rays, (name() + ": tubes and points").c_str(), 20);
  if (HasFailure()) return;
  // Some of the hits are on each kind.
  size_t on_tubes = 0, on_points = 0;
  for (const PrimHit& h : hits)
    if (h.plane < 0 && h.prim != ~0u) {
      const ObjectType type = scene.object_type(scene.prim_object(h.prim));
      on_tubes += type == ObjectType::Tubes;
      on_points += type == ObjectType::Points;
    }
  EXPECT_GT(on_tubes, rays.size() / 50) << name();
  EXPECT_GT(on_points, rays.size() / 50) << name();
  scene.commit();
  for (size_t i = 0; i < rays.size(); ++i) {
    PrimHit h;
    scene.intersect(rays[i], h);
    ASSERT_TRUE(rstest::same_bits(h, hits[i])) << name() << ": not the BVH's hit, ray " << i;
  }
}

TEST_P(AccelConformance, RangeQueriesOnTubesAndPointsMatchBruteForce) {
  Rng rng(58);
  Scene scene = rstest::tube_scene(rng);
  commit(scene);
  rstest::RangeQueries q = rstest::make_range_queries(rng, scene, 20);
  // At the twin capsules' shared end, which a point touches too.
  q.knn.push_back({Vec3(-4, 4, -4), 4});
  q.spheres.push_back({Vec3(-4, 4, -4), 0.0f});
  q.boxes.push_back(Bounds3(Vec3(-4, 4.05f, -4)));
  rstest::check_range_queries(scene, q, name() + ", tubes and points");
}

TEST_P(AccelConformance, RangeQueriesOnAMeshMatchBruteForce) {
  Scene scene = rstest::lumpy_scene();
  commit(scene);
  Rng rng(54);
  rstest::check_range_queries(scene, rstest::make_range_queries(rng, scene, 8),
                              name() + ", lumpy mesh scene");
}

// Degenerate input: every object at one point (spheres of one center,
// triangles collapsed to it, zero-area slivers through it), plus a plane
// through it.
TEST_P(AccelConformance, RangeQueriesOnDegenerateScenesMatchBruteForce) {
  Rng rng(53);
  Scene scene;
  const Vec3 o(1, 2, 3);
  TriangleMesh m;
  m.name = "collapsed";
  for (uint32_t i = 0; i < 40; ++i) {
    m.positions.push_back(o);
    m.positions.push_back(i % 2 ? o : o + to_f(rng.unit_vector()));
    m.positions.push_back(i % 2 ? o : 2.0f * m.positions.back() - o);  // a segment through o
    m.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  scene.meshes.push_back(m);
  for (int i = 0; i < 20; ++i) scene.spheres.push_back(Sphere{"s", o, 0.5f + 0.01f * float(i), 0});
  scene.planes.push_back(Plane{"p", o, Vec3(1, 1, 0), 0});
  commit(scene);
  rstest::RangeQueries q = rstest::make_range_queries(rng, scene, 10);
  q.knn.push_back({o, 5});  // everything at distance 0
  q.spheres.push_back({o, 0.0f});
  q.boxes.push_back(Bounds3(o));
  rstest::check_range_queries(scene, q, name() + ", objects at one point");
}

// Exact ties: six equal spheres at distance 2 along the axes and a plane at
// distance 1 from the origin all lie exactly 1 from it; results order them by
// index, primitives before planes.
TEST_P(AccelConformance, RangeQueryTiesResolvedByIndex) {
  Scene scene;
  const Vec3 centers[6] = {{2, 0, 0}, {-2, 0, 0}, {0, 2, 0}, {0, -2, 0}, {0, 0, 2}, {0, 0, -2}};
  for (const Vec3& c : centers) scene.spheres.push_back(Sphere{"s", c, 1.0f, 0});
  scene.spheres.push_back(Sphere{"far", Vec3(5, 5, 5), 1.0f, 0});
  scene.planes.push_back(Plane{"p", Vec3(0, 0, -1), Vec3(0, 0, 1), 0});
  commit(scene);
  const Aggregate& a = scene.accel();
  const std::vector<RangeHit> k1 = a.nearest(Vec3(0), 1);
  ASSERT_EQ(k1.size(), 1u);
  EXPECT_EQ(k1[0], (RangeHit{0, -1, 1.0f}));
  const std::vector<RangeHit> k7 = a.nearest(Vec3(0), 7);
  ASSERT_EQ(k7.size(), 7u);
  for (uint32_t i = 0; i < 6; ++i) EXPECT_EQ(k7[i], (RangeHit{i, -1, 1.0f}));
  EXPECT_EQ(k7[6], (RangeHit{~0u, 0, 1.0f}));
  EXPECT_EQ(a.query_sphere(Vec3(0), 1.0f), k7);
  EXPECT_EQ(a.query_sphere(Vec3(0), next_float_down(1.0f)).size(), 0u);
  // Every sphere's box touches the box [-1, 1]^3; the plane z = -1 too.
  Bounds3 box;
  box.lo = Vec3(-1);
  box.hi = Vec3(1);
  const std::vector<RangeHit> in_box = a.query_box(box);
  ASSERT_EQ(in_box.size(), 7u);
  EXPECT_EQ(in_box[5].prim, 5u);
  EXPECT_EQ(in_box[6].plane, 0);
}

// A shrinking range culls pushed nodes: over many k-nearest queries, some
// pushed node is skipped when popped (hierarchies; a flat grid visits the
// cells in the range's bounds).
TEST_P(AccelConformance, ShrinkingRangesCull) {
  Rng rng(55);
  Scene scene = rstest::soup_scene(rng);
  commit(scene);
  const AccelView view = make_accel_view(scene.accel());
  if (!scene.accel().walks_structure() || rstest::flat_view(view))
    GTEST_SKIP() << name() << " has no hierarchy to cull";
  rstest::CountingObserver obs(view.nodes.size(), scene.accel().object_count());
  for (int i = 0; i < 200; ++i)
    scene.accel().nearest(to_f(DVec3(rng.uniform(-6, 6), rng.uniform(-6, 6), rng.uniform(-6, 6))),
                          3, obs);
  EXPECT_GT(obs.culled, 0) << name();
}

// The walks prune, on a mesh of the bunny's size (lumpy_mesh(6), 81,920
// triangles): a small box on it enters a small part of the structure and
// tests a small part of the primitives; k = 1 enters fewer nodes than a
// sphere holding everything (which enters every node and tests every box
// once).
TEST_P(AccelConformance, RangeWalksPrune) {
  // How much a walk prunes is a property of a whole mesh of this size (under
  // sanitizers, where building 13 structures over it takes minutes, the
  // walks' contract on a mesh is RangeQueriesOnAMeshMatchBruteForce's).
  if (rstest::stress_scale() < 1.0) GTEST_SKIP() << "pruning is measured in the optimised run";
  Scene scene;
  scene.meshes.push_back(rstest::lumpy_mesh(6));
  commit(scene);
  const Aggregate& a = scene.accel();
  const AccelView view = make_accel_view(a);
  const TriangleMesh& mesh = scene.meshes.at(0);
  const Vec3 v = mesh.positions[mesh.triangles[1000].x];
  const float s = 0.02f;
  rstest::CountingObserver small(view.nodes.size(), a.object_count()),
      knn(view.nodes.size(), a.object_count()), all(view.nodes.size(), a.object_count());
  const std::vector<RangeHit> in_box = a.query_box(Bounds3(v - Vec3(s), v + Vec3(s)), small);
  const std::vector<RangeHit> k1 = a.nearest(v + Vec3(0, 0.05f, 0), 1, knn);
  const std::vector<RangeHit> everything = a.query_sphere(v, 1e6f, all);
  EXPECT_GE(in_box.size(), 3u);
  ASSERT_EQ(k1.size(), 1u);
  EXPECT_EQ(everything.size(), a.object_count());
  const size_t nodes = view.nodes.size(), prims = a.records().size();
  const size_t small_nodes = small.order.size(), small_prims = small.tested().size();
  std::printf(
      "%s (%zu nodes): small box: %zu nodes, %zu prims; k = 1: %zu nodes, %zu prims, %d "
      "culled; everything: %zu nodes, %zu prims\n",
      name().c_str(), nodes, small_nodes, small_prims, knn.order.size(), knn.tested().size(),
      knn.culled, all.order.size(), all.tested().size());
  if (!a.walks_structure()) {
    EXPECT_EQ(small_prims, prims) << "no structure: every primitive";
    return;
  }
  // Hierarchies only: a flat grid's range walk visits the cells in the
  // range's bounds, which for k nearest start unbounded (and the loose
  // grid's big list holds most of this mesh's triangles).
  if (rstest::flat_view(view)) GTEST_SKIP() << name() << " is flat";
  // The BSP tree's every-cell and smallest-cell storage hold whole triangles
  // that straddle planes far from their cell (every-cell: in leaves at the
  // depth limit; smallest-cell: in the node lists near the root); only split
  // storage prunes them.
  const bool whole_straddlers =
      GetParam().kind == AccelKind::Bsp && GetParam().storage != PrimStorage::Split;
  EXPECT_LT(small_nodes, nodes / 100) << name();
  EXPECT_LT(small_prims, prims / (whole_straddlers ? 20 : 100)) << name();
  EXPECT_EQ(small.culled, 0);
  // Every node entered, the root's box and every other box once.
  EXPECT_EQ(all.order.size(), nodes) << name();
  EXPECT_EQ(size_t(all.boxes), nodes) << name();
  EXPECT_LT(knn.order.size() * 20, all.order.size()) << name();
  EXPECT_LT(knn.tested().size() * (whole_straddlers ? 10 : 20), all.tested().size()) << name();
}

// --- Images -------------------------------------------------------------------------

// The default scene (160x120) and a mesh scene (lumpy_scene(), the bunny
// scene's shape, with a mesh of 1,280 triangles at 80x60, so that brute force
// renders it in seconds): the image is the BVH's, bit for bit (color, depth,
// normals, object ids).
TEST_P(AccelConformance, RendersLikeTheBvh) {
  // Tubes and points, lit so that they shadow each other, seen from outside.
  Rng rng(33);
  Scene tubes = rstest::tube_scene(rng);
  tubes.camera.eye = Vec3(3.0f, 4.0f, 16.0f);
  tubes.camera.look_at = Vec3(0.0f);
  rayscope::Light light;
  light.position = Vec3(5.0f, 12.0f, 8.0f);
  tubes.lights.push_back(light);
  const std::pair<Scene, RenderSettings> cases[] = {
      {make_default_scene(), rstest::small_render(160, 120, 2)},
      {rstest::lumpy_scene(3), rstest::small_render(80, 60, 2)},
      {tubes, rstest::small_render(80, 60, 2)}};
  for (auto [scene, rs] : cases) {
    scene.commit();
    const Framebuffer bvh = render(scene, rs);
    commit(scene);
    EXPECT_TRUE(rstest::same_image(render(scene, rs), bvh)) << name();
  }
}

// --- Bad input ---------------------------------------------------------------------

TEST_P(AccelConformance, NonFiniteInputIsRefusedOrSkipped) {
  // A sphere with a NaN center is refused by commit(); a triangle with a NaN
  // vertex is skipped with a warning, the structure is built over the rest
  // and answers like brute force.
  Scene scene;
  scene.spheres.push_back(rayscope::Sphere{"bad", Vec3(0.0f, std::nanf(""), 0.0f), 1.0f, 0});
  EXPECT_THROW(scene.commit(GetParam().config()), std::invalid_argument);
  scene.spheres.clear();
  TriangleMesh m = make_icosphere(Vec3(0.0f), 1.0f, 2);
  m.positions[3].y = std::nanf("");
  scene.meshes.push_back(m);
  commit(scene);
  EXPECT_GT(scene.summary().skipped_triangles, 0u);
  EXPECT_FALSE(scene.summary().warnings.empty());
  EXPECT_EQ(scene.accel().records().size(), scene.summary().triangles);
  Rng rng(58);
  std::vector<Ray> rays;
  for (int i = 0; i < 2000; ++i) {  // from around it, toward it
    const DVec3 o = 3.0 * rng.unit_vector();
    rays.push_back(Ray{to_f(o), to_f(0.4 * rng.unit_vector() - o), kInfinity});
  }
  rstest::check_queries(scene, rays, (name() + ": icosphere with a NaN vertex").c_str(), 0);
}

TEST_P(AccelConformance, BadLooseFactorsAreRefusedWithOneLine) {
  // The one check of the loose factor (loose_factor_error), for every
  // structure and storage: commit() refuses a factor outside 0 .. 0.5 or not
  // finite with one line, and builds nothing.
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 1));
  for (float bad : {-0.1f, 0.51f, kInfinity, std::nanf("")}) {
    AccelConfig ac = GetParam().config();
    ac.loose_factor = bad;
    try {
      scene.commit(ac);
      ADD_FAILURE() << name() << ": no exception for loose factor " << bad;
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("loose factor must be a number from 0 to 0.5"), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
}

}  // namespace
