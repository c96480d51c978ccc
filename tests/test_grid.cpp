// The uniform grid (grid.h): the automatic and explicit resolutions, the
// builder's invariants (every primitive in exactly the cells its bounds
// overlap), limits and degenerate input; the DDA walk enters every cell a ray
// touches, in order; the loose grid's storage rule; its own settings
// (resolutions, loose factors) through the conformance checks, and its own
// walk contract (one box, at most one cell culled); its range walk enters
// exactly the cells a range overlaps and follows a shrinking range. What every
// structure does (queries == brute force and == the BVH, mailboxing, the
// observer, range queries, images) is test_accel_conformance's.
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

GridBuildConfig explicit_res(uint32_t x, uint32_t y, uint32_t z) {
  GridBuildConfig c;
  c.resolution = glm::uvec3(x, y, z);
  return c;
}

// Whether the closed boxes a and b overlap.
bool overlap(const Bounds3& a, const Bounds3& b) {
  return a.lo.x <= b.hi.x && a.hi.x >= b.lo.x && a.lo.y <= b.hi.y && a.hi.y >= b.lo.y &&
         a.lo.z <= b.hi.z && a.hi.z >= b.lo.z;
}

// Every primitive is referenced by exactly the cells whose closed box its
// closed bounds overlap (the cells computed here by scanning the planes, not
// by the grid's binary search), once each, in index order within a cell; the
// planes split the grid's box evenly; the quality figures add up.
void check_invariants(const UniformGrid& g, const Prims& p) {
  const size_t n = p.bounds.size();
  ASSERT_EQ(g.empty(), n == 0);
  if (n == 0) return;
  Bounds3 all;
  for (const Bounds3& b : p.bounds) all.extend(b);
  ASSERT_EQ(g.bounds().lo, all.lo);
  ASSERT_EQ(g.bounds().hi, all.hi);
  const glm::uvec3 res = g.resolution();
  ASSERT_EQ(g.cells(), size_t(res.x) * res.y * res.z);
  ASSERT_EQ(g.offsets.size(), g.cells() + 1);
  for (int a = 0; a < 3; ++a) {
    ASSERT_GE(res[a], 1u);
    ASSERT_LE(res[a], UniformGrid::kMaxResolution);
    const std::vector<float>& pl = g.planes[a];
    ASSERT_EQ(pl.size(), res[a] + 1);
    ASSERT_EQ(pl.front(), all.lo[a]);
    ASSERT_EQ(pl.back(), all.hi[a]);
    const double width = (double(all.hi[a]) - double(all.lo[a])) / res[a];
    for (uint32_t k = 0; k < res[a]; ++k) {
      ASSERT_LE(pl[k], pl[k + 1]);
      ASSERT_NEAR(double(pl[k]), double(all.lo[a]) + k * width,
                  1e-6 * std::max(std::abs(double(all.lo[a])), std::abs(double(all.hi[a]))));
    }
  }
  // The cells each primitive overlaps, by scanning the planes.
  std::vector<glm::uvec3> first(n), last(n);
  size_t expected_refs = 0;
  for (size_t i = 0; i < n; ++i) {
    const Bounds3& b = p.bounds[i];
    for (int a = 0; a < 3; ++a) {
      const std::vector<float>& pl = g.planes[a];
      uint32_t f = ~0u, l = 0;
      for (uint32_t k = 0; k < res[a]; ++k)
        if (pl[k] <= b.hi[a] && pl[k + 1] >= b.lo[a]) {
          f = std::min(f, k);
          l = k;
        }
      ASSERT_NE(f, ~0u) << "primitive " << i << " overlaps no cell on axis " << a;
      first[i][a] = f;
      last[i][a] = l;
    }
    const glm::uvec3 span = last[i] - first[i] + 1u;
    expected_refs += size_t(span.x) * span.y * span.z;
  }
  ASSERT_EQ(g.refs.size(), expected_refs);
  ASSERT_EQ(g.offsets.front(), 0u);
  ASSERT_EQ(g.offsets.back(), g.refs.size());
  for (uint32_t z = 0; z < res.z; ++z)
    for (uint32_t y = 0; y < res.y; ++y)
      for (uint32_t x = 0; x < res.x; ++x) {
        const uint32_t c = g.cell_id(x, y, z);
        ASSERT_LE(g.offsets[c], g.offsets[c + 1]);
        const std::span<const uint32_t> refs = g.cell_refs(c);
        for (size_t k = 0; k < refs.size(); ++k) {
          const uint32_t r = refs[k];
          ASSERT_LT(r, n);
          if (k > 0) {
            ASSERT_LT(refs[k - 1], r) << "cell " << c;
          }
          ASSERT_TRUE(x >= first[r].x && x <= last[r].x && y >= first[r].y && y <= last[r].y &&
                      z >= first[r].z && z <= last[r].z)
              << "primitive " << r << " in cell (" << x << ", " << y << ", " << z
              << "), which its bounds do not overlap";
          ASSERT_TRUE(overlap(g.cell_box(x, y, z), p.bounds[r]));
        }
      }
  // With the count equal and no reference outside its cells, and no duplicate
  // within a cell, every primitive is in every cell it overlaps.
  const GridQuality q = g.quality();
  EXPECT_EQ(q.resolution, res);
  EXPECT_EQ(q.cells, g.cells());
  EXPECT_EQ(q.references, g.refs.size());
  EXPECT_DOUBLE_EQ(q.refs_per_prim, double(g.refs.size()) / double(n));
  EXPECT_EQ(q.memory_bytes,
            (g.offsets.size() + g.refs.size()) * 4 + (res.x + res.y + res.z + 3) * 4);
  EXPECT_EQ(g.memory_bytes(), q.memory_bytes);
  size_t empty = 0;
  uint32_t most = 0;
  for (size_t c = 0; c < g.cells(); ++c) {
    empty += g.offsets[c] == g.offsets[c + 1];
    most = std::max(most, g.offsets[c + 1] - g.offsets[c]);
  }
  EXPECT_EQ(q.empty_cells, empty);
  EXPECT_EQ(q.max_cell_refs, most);
  if (q.cells > empty) {
    EXPECT_DOUBLE_EQ(q.mean_cell_refs, double(g.refs.size()) / double(q.cells - empty));
  }
}

