// The binned SAH BVH (bvh.h): structural invariants of the built hierarchy, its
// quality() figures, and closest-hit / any-hit traversal against brute force
// over all primitives (directly on boxes, and through Scene on triangles and
// spheres). Traversal and brute force call the same primitive tests with the
// same inputs, so their answers must agree exactly (same t, bit for bit).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <functional>

#include "rayscope/bvh.h"
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

// Traversal keeps a fixed stack of 64 entries (bvh.h), at most one per level
// of the current path below the root, so a hierarchy deeper than 65 levels
// (root = level 1) could overflow it.
constexpr uint32_t kMaxSafeDepth = 65;

struct Prims {
  std::vector<Bounds3> bounds;
  std::vector<Vec3> centroids;
  void add(const Bounds3& b) {
    bounds.push_back(b);
    centroids.push_back(b.center());
  }
};

Prims random_boxes(Rng& rng, int n, int kind) {
  Prims p;
  for (int i = 0; i < n; ++i) {
    DVec3 c;
    switch (kind) {
      case 0:  // uniform in a cube
        c = DVec3(rng.uniform(-100, 100), rng.uniform(-100, 100), rng.uniform(-100, 100));
        break;
      case 1: {  // a few tight clusters
        DVec3 centers[4] = {{-50, 0, 0}, {50, 10, 0}, {0, 0, 80}, {3, 3, 3}};
        c = centers[rng.integer(0, 3)] + rng.uniform(0.01, 5) * rng.in_unit_ball();
        break;
      }
      case 2:  // all centroids coincide
        c = DVec3(1, 2, 3);
        break;
      default:  // log-uniform coordinates: sizes and positions over 12 decades
        c = DVec3(rng.log_uniform_signed(1e-6, 1e6), rng.log_uniform_signed(1e-6, 1e6),
                  rng.log_uniform_signed(1e-6, 1e6));
    }
    double s = kind == 3 ? rstest::max_abs(c) * rng.log_uniform(1e-4, 1) : rng.log_uniform(1e-3, 5);
    DVec3 h(s * rng.uniform(0.1, 1), s * rng.uniform(0.1, 1), s * rng.uniform(0.1, 1));
    if (kind == 2) h = DVec3(rng.uniform(0.1, 1), rng.uniform(0.1, 1), rng.uniform(0.1, 1));
    p.add(Bounds3(to_f(c - h), to_f(c + h)));
  }
  return p;
}

