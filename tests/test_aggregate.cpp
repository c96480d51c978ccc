// The aggregate (aggregate.h): scene queries through every structure it can
// walk (the 8-wide BVH renders use, the binary teaching walk, no structure),
// against brute force over all primitives. Every structure returns the same
// hit bit for bit, including which primitive wins an exact tie in t; an
// observed query returns exactly what the plain query returns; the observer
// sees the walk of the chosen structure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "accel_test_util.h"
#include "rayscope/scene.h"
#include "rayscope/shapes.h"

namespace {

using namespace rayscope;
using rstest::AlwaysActive;
using rstest::brute_force;
using rstest::BruteHit;
using rstest::check_queries;
using rstest::DVec3;
using rstest::random_ray;
using rstest::Rng;
using rstest::same_bits;
using rstest::soup_scene;
using rstest::to_d;
using rstest::to_f;

class AggregateKind : public ::testing::TestWithParam<AccelKind> {
 protected:
  void commit(Scene& scene) {
    AccelConfig cfg;
    cfg.kind = GetParam();
    scene.commit(cfg);
    ASSERT_EQ(scene.accel().kind(), GetParam());
    ASSERT_EQ(scene.summary().walks_structure, GetParam() != AccelKind::None);
  }
};
INSTANTIATE_TEST_SUITE_P(Accel, AggregateKind,
                         ::testing::Values(AccelKind::Bvh, AccelKind::BinaryBvh, AccelKind::None),
                         [](const auto& info) {
                           return std::string(
                               info.param == AccelKind::BinaryBvh ? "bvh2" : to_string(info.param));
                         });

TEST_P(AggregateKind, RandomRaysMatchBruteForce) {
  Rng rng(15);
  Scene scene = soup_scene(rng);
  commit(scene);
  std::vector<Ray> rays;
  rstest::add_random_rays(rng, scene, scene.bvh().bounds(), 20000, rays);
  check_queries(scene, rays, "meshes + soup + spheres + plane", 0);
}

TEST_P(AggregateKind, TiesAtVerticesAndEdgesResolveLikeBruteForce) {
  // Rays through the vertices and edge midpoints of closed meshes, and along
  // the axes through an axis-aligned cube's faces, edges and corners: several
  // triangles are hit at exactly the same t, and the winner must not depend
  // on the structure or its walk. Rays lying exactly in a cube face's plane
  // hit the edge of the perpendicular face; the walk must not cull the box
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
  check_queries(scene, rays, "vertex, edge and face-plane rays", 20);
}

TEST(Aggregate, EveryStructureGivesTheSameHitsBitForBit) {
  // The same scene committed with each kind: identical PrimHits for every ray
  // (t, barycentrics, record, primitive, plane).
  Rng rng(17);
  Scene scene = soup_scene(rng);
  scene.commit();
  std::vector<Ray> rays;
  rstest::add_random_rays(rng, scene, scene.bvh().bounds(), 5000, rays);
  std::vector<std::vector<PrimHit>> per_kind;
  for (AccelKind kind : kAccelKinds) {
    AccelConfig cfg;
    cfg.kind = kind;
    scene.commit(cfg);
    std::vector<PrimHit> hits(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) scene.intersect(rays[i], hits[i]);
    per_kind.push_back(std::move(hits));
  }
  for (size_t k = 1; k < per_kind.size(); ++k)
    for (size_t i = 0; i < rays.size(); ++i)
      ASSERT_TRUE(same_bits(per_kind[0][i], per_kind[k][i])) << "kind " << k << " ray " << i;
}

struct WalkObserver : TraversalHooks {
  static constexpr bool kActive = true;
  std::vector<int>* node_visits;
  std::vector<int>* prim_tests;
  explicit WalkObserver(std::vector<int>* nv, std::vector<int>* pt)
      : node_visits(nv), prim_tests(pt) {}
  void on_node(uint32_t n) { (*node_visits).at(n)++; }
  void on_prim_test(uint32_t p) { (*prim_tests).at(p)++; }
};

TEST_P(AggregateKind, ObserverSeesTheChosenWalk) {
  // What the observer sees tells the structure apart: with the 8-wide BVH
  // every entered inner node is the top of a wide node (the nodes a wide node
  // swallows are never reported), with the binary walk every entered inner
  // node's parent was entered too, without a structure no node at all and
  // every primitive. A primitive is tested at most once per ray; a structure
  // prunes far below the brute-force count.
  Rng rng(6);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 4));
  commit(scene);
  const Bvh& bvh = scene.bvh();
  const WideBvh& walk = scene.accel().structure_as<BvhWalk>().walk();
  std::vector<int> is_top(bvh.nodes.size(), 0), parent(bvh.nodes.size(), -1);
  is_top[0] = 1;
  for (size_t n = 0; n < walk.nodes.size(); ++n)
    for (int k = 0; k < WideBvhNode::kWidth; ++k) {
      const uint32_t src = walk.slot_source[WideBvhNode::kWidth * n + k];
      if (src != ~0u) is_top[src] = 1;
    }
  for (uint32_t n = 0; n < bvh.nodes.size(); ++n)
    if (!bvh.nodes[n].is_leaf())
      parent[bvh.nodes[n].index] = parent[bvh.nodes[n].index + 1] = int(n);
  const size_t prims = scene.meshes[0].triangles.size();
  uint64_t prim_tests = 0;
  int swallowed_nodes = 0;
  for (int i = 0; i < 2000; ++i) {
    std::vector<int> nv(bvh.nodes.size(), 0), pt(prims, 0);
    WalkObserver obs(&nv, &pt);
    const Ray ray{to_f(3.0 * rng.unit_vector()), to_f(rng.unit_vector()), kInfinity};
    SurfaceHit hit;
    scene.intersect(ray, hit, obs);
    for (size_t n = 0; n < nv.size(); ++n) {
      ASSERT_LE(nv[n], 1) << "node " << n;
      if (!nv[n]) continue;
      ASSERT_NE(GetParam(), AccelKind::None);
      ASSERT_TRUE(is_top[n]) << "node " << n << " is not a node of the walked tree";
      if (GetParam() == AccelKind::BinaryBvh && n > 0) {
        ASSERT_EQ(nv[size_t(parent[n])], 1) << "node " << n << " entered without its parent";
      }
      if (GetParam() == AccelKind::Bvh && n > 0 && !nv[size_t(parent[n])]) ++swallowed_nodes;
    }
    for (int v : pt) {
      ASSERT_LE(v, 1);
      prim_tests += uint64_t(v);
    }
  }
  if (GetParam() == AccelKind::None) {
    EXPECT_EQ(prim_tests, uint64_t(2000) * prims);
  } else {
    EXPECT_LT(prim_tests, uint64_t(2000) * prims / 20);
  }
  if (GetParam() == AccelKind::Bvh) {
    EXPECT_GT(swallowed_nodes, 0);
  }
}

