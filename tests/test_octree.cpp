// The octree (octree.h), for both storage choices (every-cell: a reference in
// each leaf a primitive overlaps, mailboxed; smallest-cell: the loose octree,
// each primitive once): builder invariants, loose factors 0 and large,
// degenerate input, its loose factors through the conformance checks, storage
// names, memory and the storage trends on a mesh of the bunny's size. What
// every structure does (queries == brute force and == the BVH, mailboxing,
// the observer, range queries, images) is test_accel_conformance's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <stdexcept>
#include <string>

#include "accel_test_util.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::Prims;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

bool overlaps(const Bounds3& a, const Bounds3& b) {
  for (int k = 0; k < 3; ++k)
    if (a.lo[k] > b.hi[k] || a.hi[k] < b.lo[k]) return false;
  return true;
}

bool halvable(const Bounds3& cell) {
  const Vec3 mid = 0.5f * cell.lo + 0.5f * cell.hi;
  for (int a = 0; a < 3; ++a)
    if (!(mid[a] > cell.lo[a] && mid[a] < cell.hi[a])) return false;
  return true;
}

// The storage rules, checked against the cells the tree reports:
// - structure: children after their parent, within the array, depth within
//   the limit, each child's cell an octant of its parent's;
// - every-cell: inner nodes hold nothing; each leaf holds exactly the
//   primitives whose (closed) bounds overlap its cell; each primitive in at
//   least one leaf;
// - smallest-cell: each primitive stored exactly once, in a node whose loose
//   box holds it; in an inner node only if no octant's loose box holds it; a
//   leaf over the size limit is at the depth limit, cannot be halved, or holds
//   nothing that fits an octant.
void check_invariants(const Octree& oc, const Prims& p) {
  const size_t n = p.bounds.size();
  ASSERT_EQ(oc.empty(), n == 0);
  if (n == 0) return;
  const std::vector<Bounds3> cells = oc.cells();
  const std::vector<uint32_t> depth = oc.depths();
  ASSERT_EQ(cells.size(), oc.nodes.size());
  for (const Bounds3& b : p.bounds) ASSERT_TRUE(oc.bounds().contains(b));
  const Vec3 e = oc.bounds().extent();
  const Vec3 far = glm::max(glm::abs(oc.bounds().lo), glm::abs(oc.bounds().hi));
  EXPECT_LE(std::max({e.x, e.y, e.z}) - std::min({e.x, e.y, e.z}),
            1e-5f * std::max({e.x, e.y, e.z}) + 1e-6f * std::max({far.x, far.y, far.z}))
      << "the root cell is a cube, up to the rounding of its corners";
  std::vector<int> seen(n, 0);
  size_t inner_refs = 0;
  for (size_t i = 0; i < oc.nodes.size(); ++i) {
    const OctNode& nd = oc.nodes[i];
    ASSERT_LE(depth[i], uint32_t(oc.max_depth()));
    ASSERT_LE(size_t(nd.first) + nd.count, oc.refs.size());
    for (int o = 0; o < 8; ++o) {
      if (!nd.has_child(o)) continue;
      const uint32_t c = nd.child(o);
      ASSERT_GT(c, i);
      ASSERT_LT(c, oc.nodes.size());
      const Bounds3 want = Octree::octant_cell(cells[i], o);
      ASSERT_EQ(cells[c].lo, want.lo);
      ASSERT_EQ(cells[c].hi, want.hi);
    }
    if (!nd.is_leaf()) inner_refs += nd.count;
    std::set<uint32_t> held;
    for (uint32_t k = 0; k < nd.count; ++k) {
      const uint32_t r = oc.refs[nd.first + k];
      ASSERT_LT(r, n);
      seen[r]++;
      held.insert(r);
    }
    ASSERT_EQ(held.size(), nd.count) << "a primitive twice in node " << i;
    if (!oc.loose()) {
      if (!nd.is_leaf()) {
        ASSERT_EQ(nd.count, 0u) << "every-cell inner node " << i << " holds primitives";
        continue;
      }
      for (size_t q = 0; q < n; ++q)
        ASSERT_EQ(held.count(uint32_t(q)) == 1, overlaps(p.bounds[q], cells[i]))
            << "leaf " << i << ", primitive " << q;
      continue;
    }
    auto fits_an_octant = [&](uint32_t r) {
      for (int o = 0; o < 8; ++o)
        if (oc.node_box(Octree::octant_cell(cells[i], o)).contains(p.bounds[r])) return true;
      return false;
    };
    for (uint32_t r : held) {
      ASSERT_TRUE(oc.node_box(cells[i]).contains(p.bounds[r])) << "node " << i << ", prim " << r;
      if (!nd.is_leaf()) {
        ASSERT_FALSE(fits_an_octant(r)) << "node " << i << ", prim " << r;
      }
    }
    if (nd.is_leaf() && nd.count > oc.config.max_leaf_size && depth[i] < uint32_t(oc.max_depth()) &&
        halvable(cells[i])) {
      for (uint32_t r : held) ASSERT_FALSE(fits_an_octant(r)) << "leaf " << i << ", prim " << r;
    }
  }
  for (size_t q = 0; q < n; ++q) {
    if (oc.loose())
      ASSERT_EQ(seen[q], 1) << "primitive " << q;
    else
      ASSERT_GE(seen[q], 1) << "primitive " << q << " in no leaf";
  }
  const OctreeQuality q = oc.quality();
  EXPECT_EQ(q.nodes, oc.nodes.size());
  EXPECT_EQ(q.references, oc.refs.size());
  EXPECT_EQ(q.inner_refs, inner_refs);
  EXPECT_EQ(q.memory_bytes, oc.nodes.size() * 16 + oc.refs.size() * 4);
  EXPECT_EQ(q.memory_bytes, oc.memory_bytes());
  EXPECT_EQ(q.depth, *std::max_element(depth.begin(), depth.end()));
  if (oc.loose()) {
    EXPECT_EQ(q.references, n);
    EXPECT_DOUBLE_EQ(q.refs_per_prim, 1.0);
  } else {
    EXPECT_EQ(q.inner_refs, 0u);
    EXPECT_LE(q.references, Octree::kMaxReferencesPerPrim * n + 8 * n);
  }
}

