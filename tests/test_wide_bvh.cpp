// The one BVH walk (wide_bvh.h), for the arities it is built with: 8 (what
// renders walk), 4 and 2 (the binary teaching walk). Structure of the
// collapse, the SIMD 8-box test and its fallbacks (SSE, scalar) against
// intersect_box() lane by lane (bit for bit, NaN slabs included), closest-hit
// / any-hit walks against brute force, and the observer hooks (binary node
// ids, every box test with its outcome, culls). Scene queries through the
// aggregate: test_aggregate.
//
// This file is compiled for the baseline (SSE2: the two-halves box test), and
// once more for each higher x86-64 level the build machine runs
// (tests/CMakeLists.txt: avx2.*, avx512.*: the 8-lane AVX box test), so that
// every box test a CPU may run is tested.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <functional>
#include <set>

#include "accel_test_util.h"
#include "rayscope/accel/wide_bvh.h"
#include "rayscope/shapes.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::random_ray;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

using rstest::BoxLayout;
using rstest::BoxLeaves;
using rstest::Prims;

// The arities the walk is built with: 2 (teaching) and kRenderArity = 8
// (rendering), and 4 between them.
class WideBvhArity : public ::testing::TestWithParam<int> {};
static_assert(WideBvh::kRenderArity == 8);
INSTANTIATE_TEST_SUITE_P(Arity, WideBvhArity, ::testing::Values(2, 4, 8),
                         [](const auto& info) { return "arity" + std::to_string(info.param); });

// Every binary leaf appears exactly once as a wide leaf with the same
// primitive range and box; inner children carry their binary node's box; empty
// slots come last, have empty boxes and no primitives; slot_source names the
// binary node of every slot; no node has more children than the arity (with
// arity 2: exactly one wide node per binary inner node); the depth fits the
// stack. A leaf child holds its first primitive, or its label where `label`
// is given (build()'s leaf_label).
void check_collapse(const Bvh& bvh, const WideBvh& w, std::span<const uint32_t> label = {}) {
  if (bvh.empty()) {
    EXPECT_TRUE(w.empty());
    EXPECT_TRUE(w.nodes.empty());
    return;
  }
  ASSERT_FALSE(w.empty());
  constexpr int W = WideBvhNode::kWidth;
  ASSERT_EQ(w.slot_source.size(), W * w.nodes.size());
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
    const WideBvhNode& node = w.nodes[n];
    bool empty_seen = false;
    int children = 0;
    for (int k = 0; k < W; ++k) {
      const uint32_t src = w.slot_source[W * n + k];
      if (src == ~0u) {
        empty_seen = true;
        EXPECT_EQ(node.child[k], WideBvhNode::kLeaf);
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
        EXPECT_EQ(node.child[k], WideBvhNode::kLeaf | (label.empty() ? b.index : label[b.index]));
        EXPECT_EQ(node.count[k], b.count);
        EXPECT_TRUE(seen_leaves.insert(src).second) << "binary leaf " << src << " twice";
      } else {
        EXPECT_EQ(node.child[k] & WideBvhNode::kLeaf, 0u);
        EXPECT_EQ(node.count[k], 0u);
        walk(node.child[k], level + 1);
      }
    }
    EXPECT_GE(children, 2) << "wide node " << n;
    EXPECT_LE(children, w.arity()) << "wide node " << n;
  };
  walk(0, 1);
  EXPECT_EQ(seen_leaves, binary_leaves);
  for (size_t n = 0; n < reached.size(); ++n) EXPECT_EQ(reached[n], 1) << "wide node " << n;
  EXPECT_EQ(w.depth(), max_level);
  EXPECT_LE(uint32_t(WideBvh::kMaxArity - 1) * w.depth(), uint32_t(WideBvh::kStackSize));
  EXPECT_LE(w.depth(), bvh.quality().depth);
  if (w.arity() == 2) {
    EXPECT_EQ(w.nodes.size(), bvh.nodes.size() - binary_leaves.size());
    EXPECT_EQ(w.depth() + 1, bvh.quality().depth);
  }
}

