// The aggregate (aggregate.h) itself: the names of the structures, the one
// check of structure and storage, what the BVH walks' observers see (the
// 8-wide walk enters the tops of its wide nodes only, the binary walk every
// node on the way), memory, the walk's triangle blocks, tiny scenes that skip
// the structure. What every structure does (queries == brute force, ties,
// any hit, observed == plain, the same hits and images as the BVH, range
// queries) is test_accel_conformance's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <memory>

#include <tbb/global_control.h>

#include "accel_test_util.h"
#include "rayscope/accel/accel_view.h"
#include "rayscope/intersect_capsule.h"
#include "rayscope/render.h"
#include "rayscope/scene.h"
#include "rayscope/shapes.h"
#include "written_heap.h"

namespace {

using namespace rayscope;
using rstest::Rng;
using rstest::to_f;

// The BVH's two walks: the 8-wide one renders use and the binary teaching one.
class AggregateKind : public ::testing::TestWithParam<AccelKind> {
 protected:
  void commit(Scene& scene) {
    AccelConfig cfg;
    cfg.kind = GetParam();
    scene.commit(cfg);
    ASSERT_EQ(scene.accel().kind(), GetParam());
    ASSERT_TRUE(scene.summary().walks_structure);
  }
};
INSTANTIATE_TEST_SUITE_P(Accel, AggregateKind,
                         ::testing::Values(AccelKind::Bvh, AccelKind::BinaryBvh),
                         [](const auto& info) { return std::string(to_string(info.param)); });

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
  // What the observer sees tells the walks apart: with the 8-wide BVH every
  // entered inner node is the top of a wide node (the nodes a wide node
  // swallows are never reported), with the binary walk every entered inner
  // node's parent was entered too. A primitive is tested at most once per
  // ray; the walk prunes far below the brute-force count. (Without a
  // structure, no node and every primitive: test_accel_conformance.)
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
      const uint32_t src =
          scene.accel().structure_as<BvhWalk>().slot_sources()[WideBvhNode::kWidth * n + k];
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
  EXPECT_LT(prim_tests, uint64_t(2000) * prims / 20);
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
  // The names the CLI, the VTK module and the ray trees use.
  const char* names[] = {"bvh", "bvh2", "kdtree", "grid", "octree", "bsp", "spheres", "none"};
  ASSERT_EQ(std::size(names), std::size(kAccelKinds));
  for (size_t i = 0; i < std::size(names); ++i) EXPECT_STREQ(to_string(kAccelKinds[i]), names[i]);
  AccelKind k = AccelKind::Bvh;
  EXPECT_FALSE(parse_accel_kind("bsp2", k));
  EXPECT_FALSE(parse_accel_kind("", k));
  EXPECT_EQ(k, AccelKind::Bvh);
}

TEST(Aggregate, OneCheckOfStructureAndStorage) {
  // Every kind takes every-cell (the default); the spatial subdivisions
  // (kD-tree, grid, octree, BSP tree) take smallest-cell; only the BSP tree
  // splits. The aggregate refuses what the check refuses, with its message.
  for (AccelKind k : kAccelKinds) {
    const bool spatial = k == AccelKind::KdTree || k == AccelKind::Grid || k == AccelKind::Octree ||
                         k == AccelKind::Bsp;
    EXPECT_EQ(accel_storage_error(k, PrimStorage::EveryCell), "");
    EXPECT_EQ(accel_storage_error(k, PrimStorage::SmallestCell).empty(), spatial);
    EXPECT_EQ(accel_storage_error(k, PrimStorage::Split).empty(), k == AccelKind::Bsp);
  }
  const std::string kd = accel_storage_error(AccelKind::KdTree, PrimStorage::Split);
  EXPECT_NE(kd.find("split"), std::string::npos) << kd;
  EXPECT_NE(kd.find("kdtree"), std::string::npos) << kd;
  EXPECT_EQ(kd.find('\n'), std::string::npos);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 1));
  AccelConfig ac;
  ac.kind = AccelKind::KdTree;
  ac.storage = PrimStorage::Split;
  try {
    scene.commit(ac);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(kd), std::string::npos) << e.what();
  }
  ac.kind = AccelKind::Octree;
  ac.storage = PrimStorage::Split;
  EXPECT_THROW(scene.commit(ac), std::invalid_argument);
}

