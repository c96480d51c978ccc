// The 4-wide hierarchy (bvh4.h): structure of the collapse, the SIMD 4-box test
// against intersect_box() lane by lane (bit for bit, NaN slabs included),
// closest-hit / any-hit traversal against brute force, the observer hooks, and
// Scene queries: the unobserved (4-wide) walk and the observed (binary) walk
// return the same hit bit for bit, and both equal brute force exactly,
// including which primitive wins an exact tie in t.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <functional>
#include <set>

#include "rayscope/bvh4.h"
#include "rayscope/scene.h"
#include "rayscope/shapes.h"
#include "test_util.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::random_ray;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

struct Prims {
  std::vector<Bounds3> bounds;
  std::vector<Vec3> centroids;
  void add(const Bounds3& b) {
    bounds.push_back(b);
    centroids.push_back(b.center());
  }
};

Prims random_boxes(Rng& rng, int n, bool log_uniform) {
  Prims p;
  for (int i = 0; i < n; ++i) {
    DVec3 c = log_uniform
                  ? DVec3(rng.log_uniform_signed(1e-6, 1e6), rng.log_uniform_signed(1e-6, 1e6),
                          rng.log_uniform_signed(1e-6, 1e6))
                  : DVec3(rng.uniform(-100, 100), rng.uniform(-100, 100), rng.uniform(-100, 100));
    double s =
        log_uniform ? rstest::max_abs(c) * rng.log_uniform(1e-4, 1) : rng.log_uniform(1e-3, 5);
    DVec3 h(s * rng.uniform(0.1, 1), s * rng.uniform(0.1, 1), s * rng.uniform(0.1, 1));
    p.add(Bounds3(to_f(c - h), to_f(c + h)));
  }
  return p;
}

// Every binary leaf appears exactly once as a wide leaf with the same
// primitive range and box; inner children carry their binary node's box; empty
// slots come last, have empty boxes and no primitives; slot_source names the
// binary node of every slot; the depth fits the stack.
void check_collapse(const Bvh& bvh, const Bvh4& w) {
  if (bvh.empty()) {
    EXPECT_TRUE(w.empty());
    EXPECT_TRUE(w.nodes.empty());
    return;
  }
  ASSERT_FALSE(w.empty());
  ASSERT_EQ(w.slot_source.size(), 4 * w.nodes.size());
  std::set<uint32_t> binary_leaves;
  for (uint32_t i = 0; i < bvh.nodes.size(); ++i)
    if (bvh.nodes[i].is_leaf()) binary_leaves.insert(i);
  if (bvh.nodes[0].is_leaf()) {
    EXPECT_TRUE(w.nodes.empty());
    EXPECT_EQ(w.depth(), 0u);
    return;
  }
  std::set<uint32_t> seen_leaves;
  std::vector<int> reached(w.nodes.size(), 0);
  uint32_t max_level = 0;
  std::function<void(uint32_t, uint32_t)> walk = [&](uint32_t n, uint32_t level) {
    ASSERT_LT(n, w.nodes.size());
    ASSERT_EQ(reached[n]++, 0) << "wide node " << n << " reached twice";
    max_level = std::max(max_level, level);
    const Bvh4Node& node = w.nodes[n];
    bool empty_seen = false;
    int children = 0;
    for (int k = 0; k < 4; ++k) {
      const uint32_t src = w.slot_source[4 * n + k];
      if (src == ~0u) {
        empty_seen = true;
        EXPECT_EQ(node.child[k], Bvh4Node::kLeaf);
        EXPECT_EQ(node.count[k], 0u);
        EXPECT_EQ(node.lo_x[k], kInfinity);
        EXPECT_EQ(node.lo_y[k], kInfinity);
        EXPECT_EQ(node.lo_z[k], kInfinity);
        EXPECT_EQ(node.hi_x[k], -kInfinity);
        EXPECT_EQ(node.hi_y[k], -kInfinity);
        EXPECT_EQ(node.hi_z[k], -kInfinity);
        continue;
      }
      ++children;
      EXPECT_FALSE(empty_seen) << "empty slot before a child in wide node " << n;
      ASSERT_LT(src, bvh.nodes.size());
      const BvhNode& b = bvh.nodes[src];
      EXPECT_EQ(node.lo_x[k], b.lo.x);
      EXPECT_EQ(node.lo_y[k], b.lo.y);
      EXPECT_EQ(node.lo_z[k], b.lo.z);
      EXPECT_EQ(node.hi_x[k], b.hi.x);
      EXPECT_EQ(node.hi_y[k], b.hi.y);
      EXPECT_EQ(node.hi_z[k], b.hi.z);
      if (b.is_leaf()) {
        EXPECT_EQ(node.child[k], Bvh4Node::kLeaf | b.index);
        EXPECT_EQ(node.count[k], b.count);
        EXPECT_TRUE(seen_leaves.insert(src).second) << "binary leaf " << src << " twice";
      } else {
        EXPECT_EQ(node.child[k] & Bvh4Node::kLeaf, 0u);
        EXPECT_EQ(node.count[k], 0u);
        walk(node.child[k], level + 1);
      }
    }
    EXPECT_GE(children, 2) << "wide node " << n;
  };
  walk(0, 1);
  EXPECT_EQ(seen_leaves, binary_leaves);
  for (size_t n = 0; n < reached.size(); ++n) EXPECT_EQ(reached[n], 1) << "wide node " << n;
  EXPECT_EQ(w.depth(), max_level);
  EXPECT_LE(3 * w.depth(), uint32_t(Bvh4::kStackSize));
  EXPECT_LE(w.depth(), bvh.quality().depth);
}