TEST_P(WideBvhArity, CollapseKeepsEveryLeafAndBox) {
  Rng rng(11);
  const BvhBuildConfig configs[] = {{}, {4, 1, 1, 1.0f, 1.0f, 56}, {64, 32, 4, 0.5f, 1.0f, 56}};
  for (BoxLayout layout : {BoxLayout::Uniform, BoxLayout::LogUniform})
    for (int n : {0, 1, 2, 3, 5, 9, 100, 3000})
      for (const BvhBuildConfig& cfg : configs) {
        SCOPED_TRACE("n=" + std::to_string(n) + " max_leaf=" + std::to_string(cfg.max_leaf_size));
        Prims p = random_boxes(rng, n, layout);
        Bvh bvh;
        bvh.build(p.bounds, p.centroids, cfg);
        WideBvh w;
        w.build(bvh, GetParam());
        EXPECT_EQ(w.arity(), GetParam());
        check_collapse(bvh, w);
        if (HasFatalFailure()) return;
        // The same collapse with leaves labelled (as the aggregate labels them
        // by their first block): only the leaf children change.
        std::vector<uint32_t> label(bvh.prim_indices.size());
        for (size_t i = 0; i < label.size(); ++i) label[i] = uint32_t(7 * i + 3);
        WideBvh labelled;
        labelled.build(bvh, GetParam(), label);
        check_collapse(bvh, labelled, label);
        if (HasFatalFailure()) return;
      }
}

TEST(WideBvhBuild, RejectsLeafLabelsOfTheWrongSizeOrTooLarge) {
  Prims p;
  p.add(Bounds3(Vec3(0), Vec3(1)));
  p.add(Bounds3(Vec3(2), Vec3(3)));
  Bvh bvh;
  bvh.build(p.bounds, p.centroids, {1, 1, 1, 1.0f, 1.0f, 56});
  ASSERT_FALSE(bvh.nodes[0].is_leaf());
  WideBvh w;
  const std::vector<uint32_t> one(1, 0u), too_large(2, WideBvhNode::kLeaf);
  EXPECT_THROW(w.build(bvh, 8, one), std::invalid_argument);
  EXPECT_THROW(w.build(bvh, 8, too_large), std::length_error);
  const std::vector<uint32_t> ok{5u, 9u};
  w.build(bvh, 8, ok);
  // The walk passes the labels to the leaf function.
  std::set<uint32_t> labels;
  auto leaf = [&](uint32_t label, uint32_t, float&) { return labels.insert(label), false; };
  float tmax = kInfinity;
  NullTraversalObserver obs;
  w.traverse<false>(Ray{Vec3(-1.0f), normalize(Vec3(1.0f)), kInfinity}, tmax, leaf, obs);
  EXPECT_EQ(labels, (std::set<uint32_t>{5u, 9u}));
}

TEST(WideBvhBuild, RejectsArityOutside2To8) {
  Bvh bvh;
  WideBvh w;
  for (int arity : {-1, 0, 1, 9, 16}) EXPECT_THROW(w.build(bvh, arity), std::invalid_argument);
}

TEST_P(WideBvhArity, EmptyAndSingleLeaf) {
  Bvh bvh;
  bvh.build({}, {});
  WideBvh w;
  w.build(bvh, GetParam());
  float tmax = kInfinity;
  NullTraversalObserver obs;
  int calls = 0;
  auto leaf = [&](uint32_t, uint32_t, float&) { return ++calls, true; };
  EXPECT_FALSE(w.traverse<false>(Ray{}, tmax, leaf, obs));
  EXPECT_EQ(calls, 0);

  Prims p;
  p.add(Bounds3(Vec3(0), Vec3(1)));
  bvh.build(p.bounds, p.centroids);
  w.build(bvh, GetParam());
  EXPECT_TRUE(
      w.traverse<false>(Ray{Vec3(0.5f, 0.5f, -1), Vec3(0, 0, 1), kInfinity}, tmax, leaf, obs));
  EXPECT_EQ(calls, 1);
  EXPECT_FALSE(
      w.traverse<false>(Ray{Vec3(2, 0.5f, -1), Vec3(0, 0, 1), kInfinity}, tmax, leaf, obs));
  EXPECT_EQ(calls, 1);
}

