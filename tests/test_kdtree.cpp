// The kD-tree (kdtree.h): its builder's invariants and degenerate input, the
// loose tree's storage rule, bad settings, and its own settings (the median
// rule, loose factors) through the conformance checks; what every structure
// does (queries == brute force and == the BVH, mailboxing, the observer,
// range queries, images) is test_accel_conformance's.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "accel_test_util.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::Prims;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

const KdTreeBuildConfig kSah{};
const KdTreeBuildConfig kMedian = [] {
  KdTreeBuildConfig c;
  c.rule = KdSplitRule::Median;
  return c;
}();

// Every primitive reachable: each primitive is referenced by every leaf whose
// cell its bounds overlap (closed on the side goes_below/goes_above choose),
// and at least once; leaves lie within the depth limit; references are valid.
void check_invariants(const KdTree& kd, const Prims& p) {
  const size_t n = p.bounds.size();
  ASSERT_EQ(kd.empty(), n == 0);
  if (n == 0) return;
  std::vector<int> seen(n, 0);
  struct Item {
    uint32_t node;
    int depth;
    Bounds3 cell;
  };
  std::vector<Item> stack{{0u, 0, kd.bounds()}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    ASSERT_LT(it.node, kd.nodes.size());
    ASSERT_LE(it.depth, kd.max_depth());
    const KdNode& nd = kd.nodes[it.node];
    if (nd.is_leaf()) {
      ASSERT_LE(size_t(nd.first()) + nd.count(), kd.refs.size());
      for (uint32_t k = 0; k < nd.count(); ++k) {
        const uint32_t r = kd.refs[nd.first() + k];
        ASSERT_LT(r, n);
        seen[r]++;
      }
      continue;
    }
    const int a = nd.axis();
    ASSERT_GT(nd.split(), it.cell.lo[a]);
    ASSERT_LT(nd.split(), it.cell.hi[a]);
    Bounds3 below = it.cell, above = it.cell;
    below.hi[a] = above.lo[a] = nd.split();
    stack.push_back({it.node + 1, it.depth + 1, below});
    stack.push_back({nd.above(), it.depth + 1, above});
  }
  for (size_t i = 0; i < n; ++i) ASSERT_GE(seen[i], 1) << "primitive " << i << " in no leaf";
  const KdTreeQuality q = kd.quality();
  EXPECT_EQ(q.nodes, kd.nodes.size());
  EXPECT_EQ(q.leaves, (q.nodes + 1) / 2);
  EXPECT_EQ(q.references, kd.refs.size());
  EXPECT_EQ(q.memory_bytes, kd.nodes.size() * 8 + kd.refs.size() * 4);
  EXPECT_LE(q.references, KdTree::kMaxReferencesPerPrim * n + n);
}

TEST(KdTree, BuildInvariantsOnRandomBoxes) {
  Rng rng(41);
  for (auto layout : {rstest::BoxLayout::Uniform, rstest::BoxLayout::Clustered,
                      rstest::BoxLayout::Coincident, rstest::BoxLayout::LogUniform})
    for (int n : {1, 2, 7, 100, 3000})
      for (const KdTreeBuildConfig& cfg : {kSah, kMedian}) {
        const Prims p = rstest::random_boxes(rng, n, layout);
        KdTree kd;
        kd.build(p.bounds, cfg);
        SCOPED_TRACE(::testing::Message() << "layout " << int(layout) << " n " << n);
        check_invariants(kd, p);
        if (layout == rstest::BoxLayout::Uniform && n == 3000) {
          const KdTreeQuality q = kd.quality();
          std::printf("%s, 3000 uniform boxes: %u nodes, depth %u, %.2f refs/prim, SAH %.1f\n",
                      cfg.rule == KdSplitRule::Sah ? "SAH" : "median", q.nodes, q.depth,
                      q.refs_per_prim, q.sah_cost);
          EXPECT_GT(q.depth, 5u);
        }
      }
}

