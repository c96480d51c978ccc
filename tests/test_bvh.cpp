// The binned SAH builder (bvh.h): structural invariants of the built
// hierarchy and its quality() figures, for random, clustered, coincident and
// log-uniform boxes and adversarial inputs. How rays walk the tree is tested in
// test_wide_bvh (the one walk) and test_aggregate (scene queries).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstdio>
#include <cstring>
#include <functional>

#include "accel_test_util.h"
#include "rayscope/accel/bvh.h"

namespace {

using namespace rayscope;
using rstest::BoxLayout;
using rstest::Prims;
using rstest::Rng;

// Traversal keeps a fixed stack (wide_bvh.h) sized for the builder's depth
// cap: a hierarchy deeper than 65 levels (root = level 1) could overflow it.
constexpr uint32_t kMaxSafeDepth = 65;

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
  const std::pair<BoxLayout, const char*> layouts[] = {{BoxLayout::Uniform, "uniform"},
                                                       {BoxLayout::Clustered, "clustered"},
                                                       {BoxLayout::Coincident, "coincident"},
                                                       {BoxLayout::LogUniform, "log-uniform"}};
  for (const auto& [layout, name] : layouts)
    for (int n : {1, 2, 3, 9, 100, 5000}) {
      Prims p = random_boxes(rng, layout == BoxLayout::Coincident ? std::min(n, 300) : n, layout);
      for (const BvhBuildConfig& cfg : configs) {
        SCOPED_TRACE(std::string(name) + ", n=" + std::to_string(p.bounds.size()) + ", bins=" +
                     std::to_string(cfg.bins) + ", max_leaf=" + std::to_string(cfg.max_leaf_size));
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

  Prims p;
  p.add(Bounds3(Vec3(0), Vec3(1)));
  bvh.build(p.bounds, p.centroids);
  ASSERT_EQ(bvh.nodes.size(), 1u);
  EXPECT_TRUE(bvh.nodes[0].is_leaf());
  EXPECT_EQ(bvh.quality().depth, 1u);
}

TEST(BvhBuild, AdversarialDepthFitsTheTraversalStack) {
  // rstest::deep_chain_boxes: the SAH can only peel off one group per split,
  // so the tree becomes a chain as deep as the builder allows, with large
  // median-split subtrees below it. The depth must fit the traversal stack
  // (test_wide_bvh walks it). (Before the builder capped the depth, this
  // overflowed the walk's stack: AddressSanitizer reported
  // stack-buffer-overflow.)
  Rng rng(2);
  const Prims p = rstest::deep_chain_boxes(rng);
  Bvh bvh;
  bvh.build(p.bounds, p.centroids);
  check_structure(bvh, p, BvhBuildConfig{});
  std::printf("geometric groups, n=%zu: depth %u\n", p.bounds.size(), bvh.quality().depth);
}

// Uniform and clustered random boxes and rstest::deep_chain_boxes, named.
std::vector<std::pair<const char*, Prims>> tree_inputs(Rng& rng, int uniform, int clustered) {
  std::vector<std::pair<const char*, Prims>> inputs;
  inputs.emplace_back("uniform", random_boxes(rng, uniform, BoxLayout::Uniform));
  inputs.emplace_back("clustered", random_boxes(rng, clustered, BoxLayout::Clustered));
  inputs.emplace_back("geometric groups", rstest::deep_chain_boxes(rng));
  return inputs;
}

// The same nodes, bit for bit, and the same primitive order.
void expect_same_tree(const Bvh& bvh, const Bvh& ref) {
  ASSERT_EQ(bvh.nodes.size(), ref.nodes.size());
  EXPECT_EQ(std::memcmp(bvh.nodes.data(), ref.nodes.data(), ref.nodes.size() * sizeof(BvhNode)), 0);
  EXPECT_EQ(bvh.prim_indices, ref.prim_indices);
}

// The parallel build keeps each task's subtree apart and then places them in
// the order the serial recursion makes: the same nodes (bit for bit) and
// primitive order for every task threshold and thread count.
TEST(BvhBuild, ParallelBuildIsTheSerialTreeNodeForNode) {
  Rng rng(3);
  for (const auto& [name, p] : tree_inputs(rng, 60000, 30000)) {
    BvhBuildConfig serial;
    serial.parallel_min_prims = ~0u;
    Bvh ref;
    ref.build(p.bounds, p.centroids, serial);
    check_structure(ref, p, serial);
    for (uint32_t min_prims : {4096u, 64u, 1u})
      for (int threads : {1, 2, 4}) {
        SCOPED_TRACE(std::string(name) + ", tasks from " + std::to_string(min_prims) +
                     " primitives, " + std::to_string(threads) + " threads");
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        BvhBuildConfig cfg;
        cfg.parallel_min_prims = min_prims;
        Bvh bvh;
        bvh.build(p.bounds, p.centroids, cfg);
        expect_same_tree(bvh, ref);
      }
  }
}

// The builder bins with AVX, SSE2 or plain loops (BvhBuildConfig::simd; a CPU
// without AVX gets SSE, one without SIMD the loops): the same tree, bit for
// bit, also with more than 64 bins (the bins' marks then live in memory) and
// with parallel tasks. The inputs include boxes whose centroids span beyond
// the float range and flat and coinciding ones.
TEST(BvhBuild, EverySimdChoiceBuildsTheSameTree) {
  Rng rng(5);
  std::vector<std::pair<const char*, Prims>> inputs = tree_inputs(rng, 20000, 20000);
  Prims odd;
  for (int i = 0; i < 300; ++i) {
    const float x = i % 3 == 0 ? 3e38f : i % 3 == 1 ? -3e38f : 0.0f;
    const Vec3 c(x, float(i % 7), i % 5 == 0 ? 0.0f : float(i));
    odd.bounds.emplace_back(c - Vec3(0.5f, 0.0f, 0.5f), c + Vec3(0.5f, 0.0f, 0.5f));
    odd.centroids.push_back(c);
  }
  inputs.emplace_back("beyond the float range, flat, coinciding", odd);
  using Simd = BvhBuildConfig::Simd;
  for (const auto& [name, p] : inputs)
    for (int bins : {16, 100})
      for (uint32_t min_prims : {~0u, 256u}) {
        SCOPED_TRACE(std::string(name) + ", " + std::to_string(bins) + " bins, tasks from " +
                     std::to_string(min_prims) + " primitives");
        BvhBuildConfig cfg;
        cfg.bins = bins;
        cfg.parallel_min_prims = min_prims;
        cfg.simd = Simd::Best;
        Bvh best;
        best.build(p.bounds, p.centroids, cfg);
        if (&p != &inputs.back().second) check_structure(best, p, cfg);  // infinite areas
        for (Simd simd : {Simd::Sse, Simd::Scalar}) {
          cfg.simd = simd;
          Bvh bvh;
          bvh.build(p.bounds, p.centroids, cfg);
          expect_same_tree(bvh, best);
        }
      }
}

}  // namespace