TEST(Grid, BuildInvariantsOnRandomBoxes) {
  Rng rng(51);
  const GridBuildConfig configs[] = {GridBuildConfig{}, explicit_res(1, 1, 1),
                                     explicit_res(40, 1, 3), explicit_res(0, 7, 0)};
  for (auto layout : {rstest::BoxLayout::Uniform, rstest::BoxLayout::Clustered,
                      rstest::BoxLayout::Coincident, rstest::BoxLayout::LogUniform})
    for (int n : {1, 2, 7, 100, 2000})
      for (const GridBuildConfig& cfg : configs) {
        const Prims p = rstest::random_boxes(rng, n, layout);
        UniformGrid g;
        g.build(p.bounds, cfg);
        SCOPED_TRACE(::testing::Message()
                     << "layout " << int(layout) << " n " << n << " resolution "
                     << ::testing::PrintToString(cfg.resolution));
        check_invariants(g, p);
        for (int a = 0; a < 3; ++a)
          if (cfg.resolution[a]) {
            EXPECT_EQ(g.resolution()[a], cfg.resolution[a]);
          }
        if (::testing::Test::HasFatalFailure()) return;
      }
}

TEST(Grid, AutomaticResolutionFollowsTheObjectCountAndTheBoxShape) {
  Rng rng(52);
  const float density = GridBuildConfig{}.density;
  // Uniform boxes in a cube: about density * n cubic cells.
  for (int n : {10, 1000, 20000}) {
    Prims p;
    for (int i = 0; i < n; ++i) {
      const Vec3 c = to_f(DVec3(rng.uniform(0, 10), rng.uniform(0, 10), rng.uniform(0, 10)));
      p.add(Bounds3(c - 0.01f, c + 0.01f));
    }
    UniformGrid g;
    g.build(p.bounds);
    const double cells = double(g.cells());
    std::printf("%d boxes in a cube: %u x %u x %u cells, %.2f per box\n", n, g.resolution().x,
                g.resolution().y, g.resolution().z, cells / n);
    EXPECT_GT(cells, 0.5 * density * n);
    EXPECT_LT(cells, 2.0 * density * n);
    const glm::uvec3 r = g.resolution();
    EXPECT_LE(std::max({r.x, r.y, r.z}) - std::min({r.x, r.y, r.z}), 1u);
  }
  // A slab 100 x 10 x 1: cells per axis in proportion to the extents.
  Prims slab;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 c = to_f(DVec3(rng.uniform(0, 100), rng.uniform(0, 10), rng.uniform(0, 1)));
    slab.add(Bounds3(c, c + 0.001f));
  }
  UniformGrid g;
  g.build(slab.bounds);
  glm::uvec3 r = g.resolution();
  std::printf("slab 100 x 10 x 1: %u x %u x %u cells\n", r.x, r.y, r.z);
  EXPECT_NEAR(double(r.x) / r.y, 10.0, 1.5);
  EXPECT_NEAR(double(r.y) / r.z, 10.0, 3.0);
  EXPECT_GT(double(g.cells()), 0.5 * density * 20000);
  EXPECT_LT(double(g.cells()), 2.0 * density * 20000);
  // Flat (all z = 0): one cell in z, the density spread over the area.
  Prims flat;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 c(float(rng.uniform(0, 20)), float(rng.uniform(0, 20)), 0.0f);
    flat.add(Bounds3(c, c + Vec3(0.01f, 0.01f, 0.0f)));
  }
  g.build(flat.bounds);
  r = g.resolution();
  EXPECT_EQ(r.z, 1u);
  EXPECT_NEAR(double(r.x) * r.y, density * 5000.0, 0.3 * density * 5000.0);
  // Thin but not flat (z extent 1e-6): z gets one cell, not a cube's share.
  flat.add(Bounds3(Vec3(0.0f, 0.0f, 1e-6f)));
  g.build(flat.bounds);
  EXPECT_EQ(g.resolution().z, 1u);
  EXPECT_NEAR(double(g.resolution().x) * g.resolution().y, density * 5001.0,
              0.3 * density * 5001.0);
  // A line: all cells along it.
  Prims line;
  for (int i = 0; i < 300; ++i) line.add(Bounds3(Vec3(float(i), 5.0f, 5.0f)));
  g.build(line.bounds);
  EXPECT_EQ(g.resolution(), glm::uvec3(uint32_t(std::lround(density * 300)), 1u, 1u));
  // One axis given: the others share the rest of the cells.
  GridBuildConfig one_axis;
  one_axis.resolution = glm::uvec3(0u, 0u, 4u);
  g.build(slab.bounds, one_axis);
  r = g.resolution();
  EXPECT_EQ(r.z, 4u);
  EXPECT_NEAR(double(r.x) / r.y, 10.0, 1.5);
  // A different density scales the cell count.
  GridBuildConfig dense;
  dense.density = 4.0f * density;
  UniformGrid g4;
  g4.build(slab.bounds, dense);
  g.build(slab.bounds);
  EXPECT_NEAR(double(g4.cells()) / double(g.cells()), 4.0, 1.0);
}