class OctreeStorage : public ::testing::TestWithParam<PrimStorage> {};
INSTANTIATE_TEST_SUITE_P(Storage, OctreeStorage,
                         ::testing::Values(PrimStorage::EveryCell, PrimStorage::SmallestCell),
                         [](const auto& info) {
                           return std::string(info.param == PrimStorage::EveryCell
                                                  ? "every_cell"
                                                  : "smallest_cell");
                         });

TEST_P(OctreeStorage, BuildInvariantsOnRandomBoxes) {
  Rng rng(51);
  for (auto layout : {rstest::BoxLayout::Uniform, rstest::BoxLayout::Clustered,
                      rstest::BoxLayout::Coincident, rstest::BoxLayout::LogUniform})
    for (int n : {1, 2, 7, 100, 3000}) {
      const Prims p = rstest::random_boxes(rng, n, layout);
      Octree oc;
      oc.build(p.bounds, {}, GetParam());
      SCOPED_TRACE(::testing::Message() << "layout " << int(layout) << " n " << n);
      check_invariants(oc, p);
      if (layout == rstest::BoxLayout::Uniform && n == 3000) {
        const OctreeQuality q = oc.quality();
        std::printf(
            "%s, 3000 uniform boxes: %u nodes, depth %u, %.2f refs/prim, %zu in inner nodes\n",
            to_string(GetParam()), q.nodes, q.depth, q.refs_per_prim, q.inner_refs);
        EXPECT_GT(q.depth, 2u);
        if (GetParam() == PrimStorage::SmallestCell) {
          EXPECT_GT(q.inner_refs, 0u) << "boxes across a cut stay in inner nodes";
        } else {
          EXPECT_GT(q.refs_per_prim, 1.0) << "boxes across a cut are stored several times";
        }
      }
    }
}

TEST(Octree, LooseFactorZeroAndLarge) {
  // 0: a plain octree where whatever straddles a cut stays above it (many
  // inner references); large: everything fits the octant of its center, down
  // to the leaves. (A bad factor: test_accel_conformance.)
  Rng rng(52);
  const Prims p = rstest::random_boxes(rng, 2000, rstest::BoxLayout::Uniform);
  size_t inner[3];
  int k = 0;
  for (float f : {0.0f, 0.1f, kMaxLooseFactor}) {
    Octree oc;
    oc.build(p.bounds, {}, PrimStorage::SmallestCell, f);
    SCOPED_TRACE(::testing::Message() << "loose factor " << f);
    check_invariants(oc, p);
    inner[k++] = oc.quality().inner_refs;
  }
  std::printf("references in inner nodes, loose factor 0, 0.1, 0.5: %zu, %zu, %zu\n", inner[0],
              inner[1], inner[2]);
  EXPECT_GT(inner[0], inner[1]);
  EXPECT_GT(inner[1], inner[2]);
}

