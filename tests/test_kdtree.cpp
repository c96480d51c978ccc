// The kD-tree (kdtree.h) behind the aggregate: its builder's invariants and
// degenerate input, and scene queries through it against brute force (closest
// hit bit for bit, ties resolved alike, any hit), with the SAH and the median
// rule, on random and adversarial rays; mailboxing tests every primitive at
// most once per ray; full renders are bit-identical to the BVH's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>

#include "accel_test_util.h"
#include "rayscope/render.h"
#include "rayscope/scene_io.h"
#include "rayscope_vtk/mesh_files.h"

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

// SmallestCell storage with `rule` and loose factor f.
KdTreeBuildConfig loose(KdSplitRule rule, float f) {
  KdTreeBuildConfig c;
  c.rule = rule;
  c.storage = PrimStorage::SmallestCell;
  c.loose_factor = f;
  return c;
}

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

// A scene committed with the kD-tree built by `cfg`.
void commit_kd(Scene& scene, const KdTreeBuildConfig& cfg) {
  AccelConfig ac;
  ac.kind = AccelKind::KdTree;
  ac.kdtree = cfg;
  ac.storage = cfg.storage;
  ac.loose_factor = cfg.loose_factor;
  scene.commit(ac);
  ASSERT_EQ(scene.accel().structure_as<KdTree>().loose(), cfg.storage == PrimStorage::SmallestCell);
  ASSERT_EQ(scene.accel().kind(), AccelKind::KdTree);
  ASSERT_TRUE(scene.accel().walks_structure());
  ASSERT_FALSE(scene.accel().structure_as<KdTree>().empty());
}

class KdTreeRule : public ::testing::TestWithParam<KdSplitRule> {
 protected:
  KdTreeBuildConfig config() const { return GetParam() == KdSplitRule::Sah ? kSah : kMedian; }
};
INSTANTIATE_TEST_SUITE_P(Rule, KdTreeRule, ::testing::Values(KdSplitRule::Sah, KdSplitRule::Median),
                         [](const auto& info) {
                           return std::string(info.param == KdSplitRule::Sah ? "sah" : "median");
                         });

TEST_P(KdTreeRule, RandomRaysMatchBruteForce) {
  Rng rng(42);
  Scene scene = rstest::soup_scene(rng);
  commit_kd(scene, config());
  std::vector<Ray> rays;
  rstest::add_random_rays(rng, scene, scene.accel().structure_as<KdTree>().bounds(), 20000, rays);
  rstest::check_queries(scene, rays, "kD-tree: meshes + soup + spheres + plane", 0);
}

// Rays that stress the walk: through vertices and edge midpoints (exact ties
// between triangles), lying along mesh edges (inside shared edges), lying in
// the tree's split planes and starting on them, axis-parallel through cells,
// starting inside cells, and grazing spheres.
std::vector<Ray> adversarial_rays(Rng& rng, const Scene& scene) {
  std::vector<Ray> rays;
  rstest::add_mesh_rays(rng, scene, rays);
  const KdTree& kd = scene.accel().structure_as<KdTree>();
  const Bounds3 world = kd.bounds();
  for (size_t i = 0; i < kd.nodes.size() && rays.size() < 40000; i += 7) {
    const KdNode& n = kd.nodes[i];
    if (n.is_leaf()) continue;
    for (int k = 0; k < 3; ++k) rstest::add_plane_rays(rng, world, n.axis(), n.split(), rays);
  }
  rstest::add_inside_and_grazing_rays(rng, scene, world, 3000, rays);
  return rays;
}

TEST_P(KdTreeRule, AdversarialRaysMatchBruteForce) {
  Rng rng(43);
  Scene scene = rstest::soup_scene(rng);
  scene.meshes.push_back(rstest::unit_cube(Vec3(7, 0, 0)));
  commit_kd(scene, config());
  const std::vector<Ray> rays = adversarial_rays(rng, scene);
  rstest::check_queries(scene, rays, "kD-tree: adversarial rays", 20);
}