TEST(Grid, LimitsAreGuardedWithClearErrors) {
  Prims p;
  p.add(Bounds3(Vec3(0.0f), Vec3(1.0f)));
  UniformGrid g;
  auto message = [&](const GridBuildConfig& cfg, const Prims& prims) -> std::string {
    try {
      g.build(prims.bounds, cfg);
    } catch (const std::length_error& e) {
      return e.what();
    }
    return "no error";
  };
  // The builder throws the one check's message (grid_resolution_error, which
  // the CLI and VTK report too).
  EXPECT_EQ(message(explicit_res(UniformGrid::kMaxResolution + 1, 1, 1), p),
            "UniformGrid::build: resolution 4097 x 1 x 1 exceeds 4096 cells per axis");
  EXPECT_EQ(message(explicit_res(4096, 4096, 4096), p),
            "UniformGrid::build: resolution 4096 x 4096 x 4096 has more than 16777216 cells");
  EXPECT_EQ(grid_resolution_error(glm::uvec3(4096, 4096, 0)), "") << "0: automatic";
  EXPECT_EQ(grid_resolution_error(glm::uvec3(2048, 2048, 4)), "") << "exactly kMaxCells";
  EXPECT_NE(grid_resolution_error(glm::uvec3(0, 5000, 0)), "");
  // 2048 x 2048 x 4 = kMaxCells cells, each holding 17 boxes that span them all.
  Prims big;
  for (int i = 0; i < 17; ++i) big.add(Bounds3(Vec3(0.0f), Vec3(1.0f)));
  EXPECT_NE(message(explicit_res(2048, 2048, 4), big).find("more than kMaxReferences"),
            std::string::npos);
  // The automatic resolution coarsens instead: long thin boxes that cross the
  // whole grid would otherwise be stored in about density * n cells each.
  Rng rng(53);
  Prims slivers;
  for (int i = 0; i < 2000; ++i) {
    const float y = float(rng.uniform(0, 10)), z = float(rng.uniform(0, 10));
    slivers.add(Bounds3(Vec3(0.0f, y, z), Vec3(10.0f, y + 10.0f, z + 0.01f)));
  }
  g.build(slivers.bounds);
  EXPECT_LE(g.refs.size(), UniformGrid::kMaxAutoReferencesPerPrim * slivers.bounds.size());
  EXPECT_GT(g.cells(), 1u);
  check_invariants(g, slivers);
  // Non-finite or inverted bounds.
  // (Set directly: Bounds3's constructor would drop a NaN through min/max.)
  Bounds3 nan_box, inf_box, inverted;
  nan_box.lo = Vec3(0.0f);
  nan_box.hi = Vec3(1.0f, std::nanf(""), 1.0f);
  inf_box.lo = Vec3(-kInfinity, 0.0f, 0.0f);
  inf_box.hi = Vec3(1.0f);
  inverted.lo = Vec3(0.0f, 2.0f, 0.0f);
  inverted.hi = Vec3(1.0f);
  for (const Bounds3& bad : {nan_box, inf_box, inverted, Bounds3()}) {
    Prims q = p;
    q.bounds.push_back(bad);
    EXPECT_THROW(g.build(q.bounds), std::invalid_argument);
  }
}