TEST(Octree, SplitStorageIsRefused) {
  // By the factory's one check, which names the storage; the builder takes
  // every-cell and smallest-cell.
  EXPECT_TRUE(rstest::storage_refused(AccelKind::Octree, PrimStorage::Split));
  const std::string e = accel_storage_error(AccelKind::Octree, PrimStorage::Split);
  EXPECT_NE(e.find("split"), std::string::npos) << e;
}

TEST_P(OctreeStorage, DegenerateInput) {
  Octree oc;
  oc.build({}, {}, GetParam());  // none
  EXPECT_TRUE(oc.empty());
  float tmax = kInfinity;
  NullTraversalObserver obs;
  EXPECT_FALSE(oc.traverse<false>(
      Ray{Vec3(0), Vec3(1, 0, 0), kInfinity}, tmax, [](uint32_t, float&) { return true; }, obs));
  Prims one;  // one
  one.add(Bounds3(Vec3(-1), Vec3(1)));
  oc.build(one.bounds, {}, GetParam());
  check_invariants(oc, one);
  EXPECT_EQ(oc.nodes.size(), 1u);
  Prims point;  // everything at one point, zero-size boxes: a point-like root
  for (int i = 0; i < 500; ++i) point.add(Bounds3(Vec3(1, 2, 3)));
  oc.build(point.bounds, {}, GetParam());
  check_invariants(oc, point);
  EXPECT_EQ(oc.nodes.size(), 1u);
  Prims two;  // two points, many boxes at each: cut down to the depth limit
  for (int i = 0; i < 100; ++i) two.add(Bounds3(Vec3(0.3f, 0.2f, 0.1f)));
  for (int i = 0; i < 100; ++i) two.add(Bounds3(Vec3(1.7f, 0.9f, 0.6f)));
  oc.build(two.bounds, {}, GetParam());
  check_invariants(oc, two);
  EXPECT_EQ(oc.quality().depth, uint32_t(oc.max_depth())) << "max depth reached";
  OctreeBuildConfig shallow;
  shallow.max_depth = 1;
  oc.build(two.bounds, shallow, GetParam());
  check_invariants(oc, two);
  EXPECT_EQ(oc.quality().depth, 1u);
  shallow.max_depth = 1000;  // capped
  oc.build(two.bounds, shallow, GetParam());
  EXPECT_EQ(oc.max_depth(), Octree::kMaxDepth);
  check_invariants(oc, two);
  Prims flat;  // zero-size boxes on a line, and a stack of flat boxes in one plane
  for (int i = 0; i < 300; ++i) flat.add(Bounds3(Vec3(float(i), 0, 0)));
  for (int i = 0; i < 300; ++i) flat.add(Bounds3(Vec3(0, 0, 5), Vec3(1, float(i % 7), 5)));
  oc.build(flat.bounds, {}, GetParam());
  check_invariants(oc, flat);
}

// The octree's own settings through the checks of the conformance suite
// (which runs both storages at the default loose factor): loose factors 0 (a
// plain octree where straddlers stay up) and the largest, and the default,
// with rays lying in each cell's exact cut planes (the view shows a loose
// octree's enlarged boxes only).
class OctreeLooseFactor : public ::testing::TestWithParam<float> {};
INSTANTIATE_TEST_SUITE_P(Own, OctreeLooseFactor,
                         ::testing::Values(0.0f, kDefaultLooseFactor, kMaxLooseFactor),
                         [](const auto& info) {
                           return info.param == 0.0f                  ? std::string("loose_0")
                                  : info.param == kDefaultLooseFactor ? std::string("loose_default")
                                                                      : std::string("loose_max");
                         });