// Checks every structural invariant and recomputes quality() independently.
void check_structure(const Bvh& bvh, const Prims& p, const BvhBuildConfig& cfg) {
  const size_t n = p.bounds.size();
  ASSERT_EQ(bvh.prim_indices.size(), n);
  // prim_indices is a permutation of 0..n-1.
  std::vector<int> seen(n, 0);
  for (uint32_t idx : bvh.prim_indices) {
    ASSERT_LT(idx, n);
    seen[idx]++;
  }
  for (size_t i = 0; i < n; ++i) ASSERT_EQ(seen[i], 1) << "primitive " << i;

  // Walk the tree: every node reached exactly once, leaves partition [0, n).
  std::vector<int> visited(bvh.nodes.size(), 0), covered(n, 0);
  uint32_t leaves = 0, depth = 0, min_leaf = ~0u, max_leaf = 0;
  uint64_t leaf_prims = 0;
  double sah = 0;
  const double root_area = std::max(1e-30, double(bvh.nodes[0].bounds().half_area()));
  std::function<void(uint32_t, uint32_t)> walk = [&](uint32_t i, uint32_t d) {
    ASSERT_LT(i, bvh.nodes.size());
    ASSERT_EQ(visited[i]++, 0) << "node " << i << " reached twice";
    const BvhNode& node = bvh.nodes[i];
    const Bounds3 box = node.bounds();
    depth = std::max(depth, d);
    double rel = double(box.half_area()) / root_area;
    if (node.is_leaf()) {
      ++leaves;
      leaf_prims += node.count;
      min_leaf = std::min(min_leaf, node.count);
      max_leaf = std::max(max_leaf, node.count);
      sah += rel * cfg.intersection_cost * node.count;
      ASSERT_LE(uint64_t(node.index) + node.count, n);
      Bounds3 tight;
      for (uint32_t k = node.index; k < node.index + node.count; ++k) {
        covered[k]++;
        const Bounds3& pb = p.bounds[bvh.prim_indices[k]];
        EXPECT_TRUE(box.contains(pb))
            << "leaf " << i << " does not contain primitive " << bvh.prim_indices[k];
        tight.extend(pb);
      }
      // The builder makes boxes tight: exactly the union of their primitives.
      EXPECT_EQ(box.lo, tight.lo);
      EXPECT_EQ(box.hi, tight.hi);
      EXPECT_LE(node.count, std::max(cfg.max_leaf_size, cfg.min_leaf_size)) << "leaf " << i;
    } else {
      sah += rel * cfg.traversal_cost;
      ASSERT_LT(node.index + 1, bvh.nodes.size());
      ASSERT_NE(node.index, i);
      const Bounds3 a = bvh.nodes[node.index].bounds(), b = bvh.nodes[node.index + 1].bounds();
      EXPECT_TRUE(box.contains(a) && box.contains(b)) << "inner node " << i;
      EXPECT_EQ(box.lo, glm::min(a.lo, b.lo));
      EXPECT_EQ(box.hi, glm::max(a.hi, b.hi));
      walk(node.index, d + 1);
      walk(node.index + 1, d + 1);
    }
  };
  walk(0, 1);
  if (::testing::Test::HasFatalFailure()) return;
  for (size_t i = 0; i < bvh.nodes.size(); ++i) EXPECT_EQ(visited[i], 1) << "node " << i;
  for (size_t k = 0; k < n; ++k) ASSERT_EQ(covered[k], 1) << "slot " << k;
  // The root holds everything.
  Bounds3 all;
  for (const Bounds3& b : p.bounds) all.extend(b);
  EXPECT_EQ(bvh.bounds().lo, all.lo);
  EXPECT_EQ(bvh.bounds().hi, all.hi);

  // quality() agrees with the walk; a binary tree has nodes = 2 leaves - 1.
  BvhQuality q = bvh.quality();
  EXPECT_EQ(q.nodes, bvh.nodes.size());
  EXPECT_EQ(q.leaves, leaves);
  EXPECT_EQ(q.nodes, 2 * q.leaves - 1);
  EXPECT_EQ(q.depth, depth);
  EXPECT_EQ(q.min_leaf_prims, min_leaf);
  EXPECT_EQ(q.max_leaf_prims, max_leaf);
  EXPECT_EQ(leaf_prims, n);
  EXPECT_DOUBLE_EQ(q.mean_leaf_prims, double(n) / leaves);
  EXPECT_NEAR(q.sah_cost, sah, 1e-9 * sah);
  EXPECT_GE(q.sah_cost, cfg.traversal_cost * (leaves > 1) + 0.0);
  EXPECT_EQ(q.memory_bytes, bvh.nodes.size() * sizeof(BvhNode) + n * sizeof(uint32_t));
  EXPECT_LE(q.depth, kMaxSafeDepth) << "deeper than the traversal stack allows";
}