TEST(Bvh4Build, CollapseKeepsEveryLeafAndBox) {
  Rng rng(11);
  const BvhBuildConfig configs[] = {{}, {4, 1, 1, 1.0f, 1.0f, 56}, {64, 32, 4, 0.5f, 1.0f, 56}};
  for (bool log_uniform : {false, true})
    for (int n : {0, 1, 2, 3, 5, 9, 100, 3000})
      for (const BvhBuildConfig& cfg : configs) {
        SCOPED_TRACE("n=" + std::to_string(n) + " max_leaf=" + std::to_string(cfg.max_leaf_size));
        Prims p = random_boxes(rng, n, log_uniform);
        Bvh bvh;
        bvh.build(p.bounds, p.centroids, cfg);
        Bvh4 w;
        w.build(bvh);
        check_collapse(bvh, w);
        if (HasFatalFailure()) return;
      }
}

TEST(Bvh4Build, DeepBinaryTreeFitsTheStack) {
  // The geometric groups of test_bvh's AdversarialDepth test: the deepest
  // binary tree the builder makes. The wide tree must fit the traversal stack,
  // and a ray along the chain (which pushes at every level) must agree with
  // brute force.
  Rng rng(2);
  Prims p;
  for (int j = -30; j <= 30; ++j)
    for (int k = 0; k < 2000; ++k) {
      float x = std::pow(17.0f, float(j)) * rstest::round_f(1.0 + 1e-3 * rng.uniform());
      p.add(Bounds3(Vec3(x, 0, 0), Vec3(x * 1.0001f, 1e-20f, 1e-20f)));
    }
  Bvh bvh;
  bvh.build(p.bounds, p.centroids);
  Bvh4 w;
  w.build(bvh);
  check_collapse(bvh, w);
  std::printf("geometric groups: binary depth %u, wide depth %u\n", bvh.quality().depth, w.depth());
  for (float y : {0.0f, 5e-21f, 1e-20f, 2e-20f}) {
    Ray ray{Vec3(-1.0f, y, y), Vec3(1.0f, 0.0f, 0.0f), kInfinity};
    const Vec3 inv = 1.0f / ray.dir;
    float best_bf = kInfinity;
    for (const Bounds3& b : p.bounds)
      best_bf = std::min(best_bf, intersect_box(b.lo, b.hi, ray.origin, inv, kInfinity));
    float tmax = kInfinity, best = kInfinity;
    NullTraversalObserver obs;
    auto leaf = [&](uint32_t first, uint32_t count, float& t) {
      bool found = false;
      for (uint32_t k = first; k < first + count; ++k) {
        const Bounds3& b = p.bounds[bvh.prim_indices[k]];
        float tb = intersect_box(b.lo, b.hi, ray.origin, inv, t);
        if (tb < best) best = t = tb, found = true;
      }
      return found;
    };
    EXPECT_EQ(w.traverse<false>(ray, tmax, leaf, obs), best_bf != kInfinity) << "y=" << y;
    EXPECT_EQ(best, best_bf) << "y=" << y;
  }
}