TEST_P(OctreeLooseFactor, QueriesMatchBruteForceAndTheBvh) {
  Rng rng(54);
  AccelConfig ac;
  ac.kind = AccelKind::Octree;
  ac.storage = PrimStorage::SmallestCell;
  ac.loose_factor = GetParam();
  rstest::check_setting(ac, "loose octree", rng, [&](const Scene& scene, std::vector<Ray>& rays) {
    const Octree& oc = scene.accel().structure_as<Octree>();
    ASSERT_TRUE(oc.loose());
    const Bounds3 world = oc.node_box(oc.bounds());
    const std::vector<Bounds3> cells = oc.cells();
    for (size_t i = 0; i < oc.nodes.size(); i += 5) {
      if (oc.nodes[i].is_leaf()) continue;
      // The cut through the middle, with an axis-parallel ray through it.
      const Vec3 mid = 0.5f * cells[i].lo + 0.5f * cells[i].hi;
      for (int a = 0; a < 3; ++a) rstest::add_plane_rays(rng, world, a, mid[a], rays, true, &mid);
    }
  });
}

TEST(Octree, StorageNamesAndMemory) {
  for (PrimStorage s : {PrimStorage::EveryCell, PrimStorage::SmallestCell, PrimStorage::Split}) {
    PrimStorage parsed = PrimStorage::Split;
    ASSERT_TRUE(parse_prim_storage(to_string(s), parsed));
    EXPECT_EQ(parsed, s);
  }
  PrimStorage s = PrimStorage::EveryCell;
  EXPECT_FALSE(parse_prim_storage("loose", s));
  EXPECT_EQ(s, PrimStorage::EveryCell);
  EXPECT_STREQ(to_string(PrimStorage::SmallestCell), "smallest-cell");
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 3));
  for (PrimStorage storage : {PrimStorage::EveryCell, PrimStorage::SmallestCell}) {
    AccelConfig ac;
    ac.kind = AccelKind::Octree;
    ac.storage = storage;
    scene.commit(ac);
    const Aggregate& a = scene.accel();
    EXPECT_TRUE(a.structure_as<BvhWalk>().walk().empty());
    EXPECT_TRUE(a.structure_as<KdTree>().empty());
    // The binary BVH is built when first asked for; from then on the
    // aggregate holds it and counts it.
    const size_t binary = a.bvh().quality().memory_bytes;
    EXPECT_EQ(a.memory_bytes(), binary + a.structure_as<Octree>().memory_bytes() +
                                    a.records().size() * (sizeof(PrimRecord) + sizeof(uint32_t)));
    EXPECT_GT(a.structure_as<Octree>().memory_bytes(), 0u);
  }
}

// The storage trends docs/acceleration.md reports for the bunny, on a mesh of
// the bunny's size (rstest::lumpy_mesh(6), 81,920 triangles): fewer triangles
// stay in inner nodes as the loose factor grows, and every-cell stores a
// triangle more often as the depth limit grows.
TEST(Octree, StorageFiguresOnAScannedSizeMesh) {
  Scene scene;
  scene.meshes.push_back(rstest::lumpy_mesh(6));
  const std::vector<Bounds3> boxes = rstest::triangle_boxes(scene);
  ASSERT_GT(boxes.size(), 60000u);
  size_t last_inner = boxes.size();
  for (float f : {0.1f, 0.25f, 0.5f}) {
    Octree oc;
    oc.build(boxes, {}, PrimStorage::SmallestCell, f);
    const OctreeQuality q = oc.quality();
    std::printf(
        "lumpy mesh, smallest-cell, loose factor %.2f: %u nodes, depth %u, %.1f%% in inner nodes\n",
        double(f), q.nodes, q.depth, 100.0 * double(q.inner_refs) / double(boxes.size()));
    EXPECT_LT(q.inner_refs, last_inner);
    last_inner = q.inner_refs;
  }
  double last_refs = 0.0;
  for (int depth : {6, 8, 10, 12}) {
    OctreeBuildConfig cfg;
    cfg.max_depth = depth;
    Octree oc;
    oc.build(boxes, cfg);
    const OctreeQuality q = oc.quality();
    std::printf(
        "lumpy mesh, every-cell, max depth %d: %u nodes, %.2f refs/prim, %.1f per leaf, %.2f MiB\n",
        depth, q.nodes, q.refs_per_prim, q.mean_leaf_refs,
        double(q.memory_bytes) / (1024.0 * 1024.0));
    EXPECT_GT(q.refs_per_prim, last_refs);
    last_refs = q.refs_per_prim;
  }
}

}  // namespace