TEST(Grid, DegenerateInput) {
  UniformGrid g;
  g.build({});  // none
  EXPECT_TRUE(g.empty());
  EXPECT_EQ(g.cells(), 0u);
  EXPECT_EQ(g.memory_bytes(), 0u);
  float tmax = kInfinity;
  NullTraversalObserver obs;
  EXPECT_FALSE(g.traverse<false>(
      Ray{Vec3(0), Vec3(1, 0, 0), kInfinity}, tmax, [](uint32_t, float&) { return true; }, obs));
  Prims one;  // one
  one.add(Bounds3(Vec3(-1), Vec3(1)));
  g.build(one.bounds);
  check_invariants(g, one);
  Prims point;  // everything at one point, zero-size boxes
  for (int i = 0; i < 500; ++i) point.add(Bounds3(Vec3(1, 2, 3)));
  g.build(point.bounds);
  check_invariants(g, point);
  EXPECT_EQ(g.resolution(), glm::uvec3(1u));
  EXPECT_EQ(g.refs.size(), 500u);
  // A ray through the point finds it; one beside it does not.
  int found = 0;
  tmax = kInfinity;
  g.traverse<false>(
      Ray{Vec3(0, 2, 3), Vec3(1, 0, 0), kInfinity}, tmax,
      [&](uint32_t, float&) { return ++found, false; }, obs);
  EXPECT_EQ(found, 500);
  found = 0;
  g.traverse<false>(
      Ray{Vec3(0, 2.5f, 3), Vec3(1, 0, 0), kInfinity}, tmax,
      [&](uint32_t, float&) { return ++found, false; }, obs);
  EXPECT_EQ(found, 0);
  // Explicit cells on a flat axis: every box is in all of them.
  g.build(point.bounds, explicit_res(3, 1, 2));
  check_invariants(g, point);
  EXPECT_EQ(g.refs.size(), 3000u);
  Prims flat;  // zero-size boxes on a line, and a stack of flat boxes in one plane
  for (int i = 0; i < 300; ++i) flat.add(Bounds3(Vec3(float(i), 0, 0)));
  for (int i = 0; i < 300; ++i) flat.add(Bounds3(Vec3(0, 0, 5), Vec3(1, float(i % 7), 5)));
  g.build(flat.bounds);
  check_invariants(g, flat);
  g.build(flat.bounds, explicit_res(64, 64, 64));
  check_invariants(g, flat);
}

struct CellLog : TraversalHooks {
  static constexpr bool kActive = true;
  std::vector<uint32_t> cells;
  size_t boxes = 0, culls = 0;
  void on_node(uint32_t c) { cells.push_back(c); }
  void on_box_test(uint32_t, bool) { ++boxes; }
  void on_cull(uint32_t) { ++culls; }
};

// The cells one walk enters, in order, with nothing hit (tmax stays).
std::vector<uint32_t> walk_cells(const UniformGrid& g, const Ray& ray, size_t* culls = nullptr) {
  CellLog obs;
  float tmax = ray.tmax;
  g.traverse<false>(
      ray, tmax, [](uint32_t, float&) { return false; }, obs);
  EXPECT_EQ(obs.boxes, 1u);
  if (culls) *culls = obs.culls;
  return obs.cells;
}