TEST(Bvh4Traversal, FourBoxTestEqualsIntersectBoxBitForBit) {
  // Nodes filled with the boxes of random primitives (and empty slots); every
  // lane must give intersect_box's answer: hit or miss, and the same entry
  // distance for hits.
  Rng rng(12);
  Prims p = random_boxes(rng, 400, false);
  Bounds3 world;
  for (const Bounds3& b : p.bounds) world.extend(b);
  int hits = 0, lanes = 0;
  for (int i = 0; i < 20000; ++i) {
    Bvh4Node node{};
    const int used = rng.integer(1, 4);
    Bounds3 box[4];
    for (int k = 0; k < 4; ++k) {
      if (k < used) box[k] = p.bounds[size_t(rng.integer(0, int(p.bounds.size()) - 1))];
      node.lo_x[k] = box[k].lo.x;
      node.lo_y[k] = box[k].lo.y;
      node.lo_z[k] = box[k].lo.z;
      node.hi_x[k] = box[k].hi.x;
      node.hi_y[k] = box[k].hi.y;
      node.hi_z[k] = box[k].hi.z;
    }
    std::vector<Bounds3> aim(box, box + used);
    const Ray ray = random_ray(rng, world, aim);
    const Vec3 inv = 1.0f / ray.dir;
    const bvh4_detail::RayBoxes rb(ray.origin, inv);
    alignas(16) float tnear[4];
    const float tmax = rng.coin() ? ray.tmax : rstest::round_f(rng.uniform(0, 300));
    const unsigned mask = bvh4_detail::intersect_boxes(node, rb, tmax, tnear);
    for (int k = 0; k < 4; ++k) {
      const float ref = intersect_box(box[k].lo, box[k].hi, ray.origin, inv, tmax);
      ++lanes;
      ASSERT_EQ(bool(mask & (1u << k)), ref != kInfinity) << "ray " << i << " lane " << k;
      if (ref != kInfinity) {
        ++hits;
        ASSERT_EQ(tnear[k], ref) << "ray " << i << " lane " << k;
      }
      if (k >= used) {
        ASSERT_FALSE(mask & (1u << k)) << "empty slot hit, ray " << i;
      }
    }
  }
  std::printf("%d lanes, %d hits\n", lanes, hits);
  EXPECT_GT(hits, lanes / 25);
}

TEST(Bvh4Traversal, ClosestAndAnyHitBoxesMatchBruteForce) {
  Rng rng(13);
  int hits = 0, rays = 0;
  for (bool log_uniform : {false, true}) {
    Prims p = random_boxes(rng, 3000, log_uniform);
    Bvh bvh;
    bvh.build(p.bounds, p.centroids);
    Bvh4 w;
    w.build(bvh);
    for (int i = 0; i < 5000; ++i) {
      Ray ray = random_ray(rng, bvh.bounds(), p.bounds);
      const Vec3 inv = 1.0f / ray.dir;
      float best_bf = kInfinity;
      for (const Bounds3& b : p.bounds)
        best_bf = std::min(best_bf, intersect_box(b.lo, b.hi, ray.origin, inv, ray.tmax));
      float tmax = ray.tmax, best = kInfinity;
      NullTraversalObserver obs;
      auto leaf = [&](uint32_t first, uint32_t count, float& t) {
        bool found = false;
        for (uint32_t k = first; k < first + count; ++k) {
          const Bounds3& b = p.bounds[bvh.prim_indices[k]];
          float tb = intersect_box(b.lo, b.hi, ray.origin, inv, t);
          if (tb < best) best = t = tb, found = true;
        }
        return found;
      };
      ++rays;
      ASSERT_EQ(w.traverse<false>(ray, tmax, leaf, obs), best_bf != kInfinity) << "ray " << i;
      if (best_bf != kInfinity) {
        ++hits;
        ASSERT_EQ(best, best_bf) << "ray " << i;
      }
      float tmax2 = ray.tmax;
      auto any_leaf = [&](uint32_t first, uint32_t count, float& t) {
        for (uint32_t k = first; k < first + count; ++k) {
          const Bounds3& b = p.bounds[bvh.prim_indices[k]];
          if (intersect_box(b.lo, b.hi, ray.origin, inv, t) != kInfinity) return true;
        }
        return false;
      };
      ASSERT_EQ(w.traverse<true>(ray, tmax2, any_leaf, obs), best_bf != kInfinity)
          << "any-hit ray " << i;
    }
  }
  std::printf("boxes: %d rays, %d hits\n", rays, hits);
  EXPECT_GT(hits, rays / 3);
}