TEST(BvhBuild, InvariantsForRandomBoxes) {
  Rng rng(1);
  const BvhBuildConfig configs[] = {
      {},
      {4, 1, 1, 1.0f, 1.0f, 56},
      {2, 4, 1, 1.0f, 2.0f, 56},
      {64, 32, 4, 0.5f, 1.0f, 56},
      {16, 8, 1, 1.0f, 1.0f, 3},  // median splits below depth 3
  };
  const char* kinds[] = {"uniform", "clustered", "coincident", "log-uniform"};
  for (int kind = 0; kind < 4; ++kind)
    for (int n : {1, 2, 3, 9, 100, 5000}) {
      Prims p = random_boxes(rng, kind == 2 ? std::min(n, 300) : n, kind);
      for (const BvhBuildConfig& cfg : configs) {
        SCOPED_TRACE(std::string(kinds[kind]) + ", n=" + std::to_string(p.bounds.size()) +
                     ", bins=" + std::to_string(cfg.bins) +
                     ", max_leaf=" + std::to_string(cfg.max_leaf_size));
        Bvh bvh;
        bvh.build(p.bounds, p.centroids, cfg);
        check_structure(bvh, p, cfg);
        if (HasFatalFailure()) return;
      }
    }
}

TEST(BvhBuild, EmptyAndSingle) {
  Bvh bvh;
  bvh.build({}, {});
  EXPECT_TRUE(bvh.empty());
  EXPECT_TRUE(bvh.bounds().empty());
  BvhQuality q = bvh.quality();
  EXPECT_EQ(q.nodes, 0u);
  EXPECT_EQ(q.leaves, 0u);
  float tmax = kInfinity;
  NullTraversalObserver obs;
  int calls = 0;
  auto leaf = [&](uint32_t, uint32_t, float&) { return ++calls, true; };
  EXPECT_FALSE(bvh.traverse<false>(Ray{}, tmax, leaf, obs));
  EXPECT_EQ(calls, 0);

  Prims p;
  p.add(Bounds3(Vec3(0), Vec3(1)));
  bvh.build(p.bounds, p.centroids);
  ASSERT_EQ(bvh.nodes.size(), 1u);
  EXPECT_TRUE(bvh.nodes[0].is_leaf());
  EXPECT_EQ(bvh.quality().depth, 1u);
  EXPECT_TRUE(
      bvh.traverse<false>(Ray{Vec3(0.5f, 0.5f, -1), Vec3(0, 0, 1), kInfinity}, tmax, leaf, obs));
  EXPECT_FALSE(
      bvh.traverse<false>(Ray{Vec3(2, 0.5f, -1), Vec3(0, 0, 1), kInfinity}, tmax, leaf, obs));
}

TEST(BvhBuild, AdversarialDepthFitsTheTraversalStack) {
  // Groups of boxes at x = 17^j (j = -30..30), thin in y and z. With 16
  // equal-width bins every group but the outermost falls into the first bin,
  // so each SAH split can only peel off one group: the tree becomes a chain as
  // deep as the builder allows, with large median-split subtrees below it. A
  // ray along +x from the origin side visits the near (inner) child first and
  // pushes the far one at every level, so the stack holds one entry per level.
  // The depth must fit the traversal stack, and traversal must still agree
  // with brute force. (Before the builder capped the depth, this overflowed
  // Bvh::traverse's stack: AddressSanitizer reported stack-buffer-overflow.)
  Rng rng(2);
  Prims p;
  for (int j = -30; j <= 30; ++j)
    for (int k = 0; k < 2000; ++k) {
      float x = std::pow(17.0f, float(j)) * rstest::round_f(1.0 + 1e-3 * rng.uniform());
      p.add(Bounds3(Vec3(x, 0, 0), Vec3(x * 1.0001f, 1e-20f, 1e-20f)));
    }
  Bvh bvh;
  bvh.build(p.bounds, p.centroids);
  check_structure(bvh, p, BvhBuildConfig{});
  std::printf("geometric groups, n=%zu: depth %u\n", p.bounds.size(), bvh.quality().depth);
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
    EXPECT_EQ(bvh.traverse<false>(ray, tmax, leaf, obs), best_bf != kInfinity) << "y=" << y;
    EXPECT_EQ(best, best_bf) << "y=" << y;
  }
}

// ---------------------------------------------------------------------------
// Traversal against brute force