// The walk enters every cell whose box the ray touches (box_interval(), the
// BVH's robust slab test), each once, and no cell it clearly misses, nearest
// first: rays through random points, through the planes' crossings (corners
// and edges of cells), lying in planes and along them, from inside and
// outside, and with short tmax.
TEST(Grid, WalkEntersTheCellsTheRayTouchesInOrder) {
  Rng rng(54);
  for (const glm::uvec3 res : {glm::uvec3(1u), glm::uvec3(5u), glm::uvec3(7u, 1u, 3u),
                               glm::uvec3(16u, 16u, 16u), glm::uvec3(40u, 2u, 9u)}) {
    Prims p;
    p.add(Bounds3(Vec3(-1.5f, 0.25f, 3.0f), Vec3(2.75f, 1.75f, 5.5f)));
    UniformGrid g;
    g.build(p.bounds, explicit_res(res.x, res.y, res.z));
    const Bounds3 box = g.bounds();
    auto plane_point = [&]() {  // a crossing of three planes (a cell corner)
      return Vec3(g.planes[0][size_t(rng.integer(0, int(res.x)))],
                  g.planes[1][size_t(rng.integer(0, int(res.y)))],
                  g.planes[2][size_t(rng.integer(0, int(res.z)))]);
    };
    auto any_point = [&](double margin) {
      const DVec3 lo = to_d(box.lo) - margin * to_d(box.extent());
      const DVec3 ext = (1.0 + 2.0 * margin) * to_d(box.extent());
      return to_f(lo + ext * DVec3(rng.uniform(), rng.uniform(), rng.uniform()));
    };
    int rays = 0, corner_rays = 0;
    for (int i = 0; i < 6000; ++i) {
      Ray ray{Vec3(0.0f), Vec3(1.0f), kInfinity};
      const int mode = i % 6;
      if (mode == 0) {  // random
        ray.origin = any_point(0.5);
        ray.dir = any_point(0.0) - ray.origin;
      } else if (mode == 1) {  // through two cell corners
        ray.origin = plane_point();
        const Vec3 to = plane_point();
        ray.dir = to - ray.origin;
        ray.origin -= 2.0f * ray.dir;
        ++corner_rays;
      } else if (mode == 2) {  // from a corner
        ray.origin = plane_point();
        ray.dir = to_f(rng.unit_vector());
      } else if (mode == 3) {  // lying in a plane, or axis-parallel
        ray.origin = any_point(0.1);
        const int a = rng.integer(0, 2);
        ray.origin[a] = g.planes[size_t(a)][size_t(rng.integer(0, int(res[a])))];
        ray.dir = to_f(rng.unit_vector());
        ray.dir[a] = 0.0f;
        if (rng.coin()) ray.dir[(a + 1) % 3] = 0.0f;
      } else if (mode == 4) {  // diagonal through corners: (1, 1, 1) steps of a cube grid
        ray.origin = plane_point();
        ray.dir =
            Vec3(rng.coin() ? 1.0f : -1.0f, rng.coin() ? 1.0f : -1.0f, rng.coin() ? 1.0f : -1.0f) *
            (box.extent() / Vec3(res));
      } else {  // inside, short
        ray.origin = any_point(0.0);
        ray.dir = to_f(rng.unit_vector());
        ray.tmax = float(rng.uniform(0, 2));
      }
      if (ray.dir == Vec3(0.0f)) continue;
      ++rays;
      const std::vector<uint32_t> cells = walk_cells(g, ray);
      std::set<uint32_t> entered(cells.begin(), cells.end());
      ASSERT_EQ(entered.size(), cells.size()) << "a cell entered twice, ray " << i;
      const Vec3 inv = 1.0f / ray.dir;
      float last_entry = 0.0f;
      for (uint32_t z = 0; z < res.z; ++z)
        for (uint32_t y = 0; y < res.y; ++y)
          for (uint32_t x = 0; x < res.x; ++x) {
            const Bounds3 c = g.cell_box(x, y, z);
            float tn, tf;
            box_interval(c.lo, c.hi, ray.origin, inv, ray.tmax, tn, tf);
            const uint32_t id = g.cell_id(x, y, z);
            // A ray lying in a face's plane touches the cells on both sides;
            // the walk takes one (a primitive touching the plane is stored
            // in both).
            bool on_face = false;
            for (int a = 0; a < 3; ++a)
              on_face |=
                  ray.dir[a] == 0.0f && (ray.origin[a] == c.lo[a] || ray.origin[a] == c.hi[a]);
            if (tn <= tf && !on_face) {
              ASSERT_TRUE(entered.count(id))
                  << "ray " << i << " (mode " << mode << ") touches cell (" << x << ", " << y
                  << ", " << z << ") at t " << tn << ".." << tf << " but skips it";
            } else if (tn > tf * 1.001f) {
              ASSERT_FALSE(entered.count(id))
                  << "ray " << i << " (mode " << mode << ") enters cell (" << x << ", " << y << ", "
                  << z << "), which it misses";
            }
          }
      // Nearest first: each cell's entry distance is not (clearly) before
      // the one entered before it.
      for (uint32_t id : cells) {
        const uint32_t x = id % res.x, y = id / res.x % res.y, z = id / (res.x * res.y);
        const Bounds3 c = g.cell_box(x, y, z);
        float tn, tf;
        box_interval(c.lo, c.hi, ray.origin, inv, ray.tmax, tn, tf);
        ASSERT_GE(tn * 1.001f + 1e-6f, last_entry) << "ray " << i << ": cells out of order";
        last_entry = std::max(last_entry, tn);
      }
    }
    EXPECT_GT(rays, 5000);
    EXPECT_GT(corner_rays, 500);
  }
}