// A mesh, a tube set, a point set, a sphere and a plane, with many triangles
// so that the hierarchy has many levels.
Scene scene_of_every_shape(int subdivisions = 3) {
  Scene s;
  s.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, subdivisions));
  TubeSet line;
  line.name = "line";
  line.positions = {Vec3(-4, 0, 0), Vec3(0, 2, 0), Vec3(4, 0, 1)};
  line.segments = {{0, 1}, {1, 2}};
  line.radius = 0.25f;
  s.tubes.push_back(line);
  PointSet dots;
  dots.name = "dots";
  dots.positions = {Vec3(0, 5, 0), Vec3(3, 5, 0), Vec3(-2, 3, 1)};
  dots.radii = {0.5f, 1.0f, 0.3f};
  s.points.push_back(dots);
  s.spheres.push_back(rayscope::Sphere{"ball", Vec3(0.3f, -5, 0.1f), 1.3f, 0});
  s.planes.push_back(Plane{"floor", Vec3(0, -20, 0), Vec3(0, 1, 0), 0});
  return s;
}

TEST(Aggregate, APlainRenderHoldsWhatItWalksAndTheToolsBuildTheRestWhenAsked) {
  Scene scene = scene_of_every_shape();
  scene.commit();
  const Aggregate& a = scene.accel();
  const BvhWalk& w = a.structure_as<BvhWalk>();
  constexpr size_t W = WideBvhNode::kWidth;
  // The walk's nodes and blocks, each record's id, the records of the two
  // tube segments, three points and the sphere (the blocks hold the
  // triangles), and the plane.
  const size_t prims = scene.meshes[0].triangles.size() + 6;
  const size_t walked = w.walk().nodes.size() * sizeof(WideBvhNode) +
                        w.triangle_blocks().size() * sizeof(TriangleBlock) + prims * 4 +
                        6 * sizeof(PrimRecord) + sizeof(PlaneRecord);
  EXPECT_GT(w.walk().nodes.size(), 1u);
  EXPECT_EQ(a.memory_bytes(), walked);
  // Renders with packets and with single rays build nothing more.
  RenderSettings rs;
  rs.width = 48;
  rs.height = 32;
  for (bool packets : {true, false}) {
    rs.packets = packets;
    RayCounters counters;
    render(scene, rs, &counters);
    EXPECT_EQ(counters.nodes_visited, 0u);
  }
  EXPECT_EQ(a.memory_bytes(), walked);
  // Statistics (which count nodes without naming them) walk the records one
  // by one, so they make the records, with every vertex; nothing else.
  rs.statistics = true;
  {
    RayCounters counters;
    render(scene, rs, &counters);
    EXPECT_GT(counters.nodes_visited, 0u);
  }
  const size_t records = prims * sizeof(PrimRecord);
  EXPECT_EQ(a.memory_bytes(), walked + records);

  // The binary tree built when asked is the one the commit built, from
  // every primitive's box in the scene's order, node for node: the triangles'
  // boxes, the tube segments' and points' rounded-out capsule boxes and the
  // sphere's box, each centered on its box but the sphere (on its center).
  std::vector<Bounds3> boxes;
  std::vector<Vec3> centers;
  const TriangleMesh& m = scene.meshes[0];
  for (const glm::uvec3& t : m.triangles) {
    Bounds3 b(m.positions[t.x]);
    b.extend(m.positions[t.y]);
    b.extend(m.positions[t.z]);
    boxes.push_back(b);
  }
  const TubeSet& ts = scene.tubes[0];
  for (const glm::uvec2& sg : ts.segments)
    boxes.push_back(capsule_bounds(ts.positions[sg.x], ts.positions[sg.y], ts.radius));
  const PointSet& ps = scene.points[0];
  for (size_t j = 0; j < ps.positions.size(); ++j)
    boxes.push_back(capsule_bounds(ps.positions[j], ps.positions[j], ps.radii[j]));
  for (const Bounds3& b : boxes) centers.push_back(b.center());
  const rayscope::Sphere& ball = scene.spheres[0];
  boxes.emplace_back(ball.center - Vec3(ball.radius), ball.center + Vec3(ball.radius));
  centers.push_back(ball.center);
  Bvh expected;
  expected.build(boxes, centers, a.config().bvh);

  const Bvh& bvh = a.bvh();
  ASSERT_EQ(bvh.nodes.size(), expected.nodes.size());
  EXPECT_EQ(
      std::memcmp(bvh.nodes.data(), expected.nodes.data(), bvh.nodes.size() * sizeof(BvhNode)), 0);
  EXPECT_EQ(bvh.prim_indices, expected.prim_indices);
  const size_t binary = bvh.nodes.size() * sizeof(BvhNode) + bvh.prim_indices.size() * 4;
  EXPECT_EQ(a.memory_bytes(), walked + records + binary);
  // An observer's walk makes the wide slots' binary ids, once, and enters
  // binary nodes by them.
  rstest::CountingObserver obs(bvh.nodes.size(), a.records().size());
  PrimHit hit;
  const Ray ray{Vec3(0.1f, 0.2f, 10.0f), Vec3(0.0f, 0.0f, -1.0f)};
  ASSERT_TRUE(a.intersect(ray, hit, obs));
  EXPECT_GT(obs.order.size(), 1u);
  EXPECT_EQ(obs.order[0], 0u);
  EXPECT_EQ(w.slot_sources().size(), W * w.walk().nodes.size());
  EXPECT_EQ(a.memory_bytes(), walked + records + binary + W * w.walk().nodes.size() * 4);
}