TEST(BvhTraversal, ClosestAndAnyHitBoxesMatchBruteForce) {
  // Primitives are the boxes themselves; a primitive's hit distance is its
  // entry distance (intersect_box). Closest hit: the smallest entry distance
  // over all boxes; any hit: whether some box is entered within tmax.
  Rng rng(3);
  int hits = 0, rays = 0;
  for (int kind : {0, 1, 3}) {
    Prims p = random_boxes(rng, 3000, kind);
    Bvh bvh;
    bvh.build(p.bounds, p.centroids);
    for (int i = 0; i < 5000; ++i) {
      Ray ray = random_ray(rng, bvh.bounds(), p.bounds);
      const Vec3 inv = 1.0f / ray.dir;
      float best_bf = kInfinity;
      uint32_t prim_bf = ~0u;
      for (uint32_t k = 0; k < p.bounds.size(); ++k) {
        float t = intersect_box(p.bounds[k].lo, p.bounds[k].hi, ray.origin, inv, ray.tmax);
        if (t < best_bf) best_bf = t, prim_bf = k;
      }
      float tmax = ray.tmax;
      float best = kInfinity;
      NullTraversalObserver obs;
      auto leaf = [&](uint32_t first, uint32_t count, float& t) {
        bool found = false;
        for (uint32_t k = first; k < first + count; ++k) {
          const Bounds3& b = p.bounds[bvh.prim_indices[k]];
          float tb = intersect_box(b.lo, b.hi, ray.origin, inv, t);
          if (tb < best) {
            best = tb;
            t = tb;
            found = true;
          }
        }
        return found;
      };
      bool got = bvh.traverse<false>(ray, tmax, leaf, obs);
      ++rays;
      ASSERT_EQ(got, best_bf != kInfinity)
          << "kind " << kind << " ray " << i << " brute-force prim " << prim_bf;
      if (got) {
        ++hits;
        ASSERT_EQ(best, best_bf) << "kind " << kind << " ray " << i;
      }
      float tmax2 = ray.tmax;
      auto any_leaf = [&](uint32_t first, uint32_t count, float& t) {
        for (uint32_t k = first; k < first + count; ++k) {
          const Bounds3& b = p.bounds[bvh.prim_indices[k]];
          if (intersect_box(b.lo, b.hi, ray.origin, inv, t) != kInfinity) return true;
        }
        return false;
      };
      ASSERT_EQ(bvh.traverse<true>(ray, tmax2, any_leaf, obs), best_bf != kInfinity)
          << "any-hit, kind " << kind << " ray " << i;
    }
  }
  std::printf("boxes: %d rays, %d hits\n", rays, hits);
  EXPECT_GT(hits, rays / 3);
  EXPECT_LT(hits, rays * 9 / 10);
}

// Closest hit by brute force over every triangle and sphere of a committed
// scene (same tests, same per-ray precomputation, as Scene::intersect).
struct BruteHit {
  float t = kInfinity;
  uint32_t object = ~0u, prim = ~0u;
};
BruteHit brute_force(const Scene& s, const Ray& ray, bool any) {
  BruteHit best;
  float tmax = ray.tmax;
  const TrianglePrecomp pre(ray);
  for (uint32_t m = 0; m < s.meshes.size(); ++m) {
    const TriangleMesh& mesh = s.meshes[m];
    for (uint32_t i = 0; i < mesh.triangles.size(); ++i) {
      const glm::uvec3& t = mesh.triangles[i];
      TriangleHit th;
      if (intersect_triangle(pre, tmax, mesh.positions[t.x], mesh.positions[t.y],
                             mesh.positions[t.z], th)) {
        tmax = th.t;
        best = {th.t, m, i};
        if (any) return best;
      }
    }
  }
  for (uint32_t k = 0; k < s.spheres.size(); ++k) {
    float ts;
    if (intersect_sphere(ray, s.spheres[k].center, s.spheres[k].radius, tmax, ts)) {
      tmax = ts;
      best = {ts, uint32_t(s.meshes.size()) + k, 0};
      if (any) return best;
    }
  }
  for (uint32_t k = 0; k < s.planes.size(); ++k) {
    float tp;
    if (intersect_plane(ray, s.planes[k].point, s.planes[k].normal, tmax, tp)) {
      tmax = tp;
      best = {tp, uint32_t(s.meshes.size() + s.spheres.size()) + k, 0};
      if (any) return best;
    }
  }
  return best;
}