TEST(KdTree, DegenerateInput) {
  for (const KdTreeBuildConfig& cfg : {kSah, kMedian}) {
    KdTree kd;
    kd.build({}, cfg);  // none
    EXPECT_TRUE(kd.empty());
    float tmax = kInfinity;
    NullTraversalObserver obs;
    EXPECT_FALSE(kd.traverse<false>(
        Ray{Vec3(0), Vec3(1, 0, 0), kInfinity}, tmax, [](uint32_t, float&) { return true; }, obs));
    Prims one;  // one
    one.add(Bounds3(Vec3(-1), Vec3(1)));
    kd.build(one.bounds, cfg);
    check_invariants(kd, one);
    EXPECT_EQ(kd.nodes.size(), 1u);
    Prims point;  // everything at one point, zero-size boxes
    for (int i = 0; i < 500; ++i) point.add(Bounds3(Vec3(1, 2, 3)));
    kd.build(point.bounds, cfg);
    check_invariants(kd, point);
    EXPECT_EQ(kd.nodes.size(), 1u);
    Prims flat;  // zero-size boxes on a line, and a stack of flat boxes in one plane
    for (int i = 0; i < 300; ++i) flat.add(Bounds3(Vec3(float(i), 0, 0)));
    for (int i = 0; i < 300; ++i) flat.add(Bounds3(Vec3(0, 0, 5), Vec3(1, float(i % 7), 5)));
    kd.build(flat.bounds, cfg);
    check_invariants(kd, flat);
  }
}

// The kD-tree's own settings: the median rule, and smallest-cell storage
// at loose factors 0 (a plain kD-tree whose straddlers stay up), the default
// and the largest, each with both rules, through the checks of the
// conformance suite (which runs the defaults: the SAH, every-cell and
// smallest-cell at the default loose factor), with rays lying in the tree's
// exact split planes (the view shows a loose tree's enlarged boxes only).
struct KdSetting {
  std::string name;
  KdSplitRule rule;
  PrimStorage storage;
  float loose_factor;
};
class KdTreeSetting : public ::testing::TestWithParam<KdSetting> {};
INSTANTIATE_TEST_SUITE_P(
    Own, KdTreeSetting,
    ::testing::Values(
        KdSetting{"median_every_cell", KdSplitRule::Median, PrimStorage::EveryCell, 0.0f},
        KdSetting{"sah_loose_0", KdSplitRule::Sah, PrimStorage::SmallestCell, 0.0f},
        KdSetting{"sah_loose_default", KdSplitRule::Sah, PrimStorage::SmallestCell,
                  kDefaultLooseFactor},
        KdSetting{"median_loose_default", KdSplitRule::Median, PrimStorage::SmallestCell,
                  kDefaultLooseFactor},
        KdSetting{"sah_loose_max", KdSplitRule::Sah, PrimStorage::SmallestCell, kMaxLooseFactor},
        KdSetting{"alternating_median_every_cell", KdSplitRule::AlternatingMedian,
                  PrimStorage::EveryCell, 0.0f},
        KdSetting{"alternating_median_loose_default", KdSplitRule::AlternatingMedian,
                  PrimStorage::SmallestCell, kDefaultLooseFactor}),
    [](const auto& info) { return info.param.name; });

TEST_P(KdTreeSetting, QueriesMatchBruteForceAndTheBvh) {
  Rng rng(47);
  AccelConfig ac;
  ac.kind = AccelKind::KdTree;
  ac.kdtree.rule = GetParam().rule;
  ac.storage = GetParam().storage;
  ac.loose_factor = GetParam().loose_factor;
  rstest::check_setting(
      ac, "kD-tree " + GetParam().name, rng, [&](const Scene& scene, std::vector<Ray>& rays) {
        const KdTree& kd = scene.accel().structure_as<KdTree>();
        ASSERT_EQ(kd.loose(), GetParam().storage == PrimStorage::SmallestCell);
        for (size_t i = 0; i < kd.nodes.size(); i += 7)
          if (!kd.nodes[i].is_leaf())
            rstest::add_plane_rays(rng, kd.bounds(), kd.nodes[i].axis(), kd.nodes[i].split(), rays);
      });
}