// The grid's own settings through the checks of the conformance suite
// (which runs the automatic resolution at the default loose factor): one
// cell, very anisotropic and fine resolutions, every-cell and loose, loose
// factors 0 and the largest, with rays lying in the grid's exact planes and
// through its cell corners (the view shows a loose grid's enlarged boxes
// only).
struct GridSetting {
  std::string name;
  glm::uvec3 resolution;
  PrimStorage storage;
  float loose_factor;
};
class GridOwnSetting : public ::testing::TestWithParam<GridSetting> {
 protected:
  AccelConfig config() const {
    AccelConfig ac;
    ac.kind = AccelKind::Grid;
    ac.grid.resolution = GetParam().resolution;
    ac.storage = GetParam().storage;
    ac.loose_factor = GetParam().loose_factor;
    return ac;
  }
};
constexpr PrimStorage kEvery = PrimStorage::EveryCell, kLoose = PrimStorage::SmallestCell;
INSTANTIATE_TEST_SUITE_P(
    Own, GridOwnSetting,
    ::testing::Values(
        GridSetting{"auto_every_cell", glm::uvec3(0u), kEvery, 0.0f},
        GridSetting{"1x1x1_every_cell", glm::uvec3(1u), kEvery, 0.0f},
        GridSetting{"200x1x3_every_cell", glm::uvec3(200u, 1u, 3u), kEvery, 0.0f},
        GridSetting{"160x160x160_every_cell", glm::uvec3(160u), kEvery, 0.0f},
        GridSetting{"auto_loose_0", glm::uvec3(0u), kLoose, 0.0f},
        GridSetting{"auto_loose_default", glm::uvec3(0u), kLoose, kDefaultLooseFactor},
        GridSetting{"auto_loose_max", glm::uvec3(0u), kLoose, kMaxLooseFactor},
        GridSetting{"1x1x1_loose_default", glm::uvec3(1u), kLoose, kDefaultLooseFactor},
        GridSetting{"200x1x3_loose_default", glm::uvec3(200u, 1u, 3u), kLoose, kDefaultLooseFactor},
        GridSetting{"3x90x2_loose_default", glm::uvec3(3u, 90u, 2u), kLoose, kDefaultLooseFactor},
        GridSetting{"128x128x128_loose_default", glm::uvec3(128u), kLoose, kDefaultLooseFactor}),
    [](const auto& info) { return info.param.name; });

TEST_P(GridOwnSetting, QueriesMatchBruteForceAndTheBvh) {
  Rng rng(56);
  rstest::check_setting(
      config(), "grid " + GetParam().name, rng, [&](const Scene& scene, std::vector<Ray>& rays) {
        const UniformGrid& g = scene.accel().structure_as<UniformGrid>();
        ASSERT_EQ(g.loose(), GetParam().storage == kLoose);
        const glm::uvec3 res = g.resolution();
        for (int a = 0; a < 3; ++a)
          if (GetParam().resolution[a]) {
            ASSERT_EQ(res[a], GetParam().resolution[a]);
          }
        auto corner = [&]() {
          return Vec3(g.planes[0][size_t(rng.integer(0, int(res.x)))],
                      g.planes[1][size_t(rng.integer(0, int(res.y)))],
                      g.planes[2][size_t(rng.integer(0, int(res.z)))]);
        };
        for (size_t i = 0; i < 1000; ++i) {
          const int a = rng.integer(0, 2);
          rstest::add_plane_rays(rng, g.bounds(), a,
                                 g.planes[size_t(a)][size_t(rng.integer(0, int(res[a])))], rays);
          const Vec3 c0 = corner(), c1 = corner();  // through two cell corners
          if (c0 != c1) rays.push_back(Ray{c0 - 1.5f * (c1 - c0), c1 - c0, kInfinity});
        }
      });
}

// The grid's walk on long thin triangles: cells are entered without box tests
// of their own, the grid's box is the one box tested (every-cell) or each
// (loose) box at most once, at most one cell is culled and never one already
// entered; with one cell nothing is culled, otherwise the grid prunes.
TEST_P(GridOwnSetting, TheWalkTestsTheGridsBoxAndCullsAtMostOneCell) {
  Rng rng(59);
  Scene scene = rstest::sliver_scene(rng);
  scene.commit(config());
  const UniformGrid& g = scene.accel().structure_as<UniformGrid>();
  const GridQuality q = g.quality();
  const bool one_cell = q.cells == 1;
  const size_t prims = scene.accel().records().size();
  const int n_rays = 2000;
  rstest::MailboxTotals t;
  rstest::mailbox_rays(scene, rng, n_rays, size_t(g.box_id()) + 1, t,
                       [&](const rstest::CountingObserver& obs, bool) {
                         ASSERT_EQ(obs.nodes[g.box_id()], 0);
                         for (uint32_t n : obs.boxed())
                           ASSERT_EQ(obs.box_tests[n], 1) << "a box tested twice";
                         if (!g.loose()) {
                           ASSERT_EQ(obs.boxes, obs.box_tests[g.box_id()]);
                           ASSERT_LE(obs.boxes, 1);
                         }
                         ASSERT_LE(obs.culled, 1);
                       });
  if (HasFatalFailure()) return;
  std::printf("grid %s (%ux%ux%u): %.1f of %zu primitives tested per ray, %zu big\n",
              GetParam().name.c_str(), g.resolution().x, g.resolution().y, g.resolution().z,
              double(t.tests) / n_rays, prims, g.big_refs.size());
  const uint64_t all = uint64_t(n_rays) * prims;
  if (one_cell) {
    EXPECT_EQ(t.culls, 0u);
    EXPECT_LE(t.tests, all);
  } else if (!g.loose()) {
    EXPECT_GT(q.refs_per_prim, 1.5) << "the test needs primitives stored several times";
    EXPECT_LT(t.tests, all / 4);
    EXPECT_GT(t.multi_node_rays, uint64_t(n_rays) / 2);
    EXPECT_GT(t.culls, 0u);
  } else if (GetParam().resolution == glm::uvec3(0u)) {
    // At the automatic resolution most slivers fit a loose cell and the grid
    // prunes; with one cell, slabs thinner than the slivers or a fine grid,
    // they do not, and the big list makes the walk brute force (the lesson
    // of docs/acceleration.md).
    EXPECT_LT(t.tests, all / 2);
  }
}