TEST(KdTree, SameHitsAsTheBvhBitForBit) {
  Rng rng(44);
  Scene scene = rstest::soup_scene(rng);
  scene.commit();
  std::vector<Ray> rays = adversarial_rays(rng, scene);
  rstest::add_random_rays(rng, scene, scene.bvh().bounds(), 5000, rays);
  std::vector<PrimHit> bvh(rays.size());
  std::vector<uint8_t> bvh_occluded(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    scene.intersect(rays[i], bvh[i]);
    bvh_occluded[i] = scene.occluded(rays[i]);
  }
  for (const KdTreeBuildConfig& cfg :
       {kSah, kMedian, loose(KdSplitRule::Sah, 0.0f), loose(KdSplitRule::Sah, kDefaultLooseFactor),
        loose(KdSplitRule::Median, kDefaultLooseFactor),
        loose(KdSplitRule::Sah, kMaxLooseFactor)}) {
    commit_kd(scene, cfg);
    for (size_t i = 0; i < rays.size(); ++i) {
      PrimHit h;
      scene.intersect(rays[i], h);
      ASSERT_TRUE(rstest::same_bits(h, bvh[i]))
          << to_string(cfg.storage) << " " << cfg.loose_factor << ", ray " << i;
      ASSERT_EQ(scene.occluded(rays[i]), bool(bvh_occluded[i])) << "ray " << i;
    }
  }
}

TEST_P(KdTreeRule, MailboxTestsEachPrimitiveOncePerRay) {
  // Long thin triangles that straddle many cells, so that most are stored
  // several times; every ray still tests each at most once (closest and any
  // hit), and the structure prunes far below brute force.
  Rng rng(45);
  Scene scene = rstest::sliver_scene(rng);
  commit_kd(scene, config());
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
  // The spatial median cuts the slivers' space blindly, duplicating them until
  // KdTree::kMaxReferencesPerPrim stops it: it prunes far less (about half of
  // them tested per ray, against a few percent with the SAH).
  const uint64_t all = uint64_t(n_rays) * prims;
  EXPECT_LT(t.tests, GetParam() == KdSplitRule::Sah ? all / 10 : all * 2 / 3);
  EXPECT_GT(t.multi_node_rays, uint64_t(n_rays) / 2);
  EXPECT_GT(t.culls, 0u);
}

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
      kd.build(p.bounds, loose(GetParam(), f));
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

TEST(KdTree, BadStorageSettingsAreRefusedWithOneLine) {
  Prims p;
  p.add(Bounds3(Vec3(-1), Vec3(1)));
  for (float bad : {-0.1f, 0.51f, kInfinity, std::nanf("")}) {
    KdTree kd;
    try {
      kd.build(p.bounds, loose(KdSplitRule::Sah, bad));
      FAIL() << "no exception for " << bad;
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("loose factor must be a number from 0 to 0.5"), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos);
    }
  }
  KdTreeBuildConfig split;
  split.storage = PrimStorage::Split;
  KdTree kd;
  EXPECT_THROW(kd.build(p.bounds, split), std::invalid_argument);
}

// Random and adversarial rays (the loose boxes' faces too) through the loose
// kD-tree == brute force, for loose factors 0, 0.1, 0.5.
TEST_P(KdTreeRule, SmallestCellRaysMatchBruteForce) {
  Rng rng(47);
  Scene scene = rstest::soup_scene(rng);
  scene.meshes.push_back(rstest::unit_cube(Vec3(7, 0, 0)));
  for (float f : {0.0f, kDefaultLooseFactor, kMaxLooseFactor}) {
    commit_kd(scene, loose(GetParam(), f));
    const KdTree& kd = scene.accel().structure_as<KdTree>();
    std::vector<Ray> rays = adversarial_rays(rng, scene);
    const std::vector<Bounds3> cells = kd.cells();
    for (size_t i = 0; i < cells.size(); i += 5) {
      const Bounds3 box = kd.node_box(cells[i]);
      const int a = rng.integer(0, 2);
      rstest::add_plane_rays(rng, kd.bounds(), a, box.lo[a], rays, false);
      rstest::add_plane_rays(rng, kd.bounds(), a, box.hi[a], rays, false);
    }
    rstest::add_random_rays(rng, scene, kd.bounds(), 4000, rays);
    rstest::check_queries(scene, rays, "loose kD-tree", 20);
  }
}