TEST_P(WideBvhArity, DeepBinaryTreeFitsTheStack) {
  // The deepest binary tree the builder makes (rstest::deep_chain_boxes). The
  // wide tree must fit the traversal stack, and a ray along the chain (which
  // pushes at every level) must agree with brute force.
  Rng rng(2);
  const Prims p = rstest::deep_chain_boxes(rng);
  Bvh bvh;
  bvh.build(p.bounds, p.centroids);
  WideBvh w;
  w.build(bvh, GetParam());
  check_collapse(bvh, w);
  std::printf("geometric groups: binary depth %u, wide depth %u\n", bvh.quality().depth, w.depth());
  for (float y : {0.0f, 5e-21f, 1e-20f, 2e-20f}) {
    const Ray ray{Vec3(-1.0f, y, y), Vec3(1.0f, 0.0f, 0.0f), kInfinity};
    BoxLeaves boxes(p, bvh.prim_indices, ray);
    float tmax = kInfinity;
    NullTraversalObserver obs;
    const float best_bf = boxes.brute_force(kInfinity);
    EXPECT_EQ(w.traverse<false>(ray, tmax, boxes.closest(), obs), best_bf != kInfinity)
        << "y=" << y;
    EXPECT_EQ(boxes.best, best_bf) << "y=" << y;
  }
}