struct CountingObserver {
  static constexpr bool kActive = true;
  std::vector<int>* node_visits;
  int boxes = 0, culled = 0, prims = 0;
  void on_node(uint32_t n) { (*node_visits).at(n)++; }
  void on_box_test() { ++boxes; }
  void on_cull(uint32_t) { ++culled; }
  void on_prim_test(uint32_t) { ++prims; }
};

TEST(Bvh4Traversal, ObserverReportsBinaryIdsAndEveryChildBoxTest) {
  Rng rng(14);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 4));
  scene.commit();
  const Bvh& bvh = scene.bvh();
  const Bvh4& w = scene.bvh4();
  // Binary id of the subtree root of each wide node -> that wide node.
  std::vector<int> wide_of(bvh.nodes.size(), -1);
  wide_of[0] = 0;
  for (size_t n = 0; n < w.nodes.size(); ++n)
    for (int k = 0; k < 4; ++k) {
      uint32_t src = w.slot_source[4 * n + k];
      if (src != ~0u && !(w.nodes[n].child[k] & Bvh4Node::kLeaf))
        wide_of[src] = int(w.nodes[n].child[k]);
    }
  const auto& records = scene.prim_records();
  uint64_t culled = 0;
  for (int i = 0; i < 2000; ++i) {
    std::vector<int> nv(bvh.nodes.size(), 0);
    CountingObserver c{&nv};
    Ray ray{to_f(3.0 * rng.unit_vector()), to_f(rng.unit_vector()), kInfinity};
    const TrianglePrecomp pre(ray);
    float tmax = ray.tmax;
    auto leaf = [&](uint32_t first, uint32_t count, float& t) {
      bool found = false;
      for (uint32_t k = first; k < first + count; ++k) {
        c.on_prim_test(k);
        TriangleHit th;
        if (intersect_triangle(pre, t, records[k].a, records[k].b, records[k].c, th))
          t = th.t, found = true;
      }
      return found;
    };
    w.traverse<false>(ray, tmax, leaf, c);
    int expected_boxes = 1, leaves_prims = 0;
    for (size_t n = 0; n < nv.size(); ++n) {
      ASSERT_LE(nv[n], 1) << "node " << n;
      if (!nv[n]) continue;
      if (bvh.nodes[n].is_leaf()) {
        leaves_prims += int(bvh.nodes[n].count);
        continue;
      }
      ASSERT_GE(wide_of[n], 0) << "binary node " << n << " is not the top of a wide node";
      for (int k = 0; k < 4; ++k)
        expected_boxes += w.slot_source[4 * size_t(wide_of[n]) + k] != ~0u;
    }
    EXPECT_EQ(c.boxes, expected_boxes) << "ray " << i;
    EXPECT_EQ(c.prims, leaves_prims) << "ray " << i;
    culled += uint64_t(c.culled);
  }
  EXPECT_GT(culled, 0u);  // early termination happened
}

// ---------------------------------------------------------------------------
// Scene: 4-wide (unobserved) and binary (observed) walks against brute force.

struct BruteHit {
  float t = kInfinity;
  uint32_t prim = ~0u;  // global primitive index (triangles, then spheres)
  int plane = -1;
  bool tie = false;  // another primitive was hit at exactly the same t
};