TEST(KdTree, MedianRulePrunesLessOnSlivers) {
  // The spatial median cuts the slivers' space blindly, duplicating them until
  // KdTree::kMaxReferencesPerPrim stops it: it prunes far less than the SAH
  // (about half of them tested per ray, against a few percent), and each
  // primitive is still tested once per ray.
  Rng rng(45);
  Scene scene = rstest::sliver_scene(rng);
  AccelConfig ac;
  ac.kind = AccelKind::KdTree;
  ac.kdtree.rule = KdSplitRule::Median;
  scene.commit(ac);
  const KdTree& kd = scene.accel().structure_as<KdTree>();
  EXPECT_GT(kd.quality().refs_per_prim, 1.5) << "the test needs primitives stored several times";
  const size_t prims = scene.accel().records().size();
  const int n_rays = 3000;
  rstest::MailboxTotals t;
  rstest::mailbox_rays(
      scene, rng, n_rays, kd.nodes.size(), t, [&](const rstest::CountingObserver& obs, bool any) {
        if (any) return;
        int inner = 0;
        for (uint32_t n : obs.order) inner += !kd.nodes[n].is_leaf();
        EXPECT_EQ(obs.boxes, 1 + 2 * inner) << "root box + two child cells per inner node";
      });
  if (HasFatalFailure()) return;
  const uint64_t all = uint64_t(n_rays) * prims;
  EXPECT_LT(t.tests, all * 2 / 3);
  EXPECT_GT(t.multi_node_rays, uint64_t(n_rays) / 2);
  EXPECT_GT(t.culls, 0u);
}

TEST(KdTree, AlternatingMedianTakesTheAxesInTurnAtTheCentersMedian) {
  // The lecture's rule: x at the root, y below it, z below those, each plane
  // at the (upper) median of the cell's primitives' centers, so that the
  // root's sides get half the primitives each; the tree passes the builder's
  // invariants.
  Rng rng(48);
  const Prims p = rstest::random_boxes(rng, 2001, rstest::BoxLayout::Uniform);
  KdTreeBuildConfig cfg;
  cfg.rule = KdSplitRule::AlternatingMedian;
  KdTree kd;
  kd.build(p.bounds, cfg);
  check_invariants(kd, p);
  if (HasFatalFailure()) return;
  auto median_center = [&](const std::vector<uint32_t>& prims, int axis) {
    std::vector<float> c;
    for (uint32_t q : prims) c.push_back(p.bounds[q].center()[axis]);
    std::sort(c.begin(), c.end());
    return c[c.size() / 2];
  };
  std::vector<uint32_t> all(p.bounds.size());
  for (uint32_t q = 0; q < all.size(); ++q) all[q] = q;
  const KdNode& root = kd.nodes[0];
  ASSERT_FALSE(root.is_leaf());
  EXPECT_EQ(root.axis(), 0);
  EXPECT_EQ(root.split(), median_center(all, 0));
  size_t below = 0, above = 0;
  for (const Bounds3& b : p.bounds) (b.center().x < root.split() ? below : above)++;
  EXPECT_EQ(below, p.bounds.size() / 2);
  // Depths 1 and 2: y, then z.
  for (const uint32_t child : {1u, root.above()}) {
    const KdNode& c = kd.nodes[child];
    ASSERT_FALSE(c.is_leaf());
    EXPECT_EQ(c.axis(), 1);
    for (const uint32_t grandchild : {child + 1, c.above()}) {
      ASSERT_FALSE(kd.nodes[grandchild].is_leaf());
      EXPECT_EQ(kd.nodes[grandchild].axis(), 2);
    }
  }
  // Its name, as the command line and the scene settings spell it.
  KdSplitRule r;
  ASSERT_TRUE(parse_kd_split_rule("alternating-median", r));
  EXPECT_EQ(r, KdSplitRule::AlternatingMedian);
  EXPECT_STREQ(to_string(r), "alternating-median");
}