TEST(WideBvhBoxTest, EightBoxTestEqualsIntersectBoxBitForBit) {
  // Nodes filled with the boxes of random primitives (and empty slots); every
  // lane of every implementation (the one this file is compiled for, the
  // SSE halves, the scalar loop) must give intersect_box's answer: hit or
  // miss, and the same entry distance for hits.
  constexpr int W = WideBvhNode::kWidth;
  Rng rng(12);
  Prims p = random_boxes(rng, 400, BoxLayout::Uniform);
  Bounds3 world;
  for (const Bounds3& b : p.bounds) world.extend(b);
  int hits = 0, lanes = 0;
  for (int i = 0; i < 20000; ++i) {
    WideBvhNode node{};
    const int used = rng.integer(1, W);
    Bounds3 box[W];
    for (int k = 0; k < W; ++k) {
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
    const wide_bvh_detail::RayBoxes rb(ray.origin, inv);
    alignas(32) float tnear[W];
    const float tmax = rng.coin() ? ray.tmax : rstest::round_f(rng.uniform(0, 300));
    const unsigned mask = wide_bvh_detail::intersect_boxes(node, rb, tmax, tnear);
    // The portable fallback (used where SSE is missing) gives the same lanes.
    alignas(32) float tnear_scalar[W];
    ASSERT_EQ(wide_bvh_detail::intersect_boxes_scalar(node, rb, tmax, tnear_scalar), mask)
        << "ray " << i;
#if defined(__SSE2__)
    // So do the two SSE halves (the fallback where AVX is missing).
    alignas(32) float tnear_sse[W];
    ASSERT_EQ(wide_bvh_detail::intersect_boxes_sse(node, rb, tmax, tnear_sse, 0) |
                  wide_bvh_detail::intersect_boxes_sse(node, rb, tmax, tnear_sse, 4),
              mask)
        << "ray " << i;
#endif
    for (int k = 0; k < W; ++k) {
      const float ref = intersect_box(box[k].lo, box[k].hi, ray.origin, inv, tmax);
      lanes += k < used;
      ASSERT_EQ(bool(mask & (1u << k)), ref != kInfinity) << "ray " << i << " lane " << k;
      if (ref != kInfinity) {
        ++hits;
        ASSERT_EQ(tnear[k], ref) << "ray " << i << " lane " << k;
        ASSERT_EQ(tnear_scalar[k], ref) << "ray " << i << " lane " << k;
#if defined(__SSE2__)
        ASSERT_EQ(tnear_sse[k], ref) << "ray " << i << " lane " << k;
#endif
      }
      if (k >= used) {
        ASSERT_FALSE(mask & (1u << k)) << "empty slot hit, ray " << i;
      }
    }
  }
  std::printf("%d lanes, %d hits\n", lanes, hits);
  EXPECT_GT(hits, lanes / 25);
}

TEST_P(WideBvhArity, ClosestAndAnyHitBoxesMatchBruteForce) {
  // Primitives are the boxes themselves; a primitive's hit distance is its
  // entry distance. Closest hit: the smallest entry distance over all boxes;
  // any hit: whether some box is entered within tmax.
  Rng rng(13);
  int hits = 0, rays = 0;
  for (BoxLayout layout : {BoxLayout::Uniform, BoxLayout::Clustered, BoxLayout::LogUniform}) {
    const Prims p = random_boxes(rng, 3000, layout);
    Bvh bvh;
    bvh.build(p.bounds, p.centroids);
    WideBvh w;
    w.build(bvh, GetParam());
    for (int i = 0; i < 5000; ++i) {
      const Ray ray = random_ray(rng, bvh.bounds(), p.bounds);
      BoxLeaves boxes(p, bvh.prim_indices, ray);
      const float best_bf = boxes.brute_force(ray.tmax);
      float tmax = ray.tmax;
      NullTraversalObserver obs;
      ++rays;
      ASSERT_EQ(w.traverse<false>(ray, tmax, boxes.closest(), obs), best_bf != kInfinity)
          << "ray " << i;
      if (best_bf != kInfinity) {
        ++hits;
        ASSERT_EQ(boxes.best, best_bf) << "ray " << i;
      }
      float tmax2 = ray.tmax;
      ASSERT_EQ(w.traverse<true>(ray, tmax2, boxes.any(), obs), best_bf != kInfinity)
          << "any-hit ray " << i;
    }
  }
  std::printf("boxes: %d rays, %d hits\n", rays, hits);
  EXPECT_GT(hits, rays / 3);
  EXPECT_LT(hits, rays * 9 / 10);
}

struct CountingObserver : TraversalHooks {
  static constexpr bool kActive = true;
  std::vector<int>* node_visits;
  std::vector<uint32_t> boxes_hit, entered, culled_nodes;
  int boxes = 0, prims = 0;
  explicit CountingObserver(std::vector<int>* visits) : node_visits(visits) {}
  void on_node(uint32_t n) {
    (*node_visits).at(n)++;
    entered.push_back(n);
  }
  void on_box_test(uint32_t n, bool hit) {
    ++boxes;
    if (hit) boxes_hit.push_back(n);
  }
  void on_cull(uint32_t n) { culled_nodes.push_back(n); }
  void on_prim_test(uint32_t) { ++prims; }
};

TEST_P(WideBvhArity, ObserverReportsBinaryIdsAndEveryBoxTest) {
  // The walk reports binary node ids: each entered inner node is the top of a
  // wide node, whose every child box is tested once; each leaf's primitives
  // are tested; a box that was hit is later entered or culled (closest-hit
  // walks finish their stack). With arity 2 this is the lecture's binary walk:
  // the root box plus two boxes per entered inner node.
  Rng rng(14);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 4));
  scene.commit();
  const Bvh& bvh = scene.bvh();
  WideBvh w;
  w.build(bvh, GetParam());
  // Binary id of the subtree root of each wide node -> that wide node.
  std::vector<int> wide_of(bvh.nodes.size(), -1);
  wide_of[0] = 0;
  for (size_t n = 0; n < w.nodes.size(); ++n)
    for (int k = 0; k < WideBvhNode::kWidth; ++k) {
      uint32_t src = w.slot_source[WideBvhNode::kWidth * n + k];
      if (src != ~0u && !(w.nodes[n].child[k] & WideBvhNode::kLeaf))
        wide_of[src] = int(w.nodes[n].child[k]);
    }
  const auto& records = scene.accel().records();
  uint64_t culled = 0;
  for (int i = 0; i < 2000; ++i) {
    std::vector<int> nv(bvh.nodes.size(), 0);
    CountingObserver c(&nv);
    const Ray ray{to_f(3.0 * rng.unit_vector()), to_f(rng.unit_vector()), kInfinity};
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
    int expected_boxes = 1, leaves_prims = 0, inner = 0;
    for (size_t n = 0; n < nv.size(); ++n) {
      ASSERT_LE(nv[n], 1) << "node " << n;
      if (!nv[n]) continue;
      if (bvh.nodes[n].is_leaf()) {
        leaves_prims += int(bvh.nodes[n].count);
        continue;
      }
      ++inner;
      ASSERT_GE(wide_of[n], 0) << "binary node " << n << " is not the top of a wide node";
      for (int k = 0; k < WideBvhNode::kWidth; ++k)
        expected_boxes += w.slot_source[WideBvhNode::kWidth * size_t(wide_of[n]) + k] != ~0u;
    }
    EXPECT_EQ(c.boxes, expected_boxes) << "ray " << i;
    if (GetParam() == 2) {
      EXPECT_EQ(c.boxes, 1 + 2 * inner) << "ray " << i;
    }
    EXPECT_EQ(c.prims, leaves_prims) << "ray " << i;
    std::vector<uint32_t> reached = c.entered;
    reached.insert(reached.end(), c.culled_nodes.begin(), c.culled_nodes.end());
    std::sort(reached.begin(), reached.end());
    std::sort(c.boxes_hit.begin(), c.boxes_hit.end());
    EXPECT_EQ(reached, c.boxes_hit) << "ray " << i;
    culled += c.culled_nodes.size();
  }
  EXPECT_GT(culled, 0u);  // early termination happened
}

}  // namespace