TEST(Aggregate, KindNamesRoundTrip) {
  for (AccelKind k : kAccelKinds) {
    AccelKind parsed = AccelKind::None;
    ASSERT_TRUE(parse_accel_kind(to_string(k), parsed));
    EXPECT_EQ(parsed, k);
  }
  AccelKind k = AccelKind::Bvh;
  EXPECT_FALSE(parse_accel_kind("bsp2", k));
  EXPECT_FALSE(parse_accel_kind("", k));
  EXPECT_EQ(k, AccelKind::Bvh);
}

TEST(Aggregate, MemoryCountsEveryStructure) {
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 3));
  scene.planes.push_back(Plane{"floor", Vec3(0, -5, 0), Vec3(0, 1, 0), 0});
  scene.commit();
  const Aggregate& a = scene.accel();
  EXPECT_EQ(a.memory_bytes(),
            a.bvh().quality().memory_bytes + a.structure_as<BvhWalk>().walk().memory_bytes() +
                (a.structure_as<BvhWalk>().triangle_blocks().size() * sizeof(TriangleBlock)) +
                a.records().size() * sizeof(PrimRecord) + sizeof(PlaneRecord));
  EXPECT_GT(a.structure_as<BvhWalk>().walk().memory_bytes(), 0u);
  // One block per started group of TriangleBlock::kLanes records of each leaf.
  size_t blocks = 0;
  for (const BvhNode& n : a.bvh().nodes)
    if (n.is_leaf()) blocks += (n.count + TriangleBlock::kLanes - 1) / TriangleBlock::kLanes;
  EXPECT_EQ(a.structure_as<BvhWalk>().triangle_blocks().size(), blocks);
  EXPECT_EQ((a.structure_as<BvhWalk>().triangle_blocks().size() * sizeof(TriangleBlock)),
            blocks * sizeof(TriangleBlock));
}