// Every byte an aggregate holds that grows with its scene is counted by
// memory_bytes(), for every structure and storage: the heap bytes its commit
// leaves written (written_heap.h), and those the tools' parts add when first
// asked for (the binary tree, every primitive's record, the wide slots'
// binary ids). What is left is the same for a scene with four times the
// triangles: the aggregate's few holders of a fixed size (shared pointers'
// blocks, locks) and the scene's first primitive of each object, under
// kFixedBytes. The bytes per triangle of bench_trace
// and docs/performance.md are these counts.
TEST(Aggregate, MemoryCountsEveryStructure) {
  // The measure itself: a vector's elements are written, its reserve is not.
  {
    written_heap::start();
    std::vector<uint32_t> v;
    v.reserve(1000);
    v.resize(10, 7u);
    const written_heap::Held held = written_heap::stop();
    EXPECT_EQ(held.bytes, 10 * sizeof(uint32_t));
    EXPECT_EQ(held.blocks, 1u);
  }
  // On one thread, and after a first commit of the larger scene: what the
  // builders keep per thread for their next build (the binary builder's node
  // array for a subtree, bvh_builder.h) is made before the measures, once.
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  {
    Scene warm = scene_of_every_shape(4);
    warm.commit();
  }
  constexpr size_t kFixedBytes = 1024;
  for (AccelKind kind : kAccelKinds)
    for (PrimStorage storage : kPrimStorages) {
      if (!accel_storage_error(kind, storage).empty()) continue;
      const std::string name = std::string(to_string(kind)) + " " + to_string(storage);
      // Per part (the commit, then each one asked for): bytes held but not
      // counted, for the scene with 1280 triangles and then with 5120.
      std::vector<size_t> uncounted[2];
      for (int size = 0; size < 2; ++size) {
        Scene scene = scene_of_every_shape(3 + size);
        AccelConfig ac;
        ac.kind = kind;
        ac.storage = storage;
        auto part = [&](const char* what, auto&& make) {
          const Aggregate& a = scene.accel();
          const size_t before = a.memory_bytes();
          written_heap::start();
          make();
          const written_heap::Held held = written_heap::stop();
          const size_t counted = a.memory_bytes() - before;
          EXPECT_GE(held.bytes, counted) << name << ", " << what << ", blocks:" << held.sizes;
          EXPECT_LE(held.bytes, counted + kFixedBytes)
              << name << ", " << what << ", blocks:" << held.sizes;
          uncounted[size].push_back(held.bytes - counted);
        };
        part("the commit", [&] { scene.commit(ac); });
        part("the binary tree", [&] { scene.accel().bvh(); });
        part("the records", [&] { scene.accel().records(); });
        if (kind == AccelKind::Bvh)
          part("the slots' ids", [&] { scene.accel().structure_as<BvhWalk>().slot_sources(); });
      }
      EXPECT_EQ(uncounted[0], uncounted[1]) << name;
    }
}

TEST(Aggregate, ACopyBuildsItsHierarchyFromItsOwnRecords) {
  // The hierarchy of a copy outlives the scene it was copied from, whether
  // the original had built it (shared) or not (built from the copy's records).
  for (bool asked_before : {false, true}) {
    auto original = std::make_unique<Scene>(scene_of_every_shape());
    original->commit();
    const std::vector<BvhNode> nodes = Scene(*original).bvh().nodes;
    if (asked_before) original->bvh();
    Scene copy = *original;
    original.reset();
    ASSERT_EQ(copy.bvh().nodes.size(), nodes.size()) << asked_before;
    EXPECT_EQ(std::memcmp(copy.bvh().nodes.data(), nodes.data(), nodes.size() * sizeof(BvhNode)),
              0);
    const BvhWalk& w = copy.accel().structure_as<BvhWalk>();
    EXPECT_EQ(w.slot_sources().size(), WideBvhNode::kWidth * w.walk().nodes.size());
    EXPECT_EQ(make_accel_view(copy.accel()).nodes.size(), nodes.size());
  }
}