void compare_scene_with_brute_force(Scene& scene, Rng& rng, int nrays, const char* what) {
  scene.commit();
  ASSERT_TRUE(scene.summary().bvh_used);
  std::vector<Bounds3> boxes;
  for (const TriangleMesh& m : scene.meshes)
    for (const glm::uvec3& t : m.triangles) {
      Bounds3 b(m.positions[t.x]);
      b.extend(m.positions[t.y]);
      b.extend(m.positions[t.z]);
      boxes.push_back(b);
    }
  int hits = 0, ties = 0;
  for (int i = 0; i < nrays; ++i) {
    Ray ray = random_ray(rng, scene.bvh().bounds(), boxes);
    BruteHit bf = brute_force(scene, ray, false);
    SurfaceHit hit;
    bool got = scene.intersect(ray, hit);
    ASSERT_EQ(got, bf.t != kInfinity) << what << ", ray " << i << ": brute force t=" << bf.t
                                      << " object " << bf.object << " prim " << bf.prim;
    if (got) {
      ++hits;
      // Same distance bit for bit; same primitive unless two share that t.
      ASSERT_EQ(hit.t, bf.t) << what << ", ray " << i << std::hexfloat << " t=" << hit.t
                             << " bf=" << bf.t << " obj " << hit.object << "/" << bf.object
                             << " prim " << hit.prim << "/" << bf.prim;
      if (hit.object != bf.object || hit.prim != bf.prim) {
        // A tie: the primitive the BVH reports must itself be hit at that t.
        ++ties;
        if (hit.object < scene.meshes.size()) {
          const TriangleMesh& m = scene.meshes[hit.object];
          const glm::uvec3& t = m.triangles[hit.prim];
          TriangleHit th;
          ASSERT_TRUE(
              intersect_triangle(ray, m.positions[t.x], m.positions[t.y], m.positions[t.z], th));
          EXPECT_EQ(th.t, hit.t);
        } else if (hit.object < scene.meshes.size() + scene.spheres.size()) {
          const rayscope::Sphere& sp = scene.spheres[hit.object - scene.meshes.size()];
          float ts;
          ASSERT_TRUE(intersect_sphere(ray, sp.center, sp.radius, ray.tmax, ts));
          EXPECT_EQ(ts, hit.t);
        }
      }
    }
    uint32_t occluder = ~0u;
    bool blocked = scene.occluded(ray, NullTraversalObserver{}, &occluder);
    ASSERT_EQ(blocked, bf.t != kInfinity) << what << ", any-hit ray " << i;
    if (blocked) {
      EXPECT_LT(occluder, scene.object_count());
    }
  }
  std::printf("%s: %d rays, %d hits (%d ties between primitives)\n", what, nrays, hits, ties);
  EXPECT_GT(hits, nrays / 4) << what;
  EXPECT_LT(hits, nrays * 9 / 10) << what;
}

TEST(BvhTraversal, SceneTriangleSoupMatchesBruteForce) {
  Rng rng(4);
  Scene scene;
  TriangleMesh soup;
  for (uint32_t i = 0; i < 3000; ++i) {
    DVec3 c(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10));
    double s = rng.log_uniform(0.01, 2);
    for (int k = 0; k < 3; ++k) soup.positions.push_back(to_f(c + s * rng.in_unit_ball()));
    soup.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  scene.meshes.push_back(soup);
  for (int k = 0; k < 20; ++k)
    scene.spheres.push_back(rayscope::Sphere{
        "s", to_f(DVec3(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10))),
        rstest::round_f(rng.log_uniform(0.05, 1)), 0});
  compare_scene_with_brute_force(scene, rng, 20000, "triangle soup + spheres");
}