TEST(Aggregate, WalkLeavesNameTheirFirstBlockAndItsRecords) {
  // Every leaf child of the walk holds its leaf's first triangle block, and
  // each of the leaf's blocks names the record of its lane 0 and holds that
  // record's vertices, lane by lane. Leaves of up to 16 records (cheap
  // primitives in the SAH), so that most take more than one block.
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 3));
  AccelConfig cfg;
  cfg.bvh.max_leaf_size = 16;
  cfg.bvh.intersection_cost = 0.05f;
  scene.commit(cfg);
  const Aggregate& a = scene.accel();
  const WideBvh& walk = a.structure_as<BvhWalk>().walk();
  const auto& blocks = a.structure_as<BvhWalk>().triangle_blocks();
  constexpr int W = WideBvhNode::kWidth, L = TriangleBlock::kLanes;
  int leaves = 0;
  for (size_t n = 0; n < walk.nodes.size(); ++n)
    for (int k = 0; k < W; ++k) {
      const uint32_t src = walk.slot_source[W * n + k];
      const uint32_t child = walk.nodes[n].child[k];
      if (src == ~0u || !(child & WideBvhNode::kLeaf)) continue;
      ++leaves;
      const BvhNode& leaf = a.bvh().nodes[src];
      const uint32_t block = child & ~WideBvhNode::kLeaf;
      ASSERT_EQ(walk.nodes[n].count[k], leaf.count);
      for (uint32_t j = 0; j < leaf.count; ++j) {
        ASSERT_LT(block + j / L, blocks.size());
        const TriangleBlock& b = blocks[block + j / L];
        EXPECT_EQ(b.first, leaf.index + j - j % L);
        const PrimRecord& r = a.records()[leaf.index + j];
        EXPECT_EQ(b.v[0][0][j % L], r.a.x);
        EXPECT_EQ(b.v[1][1][j % L], r.b.y);
        EXPECT_EQ(b.v[2][2][j % L], r.c.z);
      }
    }
  EXPECT_GT(leaves, 1);
  EXPECT_GT(a.bvh().quality().max_leaf_prims, uint32_t(L));
}

TEST(Aggregate, TinyScenesSkipTheStructureUnlessAsked) {
  Scene scene;
  for (int k = 0; k < int(Aggregate::kBruteForceMax); ++k)
    scene.spheres.push_back(rayscope::Sphere{"s", Vec3(float(3 * k), 0, 0), 1.0f, 0});
  scene.commit();
  EXPECT_FALSE(scene.accel().walks_structure());
  AccelConfig cfg;
  cfg.allow_brute_force = false;
  scene.commit(cfg);
  EXPECT_TRUE(scene.accel().walks_structure());
  scene.spheres.push_back(rayscope::Sphere{"s", Vec3(-3, 0, 0), 1.0f, 0});
  scene.commit();
  EXPECT_TRUE(scene.accel().walks_structure());
}

}  // namespace