TEST_P(KdTreeRule, SmallestCellTestsEachPrimitiveOncePerRay) {
  Rng rng(48);
  Scene scene = rstest::sliver_scene(rng);
  commit_kd(scene, loose(GetParam(), kDefaultLooseFactor));
  const KdTree& kd = scene.accel().structure_as<KdTree>();
  EXPECT_GT(kd.quality().inner_refs, 100u) << "the test needs straddlers in inner nodes";
  const size_t prims = scene.accel().records().size();
  const int n_rays = 3000;
  rstest::MailboxTotals t;
  rstest::mailbox_rays(
      scene, rng, n_rays, kd.nodes.size(), t, [&](const rstest::CountingObserver& obs, bool any) {
        if (any) return;
        int inner = 0;
        for (uint32_t n : obs.order) inner += !kd.nodes[n].is_leaf();
        EXPECT_EQ(obs.boxes, 1 + 2 * inner) << "root box + two child boxes per inner node";
      });
  if (HasFatalFailure()) return;
  std::printf("loose kD-tree (%s): %.1f of %zu primitives tested per ray\n",
              GetParam() == KdSplitRule::Sah ? "sah" : "median", double(t.tests) / n_rays, prims);
  EXPECT_LT(t.tests, uint64_t(n_rays) * prims / 2);
  EXPECT_GT(t.culls, 0u);
}

TEST_P(KdTreeRule, RangeWalkFindsWhatBruteForceFinds) {
  Rng rng(49);
  for (const KdTreeBuildConfig& cfg :
       {config(), loose(GetParam(), kDefaultLooseFactor), loose(GetParam(), kMaxLooseFactor)})
    for (auto layout : {rstest::BoxLayout::Uniform, rstest::BoxLayout::Clustered}) {
      const Prims p = rstest::random_boxes(rng, 3000, layout);
      KdTree kd;
      kd.build(p.bounds, cfg);
      rstest::RangeTotals t;
      rstest::check_range_walk(kd, p, rng, kd.bounds(), kd.nodes.size(), t);
      if (HasFatalFailure()) return;
      EXPECT_LT(t.entered, 300 * kd.nodes.size() / 4);
      EXPECT_GT(t.found, 300u);
    }
}

TEST(KdTree, KindNameAndMemory) {
  AccelKind k = AccelKind::Bvh;
  ASSERT_TRUE(parse_accel_kind("kdtree", k));
  EXPECT_EQ(k, AccelKind::KdTree);
  EXPECT_STREQ(to_string(AccelKind::KdTree), "kdtree");
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 3));
  commit_kd(scene, kSah);
  const Aggregate& a = scene.accel();
  EXPECT_TRUE(a.structure_as<BvhWalk>().walk().empty());
  EXPECT_EQ(a.memory_bytes(), a.bvh().quality().memory_bytes +
                                  a.structure_as<KdTree>().memory_bytes() +
                                  a.records().size() * sizeof(PrimRecord));
  EXPECT_GT(a.structure_as<KdTree>().memory_bytes(), 0u);
}

// Renders of the default scene and the bunny scene: the kD-tree's image is
// the BVH's, bit for bit (color, depth, normals, object ids).
void expect_same_render(Scene scene, const RenderSettings& rs) {
  scene.commit();
  const Framebuffer bvh = render(scene, rs);
  for (const KdTreeBuildConfig& cfg : {kSah, kMedian}) {
    commit_kd(scene, cfg);
    const Framebuffer kd = render(scene, rs);
    auto same = [](const auto& a, const auto& b) {
      return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
    };
    EXPECT_TRUE(same(kd.color, bvh.color));
    EXPECT_TRUE(same(kd.depth, bvh.depth));
    EXPECT_TRUE(same(kd.normal, bvh.normal));
    EXPECT_TRUE(same(kd.object_id, bvh.object_id));
  }
}

TEST(KdTree, DefaultSceneRendersLikeTheBvh) {
  expect_same_render(make_default_scene(), rstest::small_render(160, 120, 2));
}

TEST(KdTree, BunnySceneRendersLikeTheBvh) {
  const std::filesystem::path file =
      std::filesystem::path(RAYSCOPE_SOURCE_DIR) / "data/scenes/bunny.json";
  LoadedScene ls = load_scene(file.string(), rayscope_vtk::load_mesh);
  expect_same_render(std::move(ls.scene), rstest::small_render(160, 120, 2));
}

}  // namespace