// The loose grid's invariants: each primitive stored exactly once, in the
// cell of its bounds' center when its bounds fit that cell's loose box, else
// in the big list; loose factors 0, 0.1 and the largest, 0.5.
TEST(Grid, SmallestCellStoresEachPrimitiveOnceInItsCenterCell) {
  Rng rng(62);
  for (auto layout : {rstest::BoxLayout::Uniform, rstest::BoxLayout::Clustered})
    for (const glm::uvec3 res : {glm::uvec3(0u), glm::uvec3(40u, 3u, 17u)}) {
      const Prims p = rstest::random_boxes(rng, 3000, layout);
      size_t big[3];
      int k = 0;
      for (float f : {0.0f, kDefaultLooseFactor, kMaxLooseFactor}) {
        SCOPED_TRACE(::testing::Message() << "loose factor " << f);
        UniformGrid g;
        g.build(p.bounds, explicit_res(res.x, res.y, res.z), PrimStorage::SmallestCell, f);
        ASSERT_TRUE(g.loose());
        std::vector<int> seen(p.bounds.size(), 0);
        const glm::uvec3 r = g.resolution();
        // The center's cell, found by scanning the planes (not cell_of()).
        auto center_cell = [&](const Bounds3& b, int a) {
          const float c = b.center()[a];
          uint32_t i = 0;
          while (i + 1 < r[a] && c >= g.planes[size_t(a)][i + 1]) ++i;
          return i;
        };
        for (uint32_t z = 0; z < r.z; ++z)
          for (uint32_t y = 0; y < r.y; ++y)
            for (uint32_t x = 0; x < r.x; ++x)
              for (uint32_t q : g.cell_refs(g.cell_id(x, y, z))) {
                seen.at(q)++;
                const Bounds3& b = p.bounds[q];
                ASSERT_EQ(glm::uvec3(x, y, z),
                          glm::uvec3(center_cell(b, 0), center_cell(b, 1), center_cell(b, 2)));
                ASSERT_TRUE(g.node_box(x, y, z).contains(b));
              }
        for (uint32_t q : g.big_refs) {
          seen.at(q)++;
          const Bounds3& b = p.bounds[q];
          ASSERT_FALSE(
              g.node_box(center_cell(b, 0), center_cell(b, 1), center_cell(b, 2)).contains(b));
        }
        for (int v : seen) ASSERT_EQ(v, 1);
        const GridQuality gq = g.quality();
        EXPECT_EQ(gq.references, p.bounds.size());
        EXPECT_EQ(gq.big_refs, g.big_refs.size());
        big[k++] = g.big_refs.size();
      }
      EXPECT_GT(big[0], big[1]);
      EXPECT_GT(big[1], big[2]);
    }
}

TEST(Grid, SplitStorageIsRefused) {
  // By the factory's one check (a bad loose factor: test_accel_conformance,
  // through the same check); the builder takes every-cell and smallest-cell.
  EXPECT_TRUE(rstest::storage_refused(AccelKind::Grid, PrimStorage::Split));
}

TEST(Grid, MemoryOfTheAggregate) {
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 3));
  AccelConfig ac;
  ac.kind = AccelKind::Grid;
  scene.commit(ac);
  const Aggregate& a = scene.accel();
  EXPECT_TRUE(a.structure_as<BvhWalk>().walk().empty());
  EXPECT_TRUE(a.structure_as<KdTree>().empty());
  // The binary BVH is built when first asked for; from then on the
  // aggregate holds it and counts it.
  const size_t binary = a.bvh().quality().memory_bytes;
  EXPECT_EQ(a.memory_bytes(), binary + a.structure_as<UniformGrid>().memory_bytes() +
                                  a.records().size() * (sizeof(PrimRecord) + sizeof(uint32_t)));
  EXPECT_GT(a.structure_as<UniformGrid>().memory_bytes(), 0u);
}