TEST(Aggregate, TheRecordsMadeFromTheBlocksAreTheRecords) {
  // Behind the BVH (8-wide and binary) a render keeps each record's id, and
  // the records are made from the blocks when asked: byte for byte the ones
  // a kD-tree keeps (every structure has the binary BVH's leaf order), and
  // the scene's own, also in a copy that outlives its original.
  Scene held_scene = scene_of_every_shape();
  AccelConfig kd;
  kd.kind = AccelKind::KdTree;
  held_scene.commit(kd);
  const std::vector<PrimRecord>& held = held_scene.accel().records();
  ASSERT_EQ(held.size(), held_scene.meshes[0].triangles.size() + 6);
  for (size_t i = 0; i < held.size(); ++i) {
    const PrimRecord r = held_scene.prim_record(held[i].id);
    EXPECT_EQ(std::memcmp(&r, &held[i], sizeof r), 0) << i;
  }
  for (AccelKind kind : {AccelKind::Bvh, AccelKind::BinaryBvh}) {
    auto original = std::make_unique<Scene>(scene_of_every_shape());
    AccelConfig cfg;
    cfg.kind = kind;
    original->commit(cfg);
    Scene copy = *original;
    for (const Scene* s : {original.get(), &copy}) {
      EXPECT_EQ(s->accel().record_ids().size(), held.size());
      EXPECT_EQ(s->accel().other_records().size(), 6u);
    }
    original.reset();
    const std::vector<PrimRecord>& made = copy.accel().records();
    ASSERT_EQ(made.size(), held.size()) << to_string(kind);
    EXPECT_EQ(std::memcmp(made.data(), held.data(), held.size() * sizeof(PrimRecord)), 0)
        << to_string(kind);
  }
}

TEST(Aggregate, WalkLeavesNameTheirFirstLaneAndItsRecords) {
  // Every leaf child of the walk holds its leaf's first lane of the triangle
  // blocks (block * kLanes + lane), and lane after lane from there holds the
  // leaf's records' vertices; each block names the record of its lane 0.
  // A leaf of up to kLanes records lies in one block, so it takes one block
  // test. Leaves of up to 16 records (cheap primitives in the SAH), so that
  // many take more than one block, and with the default costs, whose small
  // leaves share blocks: fewer blocks than if each leaf began its own.
  for (bool big_leaves : {true, false}) {
    Scene scene;
    scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 3));
    AccelConfig cfg;
    if (big_leaves) {
      cfg.bvh.max_leaf_size = 16;
      cfg.bvh.intersection_cost = 0.05f;
    }
    scene.commit(cfg);
    const Aggregate& a = scene.accel();
    const BvhWalk& w = a.structure_as<BvhWalk>();
    const WideBvh& walk = w.walk();
    const auto& blocks = w.triangle_blocks();
    constexpr int W = WideBvhNode::kWidth, L = TriangleBlock::kLanes;
    int leaves = 0;
    size_t own_blocks = 0;
    for (size_t n = 0; n < walk.nodes.size(); ++n)
      for (int k = 0; k < W; ++k) {
        const uint32_t src = w.slot_sources()[W * n + k];
        const uint32_t child = walk.nodes[n].child[k];
        if (src == ~0u || !(child & WideBvhNode::kLeaf)) continue;
        ++leaves;
        const BvhNode& leaf = a.bvh().nodes[src];
        own_blocks += (leaf.count + L - 1) / L;
        const uint32_t start = child & ~WideBvhNode::kLeaf;
        ASSERT_EQ(walk.nodes[n].count[k], leaf.count);
        if (leaf.count <= uint32_t(L)) {
          EXPECT_EQ(start / L, (start + leaf.count - 1) / L);
        }
        for (uint32_t j = 0; j < leaf.count; ++j) {
          const uint32_t lane = start + j;
          ASSERT_LT(lane / L, blocks.size());
          const TriangleBlock& b = blocks[lane / L];
          EXPECT_EQ(b.first + lane % L, leaf.index + j);
          EXPECT_TRUE((b.triangles >> (lane % L)) & 1u);
          const PrimRecord& r = a.records()[leaf.index + j];
          EXPECT_EQ(b.v[0][0][lane % L], r.a.x);
          EXPECT_EQ(b.v[1][1][lane % L], r.b.y);
          EXPECT_EQ(b.v[2][2][lane % L], r.c.z);
        }
      }
    EXPECT_GT(leaves, 1);
    if (big_leaves) {
      EXPECT_LE(blocks.size(), own_blocks);
      EXPECT_GT(a.bvh().quality().max_leaf_prims, uint32_t(L));
    } else {
      EXPECT_LT(blocks.size(), own_blocks);
    }
  }
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