class KdTreeRule : public ::testing::TestWithParam<KdSplitRule> {};
INSTANTIATE_TEST_SUITE_P(Rule, KdTreeRule, ::testing::Values(KdSplitRule::Sah, KdSplitRule::Median),
                         [](const auto& info) {
                           return std::string(info.param == KdSplitRule::Sah ? "sah" : "median");
                         });

// SmallestCell's invariants: each primitive stored exactly once; where it is
// stored its bounds fit the node's loose box; one held by an inner node fits
// neither child's loose box (a straddler), one in a leaf sits there because
// the leaf was not split further. Loose factors 0 (a plain kD-tree where
// straddlers stay up), the lecture's 0.1 and the largest, 0.5.
TEST_P(KdTreeRule, SmallestCellStoresEachPrimitiveOnceInItsLooseCell) {
  Rng rng(46);
  for (auto layout : {rstest::BoxLayout::Uniform, rstest::BoxLayout::Clustered}) {
    const Prims p = rstest::random_boxes(rng, 3000, layout);
    size_t inner[3];
    int k = 0;
    for (float f : {0.0f, kDefaultLooseFactor, kMaxLooseFactor}) {
      SCOPED_TRACE(::testing::Message() << "loose factor " << f);
      KdTree kd;
      kd.build(p.bounds, GetParam() == KdSplitRule::Sah ? kSah : kMedian, PrimStorage::SmallestCell,
               f);
      ASSERT_TRUE(kd.loose());
      ASSERT_EQ(kd.offsets.size(), kd.nodes.size() + 1);
      const std::vector<Bounds3> cells = kd.cells();
      std::vector<int> seen(p.bounds.size(), 0);
      for (uint32_t n = 0; n < kd.nodes.size(); ++n) {
        const KdNode& node = kd.nodes[n];
        Bounds3 below = cells[n], above = cells[n];
        if (!node.is_leaf()) below.hi[node.axis()] = above.lo[node.axis()] = node.split();
        for (uint32_t q : kd.node_refs(n)) {
          seen.at(q)++;
          ASSERT_TRUE(kd.node_box(cells[n]).contains(p.bounds[q])) << "node " << n;
          if (!node.is_leaf()) {
            ASSERT_FALSE(kd.node_box(below).contains(p.bounds[q])) << "inner node " << n;
            ASSERT_FALSE(kd.node_box(above).contains(p.bounds[q])) << "inner node " << n;
          }
        }
      }
      for (int v : seen) ASSERT_EQ(v, 1);
      const KdTreeQuality q = kd.quality();
      EXPECT_EQ(q.references, p.bounds.size());
      EXPECT_EQ(q.refs_per_prim, 1.0);
      inner[k++] = q.inner_refs;
    }
    // With the median rule's fixed planes, the larger the factor, the fewer
    // straddlers stay in inner nodes (the SAH moves its planes with the
    // factor: no such order).
    if (GetParam() == KdSplitRule::Median) {
      EXPECT_GT(inner[0], inner[2]);
    }
    EXPECT_GT(inner[0], 0u);
  }
}

TEST(KdTree, SplitStorageIsRefused) {
  // By the factory's one check (a bad loose factor: test_accel_conformance,
  // through the same check); the builder takes every-cell and smallest-cell.
  EXPECT_TRUE(rstest::storage_refused(AccelKind::KdTree, PrimStorage::Split));
}

TEST(KdTree, MemoryOfTheAggregate) {
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 3));
  AccelConfig ac;
  ac.kind = AccelKind::KdTree;
  scene.commit(ac);
  const Aggregate& a = scene.accel();
  EXPECT_TRUE(a.structure_as<BvhWalk>().walk().empty());
  // The binary BVH is built when first asked for; from then on the
  // aggregate holds it and counts it.
  const size_t binary = a.bvh().quality().memory_bytes;
  EXPECT_EQ(a.memory_bytes(), binary + a.structure_as<KdTree>().memory_bytes() +
                                  a.records().size() * (sizeof(PrimRecord) + sizeof(uint32_t)));
  EXPECT_GT(a.structure_as<KdTree>().memory_bytes(), 0u);
}

}  // namespace