TEST(BvhTraversal, SceneClosedMeshesAndPlaneMatchBruteForce) {
  // Meshes with shared edges and vertices, axis-aligned bounds on many nodes,
  // and a plane (tested outside the BVH).
  Rng rng(5);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 2.0f, 3));
  scene.meshes.push_back(make_torus(Vec3(3.0f, 0.0f, 0.0f), 1.5f, 0.4f, 32, 16));
  TriangleMesh cube;  // unit cube at (-4, 0, 0), 12 triangles
  for (int i = 0; i < 8; ++i)
    cube.positions.push_back(Vec3(-4.0f + float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)));
  cube.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  scene.meshes.push_back(cube);
  scene.spheres.push_back(rayscope::Sphere{"s", Vec3(0, 3, 0), 0.5f, 0});
  scene.planes.push_back(Plane{"floor", Vec3(0, -3, 0), Vec3(0, 1, 0), 0});
  compare_scene_with_brute_force(scene, rng, 20000, "closed meshes + plane");

  // Rays running exactly in the plane of a cube face hit the edge of the
  // perpendicular face (the watertight test reports edge hits); the BVH must
  // not cull the box they touch.
  SurfaceHit hit;
  for (float x : {-4.0f, -3.0f})
    for (float y : {0.0f, 0.5f, 1.0f}) {
      Ray ray{Vec3(x, y, -5.0f), Vec3(0, 0, 1), kInfinity};
      BruteHit bf = brute_force(scene, ray, false);
      ASSERT_NE(bf.t, kInfinity);
      ASSERT_TRUE(scene.intersect(ray, hit)) << "x=" << x << " y=" << y;
      EXPECT_EQ(hit.t, bf.t);
      EXPECT_EQ(hit.object, 2u);
      EXPECT_TRUE(scene.occluded(ray));
    }
}

struct CountingObserver {
  static constexpr bool kActive = true;
  std::vector<int>* node_visits;
  std::vector<int>* prim_tests;
  int boxes = 0, culled = 0;
  void on_node(uint32_t n) { (*node_visits)[n]++; }
  void on_box_test() { ++boxes; }
  void on_cull(uint32_t) { ++culled; }
  void on_prim_test(uint32_t p) { (*prim_tests)[p]++; }
};

TEST(BvhTraversal, ObserverSeesEveryNodeVisitOnce) {
  // The observer hooks count what traversal does; each visited node is a real
  // node, and a primitive is tested at most once per ray.
  Rng rng(6);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 4));
  scene.commit();
  size_t nodes = scene.bvh().nodes.size(), prims = scene.meshes[0].triangles.size();
  uint64_t total_prim_tests = 0;
  for (int i = 0; i < 2000; ++i) {
    std::vector<int> nv(nodes, 0), pt(prims, 0);
    CountingObserver c{&nv, &pt};
    Ray ray{to_f(3.0 * rng.unit_vector()), to_f(rng.unit_vector()), kInfinity};
    SurfaceHit hit;
    scene.intersect(ray, hit, c);
    int visited = 0;
    for (int v : nv) {
      ASSERT_LE(v, 1);
      visited += v;
    }
    for (int v : pt) {
      ASSERT_LE(v, 1);
      total_prim_tests += uint64_t(v);
    }
    // Box tests: the root plus two per visited inner node.
    int inner = 0;
    for (size_t n = 0; n < nodes; ++n)
      if (nv[n] && !scene.bvh().nodes[n].is_leaf()) ++inner;
    if (visited > 0) {
      EXPECT_EQ(c.boxes, 1 + 2 * inner);
    }
  }
  // The hierarchy prunes: far fewer than all 5120 triangles per ray.
  EXPECT_LT(total_prim_tests, uint64_t(2000) * prims / 20);
}

}  // namespace