// A box range: all primitives whose bounds overlap the box.
struct BoxRange {
  Bounds3 box;
  Bounds3 bounds() const { return box; }
  bool overlaps(const Bounds3& b) const { return overlap(box, b); }
};

struct RangeObserver : TraversalHooks {
  static constexpr bool kActive = true;
  std::vector<uint32_t> entered;
  std::set<uint32_t> tested_cells;
  int overlapping_tests = 0;
  void on_node(uint32_t c) { entered.push_back(c); }
  void on_box_test(uint32_t c, bool hit) {
    tested_cells.insert(c);
    overlapping_tests += hit;
  }
};

TEST(Grid, RangeWalkFindsWhatBruteForceFinds) {
  Rng rng(60);
  for (auto layout :
       {rstest::BoxLayout::Uniform, rstest::BoxLayout::Clustered, rstest::BoxLayout::Coincident})
    for (const GridBuildConfig& cfg :
         {GridBuildConfig{}, explicit_res(1, 1, 1), explicit_res(30, 2, 11)}) {
      const Prims p = rstest::random_boxes(rng, 1500, layout);
      UniformGrid g;
      g.build(p.bounds, cfg);
      const Bounds3 world = g.bounds();
      for (int q = 0; q < 200; ++q) {
        BoxRange range;
        const DVec3 lo = to_d(world.lo) - 0.2 * to_d(world.extent());
        const DVec3 ext = 1.4 * to_d(world.extent());
        Vec3 a = to_f(lo + ext * DVec3(rng.uniform(), rng.uniform(), rng.uniform()));
        Vec3 b = to_f(lo + ext * DVec3(rng.uniform(), rng.uniform(), rng.uniform()));
        if (q % 4 == 0) b = a + to_f(0.05 * to_d(world.extent()));  // small
        if (q % 7 == 0) a[q % 3] = b[q % 3];                        // flat
        range.box = Bounds3(a, b);
        std::vector<int> found(p.bounds.size(), 0);
        RangeObserver obs;
        g.walk_range(
            range, [&](uint32_t i) { found.at(i)++; }, obs);
        size_t expected = 0;
        for (size_t i = 0; i < p.bounds.size(); ++i) {
          const bool in = overlap(range.box, p.bounds[i]);
          expected += in;
          ASSERT_LE(found[i], 1) << "primitive " << i << " reported twice";
          // Every primitive whose bounds overlap the range is reported;
          // others only if they share a cell with it.
          if (in) {
            ASSERT_EQ(found[i], 1) << "primitive " << i << " missed, query " << q;
          }
        }
        // The cells entered are exactly those whose box overlaps the range.
        std::set<uint32_t> entered(obs.entered.begin(), obs.entered.end());
        ASSERT_EQ(entered.size(), obs.entered.size());
        const glm::uvec3 r = g.resolution();
        for (uint32_t z = 0; z < r.z; ++z)
          for (uint32_t y = 0; y < r.y; ++y)
            for (uint32_t x = 0; x < r.x; ++x)
              ASSERT_EQ(entered.count(g.cell_id(x, y, z)) == 1,
                        overlap(range.box, g.cell_box(x, y, z)))
                  << "cell (" << x << ", " << y << ", " << z << "), query " << q;
        if (!overlap(range.box, world)) {
          ASSERT_TRUE(obs.entered.empty());
          ASSERT_EQ(obs.tested_cells, std::set<uint32_t>{g.box_id()});
        }
        (void)expected;
      }
    }
}

TEST(Grid, RangeWalkFollowsAShrinkingRange) {
  // The range's bounds shrink after the first primitive found: every
  // primitive overlapping the final box is still reported, once, and cells
  // outside it that were not yet visited are skipped.
  Rng rng(61);
  const Prims p = rstest::random_boxes(rng, 3000, rstest::BoxLayout::Uniform);
  UniformGrid g;
  g.build(p.bounds, explicit_res(20, 20, 20));
  struct Shrinking {
    Bounds3 box, small;
    Bounds3 bounds() const { return box; }
    bool overlaps(const Bounds3& b) const { return overlap(box, b); }
  } range{Bounds3(Vec3(-100.0f), Vec3(100.0f)), Bounds3(Vec3(10.0f), Vec3(30.0f))};
  std::vector<int> found(p.bounds.size(), 0);
  RangeObserver obs;
  g.walk_range(
      range,
      [&](uint32_t i) {
        found.at(i)++;
        range.box = range.small;
      },
      obs);
  for (size_t i = 0; i < p.bounds.size(); ++i) {
    ASSERT_LE(found[i], 1);
    if (overlap(range.small, p.bounds[i])) {
      ASSERT_EQ(found[i], 1) << "primitive " << i;
    }
  }
  EXPECT_LT(obs.entered.size(), g.cells() / 10) << "the walk did not follow the smaller range";
}

}  // namespace