// A loop over every triangle, sphere and plane in order, with the tests'
// own range checks: a triangle at exactly the closest t so far replaces it
// (intersect_triangle accepts t == tmax), a sphere or plane does not.
BruteHit brute_force(const Scene& s, const Ray& ray) {
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

struct AlwaysActive {
  static constexpr bool kActive = true;
  void on_node(uint32_t) {}
  void on_box_test() {}
  void on_cull(uint32_t) {}
  void on_prim_test(uint32_t) {}
};

bool same_bits(const PrimHit& a, const PrimHit& b) {
  return std::memcmp(&a.t, &b.t, sizeof(float)) == 0 &&
         std::memcmp(&a.b0, &b.b0, sizeof(float)) == 0 &&
         std::memcmp(&a.b1, &b.b1, sizeof(float)) == 0 &&
         std::memcmp(&a.b2, &b.b2, sizeof(float)) == 0 && a.record == b.record &&
         a.prim == b.prim && a.plane == b.plane;
}

void compare_walks(Scene& scene, const std::vector<Ray>& rays, const char* what, int min_ties) {
  ASSERT_TRUE(scene.summary().bvh_used);
  int hits = 0, ties = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Ray& ray = rays[i];
    const BruteHit bf = brute_force(scene, ray);
    PrimHit wide, binary;
    const bool got = scene.intersect(ray, wide);
    ASSERT_EQ(scene.intersect(ray, binary, AlwaysActive{}), got) << what << ", ray " << i;
    ASSERT_EQ(got, bf.t != kInfinity) << what << ", ray " << i;
    ASSERT_TRUE(same_bits(wide, binary))
        << what << ", ray " << i << ": 4-wide prim " << wide.prim << " t " << wide.t
        << ", binary prim " << binary.prim << " t " << binary.t;
    const bool occluded = scene.occluded(ray);
    ASSERT_EQ(scene.occluded(ray, AlwaysActive{}), occluded) << what << ", ray " << i;
    ASSERT_EQ(occluded, got) << what << ", any-hit ray " << i;
    if (!got) continue;
    ++hits;
    ties += bf.tie;
    ASSERT_EQ(wide.t, bf.t) << what << ", ray " << i;
    ASSERT_EQ(wide.plane, bf.plane) << what << ", ray " << i;
    ASSERT_EQ(wide.prim, bf.prim) << what << ", ray " << i << (bf.tie ? " (tie)" : "");
    if (wide.plane < 0) {
      ASSERT_LT(wide.record, scene.prim_records().size());
      EXPECT_EQ(scene.prim_records()[wide.record].id, wide.prim);
    }
    // The SurfaceHit query is the lean query plus surface_hit().
    SurfaceHit sh;
    ASSERT_TRUE(scene.intersect(ray, sh));
    const SurfaceHit ref = scene.surface_hit(ray, wide);
    EXPECT_EQ(std::memcmp(&sh.p, &ref.p, sizeof(Vec3)), 0);
    EXPECT_EQ(std::memcmp(&sh.ns, &ref.ns, sizeof(Vec3)), 0);
    EXPECT_EQ(sh.object, ref.object);
    EXPECT_EQ(sh.prim, ref.prim);
  }
  std::printf("%s: %zu rays, %d hits, %d with exact ties\n", what, rays.size(), hits, ties);
  EXPECT_GT(hits, int(rays.size()) / 4) << what;
  EXPECT_GE(ties, min_ties) << what;
}

TEST(Bvh4Scene, RandomRaysMatchBinaryWalkAndBruteForce) {
  Rng rng(15);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 2.0f, 3));
  scene.meshes.push_back(make_torus(Vec3(3.0f, 0.0f, 0.0f), 1.5f, 0.4f, 32, 16));
  TriangleMesh soup;
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
  scene.planes.push_back(Plane{"floor", Vec3(0, -5, 0), Vec3(0, 1, 0), 0});
  scene.commit();
  std::vector<Bounds3> boxes;
  for (const TriangleMesh& m : scene.meshes)
    for (const glm::uvec3& t : m.triangles) {
      Bounds3 b(m.positions[t.x]);
      b.extend(m.positions[t.y]);
      b.extend(m.positions[t.z]);
      boxes.push_back(b);
    }
  std::vector<Ray> rays;
  for (int i = 0; i < 20000; ++i) rays.push_back(random_ray(rng, scene.bvh().bounds(), boxes));
  compare_walks(scene, rays, "meshes + soup + spheres + plane", 0);
}

TEST(Bvh4Scene, TiesAtVerticesAndEdgesResolveLikeBruteForce) {
  // Rays through the vertices and edge midpoints of closed meshes, and along
  // the axes through an axis-aligned cube's edges and corners: several
  // triangles are hit at exactly the same t, and the winner must not depend
  // on the walk.
  Rng rng(16);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 2));
  TriangleMesh cube;  // unit cube at (3, 0, 0)
  for (int i = 0; i < 8; ++i)
    cube.positions.push_back(Vec3(3.0f + float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)));
  cube.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  scene.meshes.push_back(cube);
  scene.meshes.push_back(make_torus(Vec3(-3.0f, 0.0f, 0.0f), 1.0f, 0.3f, 24, 12));
  scene.commit();
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
  compare_walks(scene, rays, "vertex and edge rays", 20);
}

}  // namespace
