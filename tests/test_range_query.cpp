// Range queries (range_query.h) through every structure behind the aggregate:
// the exact primitive tests against hand-computed cases; box, sphere and
// k-nearest queries equal to brute force (a loop over the scene's objects)
// for random scenes, degenerate scenes and the bunny, on random, touching,
// zero-size and huge ranges, with exact ties; the walks' observer contract;
// and that the walks prune (a small range visits few nodes, k = 1 fewer than
// a range holding everything).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "accel_test_util.h"
#include "rayscope/accel/accel_view.h"
#include "rayscope/range_query.h"
#include "rayscope/scene_io.h"
#include "rayscope/stats.h"
#include "rayscope_vtk/mesh_files.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

Bounds3 box(const Vec3& lo, const Vec3& hi) {
  Bounds3 b;
  b.lo = lo;
  b.hi = hi;
  return b;
}

// ---------------------------------------------------------------------------
// Exact tests, by hand.

TEST(RangeQueryExact, PointTriangleDistanceByRegion) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // Face region: straight above the face.
  EXPECT_EQ(point_triangle_distance(Vec3(0.25f, 0.25f, 2), a, b, c), 2.0f);
  EXPECT_EQ(point_triangle_distance(Vec3(0.25f, 0.25f, -3), a, b, c), 3.0f);
  // On the face, on an edge, at a vertex: 0.
  EXPECT_EQ(point_triangle_distance(Vec3(0.25f, 0.25f, 0), a, b, c), 0.0f);
  EXPECT_EQ(point_triangle_distance(Vec3(0.5f, 0, 0), a, b, c), 0.0f);
  EXPECT_EQ(point_triangle_distance(Vec3(0.5f, 0.5f, 0), a, b, c), 0.0f);
  EXPECT_EQ(point_triangle_distance(b, a, b, c), 0.0f);
  EXPECT_EQ(point_triangle_distance(c, a, b, c), 0.0f);
  // Vertex regions: the distance to the vertex (3-4-5 triangles).
  EXPECT_EQ(point_triangle_distance(Vec3(-3, 0, 4), a, b, c), 5.0f);
  EXPECT_EQ(point_triangle_distance(Vec3(4, 0, 4), a, b, c), 5.0f);
  EXPECT_EQ(point_triangle_distance(Vec3(0, 4, -4), a, b, c), 5.0f);
  EXPECT_FLOAT_EQ(point_triangle_distance(Vec3(-1, -1, 0), a, b, c), std::sqrt(2.0f));
  // Edge regions: the distance to the edge's line.
  EXPECT_EQ(point_triangle_distance(Vec3(0.5f, -3, 4), a, b, c), 5.0f);   // edge ab
  EXPECT_EQ(point_triangle_distance(Vec3(-4, 0.5f, -3), a, b, c), 5.0f);  // edge ca
  EXPECT_FLOAT_EQ(point_triangle_distance(Vec3(1, 1, 0), a, b, c),
                  float(std::sqrt(0.5)));  // hypotenuse, in the plane
  EXPECT_FLOAT_EQ(point_triangle_distance(Vec3(1, 1, 1), a, b, c), float(std::sqrt(1.5)));
  // Degenerate triangles: a segment, a point.
  EXPECT_EQ(point_triangle_distance(Vec3(1, 3, 4), Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 0, 0)),
            5.0f);
  EXPECT_EQ(point_triangle_distance(Vec3(6, 3, 0), Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 0, 0)),
            5.0f);
  EXPECT_EQ(point_triangle_distance(Vec3(1, 1, 3), Vec3(1), Vec3(1), Vec3(1)), 2.0f);
}

TEST(RangeQueryExact, DistanceNeverBelowTheBoundsDistance) {
  Rng rng(7);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 a = to_f(rng.in_unit_ball()), b = to_f(rng.in_unit_ball()),
               c = to_f(rng.in_unit_ball()), p = to_f(3.0 * rng.in_unit_ball());
    Bounds3 tb(a);
    tb.extend(b);
    tb.extend(c);
    const float d = point_triangle_distance(p, a, b, c);
    EXPECT_GE(d, point_box_distance(p, tb));
    // The maximum only repairs rounding: the exact distance agrees closely.
    EXPECT_NEAR(d, exact_point_triangle_distance(p, a, b, c), 1e-6f * (1.0f + d));
    // And the exact distance is no more than to any vertex, no less than to the plane.
    const float to_vertex = std::min({glm::length(p - a), glm::length(p - b), glm::length(p - c)});
    EXPECT_LE(d, to_vertex * (1 + 1e-6f));
    const DVec3 n = glm::cross(to_d(b) - to_d(a), to_d(c) - to_d(a));
    if (glm::length(n) > 1e-3) {
      EXPECT_GE(d, float(std::abs(glm::dot(to_d(p) - to_d(a), glm::normalize(n)))) * (1 - 1e-6f));
    }
  }
}

TEST(RangeQueryExact, PointBoxDistanceIsMonotone) {
  Rng rng(8);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p = to_f(DVec3(rng.log_uniform_signed(1e-3, 1e3), rng.log_uniform_signed(1e-3, 1e3),
                              rng.log_uniform_signed(1e-3, 1e3)));
    Bounds3 inner(to_f(10.0 * rng.in_unit_ball()), to_f(10.0 * rng.in_unit_ball()));
    Bounds3 outer = inner;
    outer.extend(to_f(20.0 * rng.in_unit_ball()));
    EXPECT_LE(point_box_distance(p, outer), point_box_distance(p, inner));
  }
  EXPECT_EQ(point_box_distance(Vec3(4, 5, 0), box(Vec3(0), Vec3(1, 1, 1))), 5.0f);
  EXPECT_EQ(point_box_distance(Vec3(0.5f), box(Vec3(0), Vec3(1))), 0.0f);
}

TEST(RangeQueryExact, SpherePlaneDistances) {
  EXPECT_EQ(point_sphere_distance(Vec3(0.5f, 0, 0), Vec3(0), 1.0f), 0.0f);  // inside
  EXPECT_EQ(point_sphere_distance(Vec3(1, 0, 0), Vec3(0), 1.0f), 0.0f);     // on it
  EXPECT_EQ(point_sphere_distance(Vec3(3, 4, 0), Vec3(0), 1.0f), 4.0f);
  EXPECT_EQ(point_plane_distance(Vec3(3, -2, 7), Vec3(0), Vec3(0, 1, 0)), 2.0f);
  EXPECT_EQ(point_plane_distance(Vec3(3, 0, 7), Vec3(1, 0, 1), Vec3(0, 1, 0)), 0.0f);
}

TEST(RangeQueryExact, TriangleBoxSeparatingAxes) {
  const Bounds3 unit = box(Vec3(0), Vec3(1));
  // Touching the box at one point, its corner (1, 1, 1); a float further: apart.
  EXPECT_TRUE(triangle_overlaps_box(Vec3(1, 1, 1), Vec3(2, 1, 1), Vec3(1, 2, 1), unit));
  const float up = next_float_up(1.0f);
  EXPECT_FALSE(triangle_overlaps_box(Vec3(up, 1, 1), Vec3(2, 1, 1), Vec3(up, 2, 1), unit));
  // Touching a face with a vertex, and lying in a face.
  EXPECT_TRUE(triangle_overlaps_box(Vec3(0.5f, 0.5f, 1), Vec3(3, 3, 5), Vec3(-3, 3, 5), unit));
  EXPECT_TRUE(triangle_overlaps_box(Vec3(-1, -1, 0), Vec3(3, -1, 0), Vec3(-1, 3, 0), unit));
  // Crossing the box with no vertex inside it: a big triangle through its middle.
  EXPECT_TRUE(
      triangle_overlaps_box(Vec3(-5, -5, 0.5f), Vec3(5, -5, 0.5f), Vec3(0, 10, 0.5f), unit));
  // A sliver through the box diagonally, vertices far outside on both sides.
  EXPECT_TRUE(triangle_overlaps_box(Vec3(-4, -4, -4), Vec3(5, 5, 5), Vec3(5, 5, 5.5f), unit));
  // Bounds overlap but the triangle's plane passes beyond the corner (normal
  // axis separates): x + y + z = 3.5 against max 3.
  EXPECT_FALSE(triangle_overlaps_box(Vec3(3.5f, 0, 0), Vec3(0, 3.5f, 0), Vec3(0, 0, 3.5f), unit));
  // x + y + z = 3 touches the corner (1, 1, 1).
  EXPECT_TRUE(triangle_overlaps_box(Vec3(3, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 3), unit));
  // Separated only by an edge-cross axis: the triangle lies in z = 0.5 beyond
  // the line x + y = 2.25, which misses the box's edge at x = y = 1.
  EXPECT_FALSE(
      triangle_overlaps_box(Vec3(2.25f, 0, 0.5f), Vec3(0, 2.25f, 0.5f), Vec3(3, 3, 0.5f), unit));
  // ... and touching it when the line is x + y = 2.
  EXPECT_TRUE(triangle_overlaps_box(Vec3(2, 0, 0.5f), Vec3(0, 2, 0.5f), Vec3(3, 3, 0.5f), unit));
  // A triangle standing in the plane x + y = 2.25, beside the box's edge.
  EXPECT_FALSE(
      triangle_overlaps_box(Vec3(2.25f, 0, -1), Vec3(0, 2.25f, -1), Vec3(1.125f, 1.125f, 3), unit));
  // Zero-size boxes: points on, off and at the edge of a triangle.
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(triangle_overlaps_box(a, b, c, Bounds3(Vec3(0.25f, 0.25f, 0))));
  EXPECT_TRUE(triangle_overlaps_box(a, b, c, Bounds3(Vec3(0.5f, 0.5f, 0))));
  EXPECT_TRUE(triangle_overlaps_box(a, b, c, Bounds3(b)));
  EXPECT_FALSE(triangle_overlaps_box(a, b, c, Bounds3(Vec3(0.75f, 0.75f, 0))));
  EXPECT_FALSE(triangle_overlaps_box(a, b, c, Bounds3(Vec3(0.25f, 0.25f, 1e-7f))));
  // A segment box (zero size in two axes) through the face, and one beside it.
  EXPECT_TRUE(triangle_overlaps_box(a, b, c, box(Vec3(0.2f, 0.2f, -1), Vec3(0.2f, 0.2f, 1))));
  EXPECT_FALSE(triangle_overlaps_box(a, b, c, box(Vec3(0.6f, 0.6f, -1), Vec3(0.6f, 0.6f, 1))));
  // A flat box (zero size in z) in the triangle's plane, overlapping it only
  // beyond the hypotenuse's corner region: apart, then touching.
  EXPECT_FALSE(triangle_overlaps_box(a, b, c, box(Vec3(0.6f, 0.6f, 0), Vec3(2, 2, 0))));
  EXPECT_TRUE(triangle_overlaps_box(a, b, c, box(Vec3(0.5f, 0.5f, 0), Vec3(2, 2, 0))));
  // Degenerate triangles: a segment crossing the box, a point inside and outside.
  EXPECT_TRUE(triangle_overlaps_box(Vec3(-1, 0.5f, 0.5f), Vec3(2, 0.5f, 0.5f),
                                    Vec3(0.5f, 0.5f, 0.5f), unit));
  EXPECT_TRUE(triangle_overlaps_box(Vec3(0.5f), Vec3(0.5f), Vec3(0.5f), unit));
  EXPECT_FALSE(triangle_overlaps_box(Vec3(1.5f), Vec3(1.5f), Vec3(1.5f), unit));
  // A segment passing the corner (1, 1) in z = 0.5 along x + y = 2.5: apart.
  EXPECT_FALSE(triangle_overlaps_box(Vec3(2.5f, 0, 0.5f), Vec3(0, 2.5f, 0.5f),
                                     Vec3(1.25f, 1.25f, 0.5f), unit));
}

// The separating-axis test against a dense sampling of the triangle: whatever
// sample lies in the box proves an overlap, and far from the box's surface a
// clear miss is a miss.
TEST(RangeQueryExact, TriangleBoxAgreesWithSampling) {
  Rng rng(9);
  int overlaps = 0, apart = 0;
  for (int i = 0; i < 3000; ++i) {
    const DVec3 a = 1.5 * rng.in_unit_ball(), b = 1.5 * rng.in_unit_ball(),
                c = 1.5 * rng.in_unit_ball();
    const Bounds3 bx(to_f(0.6 * rng.in_unit_ball()), to_f(0.6 * rng.in_unit_ball()));
    const bool sat = triangle_overlaps_box(to_f(a), to_f(b), to_f(c), bx);
    // Closest sampled distance of the triangle to the box.
    double nearest = 1e30;
    const int n = 60;
    for (int u = 0; u <= n; ++u)
      for (int v = 0; u + v <= n; ++v) {
        const DVec3 p = a + (b - a) * (double(u) / n) + (c - a) * (double(v) / n);
        nearest = std::min(nearest, double(point_box_distance(to_f(p), bx)));
      }
    if (nearest == 0.0) {
      EXPECT_TRUE(sat) << "case " << i;
      ++overlaps;
    } else if (nearest > 0.1) {  // farther than the sampling's resolution
      EXPECT_FALSE(sat) << "case " << i;
      ++apart;
    }
  }
  EXPECT_GT(overlaps, 300);
  EXPECT_GT(apart, 300);
}

TEST(RangeQueryExact, SphereAndPlaneAgainstBoxes) {
  const Bounds3 unit = box(Vec3(0), Vec3(1));
  EXPECT_TRUE(sphere_overlaps_box(Vec3(2, 0.5f, 0.5f), 1.0f, unit));  // touches a face
  EXPECT_FALSE(sphere_overlaps_box(Vec3(2, 0.5f, 0.5f), next_float_down(1.0f), unit));
  EXPECT_TRUE(sphere_overlaps_box(Vec3(4, 5, 0.5f), 5.0f, unit));  // touches the edge x = y = 1
  EXPECT_FALSE(sphere_overlaps_box(Vec3(4, 5, 0.5f), next_float_down(5.0f), unit));
  EXPECT_TRUE(sphere_overlaps_box(Vec3(0.5f), 0.01f, unit));  // inside
  EXPECT_TRUE(sphere_overlaps_box(Vec3(0.5f), 10.0f, unit));  // around
  EXPECT_TRUE(sphere_overlaps_box(Vec3(1.5f, 0.5f, 0.5f), 0.5f, Bounds3(Vec3(1, 0.5f, 0.5f))));
  EXPECT_TRUE(plane_overlaps_box(Vec3(0), Vec3(0, 1, 0), box(Vec3(-1, 0, -1), Vec3(1))));
  EXPECT_FALSE(plane_overlaps_box(Vec3(0), Vec3(0, 1, 0), box(Vec3(-1, 0.5f, -1), Vec3(1))));
  EXPECT_TRUE(plane_overlaps_box(Vec3(0), Vec3(0, 1, 0), Bounds3(Vec3(3, 0, 3))));
  EXPECT_TRUE(plane_overlaps_box(Vec3(0), Vec3(0, 1, 0), box(Vec3(-1, -2, -1), Vec3(1, 2, 1))));
}

TEST(RangeQueryExact, BadRangesAreRefused) {
  EXPECT_THROW(BoxRange(box(Vec3(1, 0, 0), Vec3(0, 1, 1))), std::invalid_argument);
  EXPECT_THROW(BoxRange(box(Vec3(0), Vec3(NAN, 1, 1))), std::invalid_argument);
  EXPECT_THROW(BoxRange(box(Vec3(-kInfinity), Vec3(1))), std::invalid_argument);
  EXPECT_NO_THROW(BoxRange(Bounds3(Vec3(2))));
  EXPECT_THROW(SphereRange(Vec3(0), -1.0f), std::invalid_argument);
  EXPECT_THROW(SphereRange(Vec3(0), NAN), std::invalid_argument);
  EXPECT_THROW(SphereRange(Vec3(0), kInfinity), std::invalid_argument);
  EXPECT_THROW(SphereRange(Vec3(NAN, 0, 0), 1.0f), std::invalid_argument);
  EXPECT_NO_THROW(SphereRange(Vec3(0), 0.0f));
  EXPECT_THROW(KnnRange(Vec3(0), 0), std::invalid_argument);
  EXPECT_THROW(KnnRange(Vec3(0, kInfinity, 0), 1), std::invalid_argument);
  try {
    BoxRange(box(Vec3(0, 2, 0), Vec3(1, 1, 1)));
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "the minimum corner (0, 2, 0) exceeds the maximum corner (1, 1, 1) in y");
  }
}

TEST(RangeQueryExact, KnnRangeShrinksAndKeepsTheBest) {
  KnnRange r(Vec3(0), 3);
  EXPECT_EQ(r.radius(), kInfinity);
  EXPECT_TRUE(r.offer({10, -1, 5.0f}));
  EXPECT_TRUE(r.offer({11, -1, 2.0f}));
  EXPECT_EQ(r.radius(), kInfinity);
  EXPECT_TRUE(r.offer({12, -1, 4.0f}));
  EXPECT_EQ(r.radius(), 5.0f);
  EXPECT_FALSE(r.offer({13, -1, 6.0f}));
  EXPECT_TRUE(r.offer({~0u, 0, 4.0f}));  // a plane at 4 pushes out the 5
  EXPECT_EQ(r.radius(), 4.0f);
  EXPECT_TRUE(r.offer({9, -1, 4.0f}));    // prim 9 at 4 beats the plane at 4
  EXPECT_FALSE(r.offer({14, -1, 4.0f}));  // prim 14 at 4 does not beat prim 12
  EXPECT_FALSE(r.overlaps(Bounds3(Vec3(4.5f, 0, 0))));
  EXPECT_TRUE(r.overlaps(Bounds3(Vec3(4, 0, 0))));
  const std::vector<RangeHit> best = r.take_sorted();
  ASSERT_EQ(best.size(), 3u);
  EXPECT_EQ(best[0], (RangeHit{11, -1, 2.0f}));
  EXPECT_EQ(best[1], (RangeHit{9, -1, 4.0f}));
  EXPECT_EQ(best[2], (RangeHit{12, -1, 4.0f}));
  // The range's bounds contain it, rounded outward.
  const SphereRange s(Vec3(0.1f, 0.2f, 0.3f), 0.7f);
  const Bounds3 sb = s.bounds();
  EXPECT_LE(double(sb.lo.x), 0.1 - 0.7);
  EXPECT_GE(double(sb.hi.z), double(0.3f) + double(0.7f));
}

// ---------------------------------------------------------------------------
// Brute force: a loop over the scene's objects (triangles mesh by mesh, then
// spheres: global primitive indices; then planes), with the exact tests.

std::vector<RangeHit> brute_box(const Scene& s, const Bounds3& bx) {
  std::vector<RangeHit> out;
  uint32_t id = 0;
  for (const TriangleMesh& m : s.meshes)
    for (const glm::uvec3& t : m.triangles) {
      if (triangle_overlaps_box(m.positions[t.x], m.positions[t.y], m.positions[t.z], bx))
        out.push_back({id, -1, 0.0f});
      ++id;
    }
  for (const Sphere& sp : s.spheres) {
    if (sphere_overlaps_box(sp.center, sp.radius, bx)) out.push_back({id, -1, 0.0f});
    ++id;
  }
  const std::vector<PlaneRecord>& planes = s.accel().plane_records();  // unit normals
  for (size_t k = 0; k < planes.size(); ++k)
    if (plane_overlaps_box(planes[k].point, planes[k].normal, bx))
      out.push_back({~0u, int(k), 0.0f});
  return out;
}

// Every object with its distance from p, nearest first.
std::vector<RangeHit> brute_distances(const Scene& s, const Vec3& p) {
  std::vector<RangeHit> out;
  uint32_t id = 0;
  for (const TriangleMesh& m : s.meshes)
    for (const glm::uvec3& t : m.triangles)
      out.push_back(
          {id++, -1,
           point_triangle_distance(p, m.positions[t.x], m.positions[t.y], m.positions[t.z])});
  for (const Sphere& sp : s.spheres)
    out.push_back({id++, -1, point_sphere_distance(p, sp.center, sp.radius)});
  const std::vector<PlaneRecord>& planes = s.accel().plane_records();  // unit normals
  for (size_t k = 0; k < planes.size(); ++k)
    out.push_back({~0u, int(k), point_plane_distance(p, planes[k].point, planes[k].normal)});
  std::sort(out.begin(), out.end(), nearer);
  return out;
}

std::vector<RangeHit> brute_sphere(const Scene& s, const Vec3& c, float r) {
  std::vector<RangeHit> all = brute_distances(s, c);
  all.erase(std::find_if(all.begin(), all.end(), [r](const RangeHit& h) { return h.distance > r; }),
            all.end());
  return all;
}

std::vector<RangeHit> brute_knn(const Scene& s, const Vec3& p, uint32_t k) {
  std::vector<RangeHit> all = brute_distances(s, p);
  if (all.size() > k) all.resize(k);
  return all;
}

struct Structure {
  std::string name;
  AccelConfig config;
};

std::vector<Structure> structures() {
  std::vector<Structure> out;
  auto add = [&](const char* name, AccelKind kind, KdSplitRule rule = KdSplitRule::Sah) {
    AccelConfig c;
    c.kind = kind;
    c.kdtree.rule = rule;
    out.push_back({name, c});
  };
  add("bvh", AccelKind::Bvh);
  add("bvh2", AccelKind::BinaryBvh);
  add("kdtree", AccelKind::KdTree);
  add("kdtree-median", AccelKind::KdTree, KdSplitRule::Median);
  add("grid", AccelKind::Grid);
  add("octree", AccelKind::Octree);
  add("spheres", AccelKind::Spheres);
  add("none", AccelKind::None);
  for (AccelKind kind : {AccelKind::KdTree, AccelKind::Grid, AccelKind::Octree}) {
    AccelConfig c;  // smallest-cell: loose cells, at the default loose factor
    c.kind = kind;
    c.storage = PrimStorage::SmallestCell;
    out.push_back({std::string(to_string(kind)) + "-loose", c});
  }
  for (PrimStorage st : kPrimStorages) {  // the BSP tree takes all three
    AccelConfig c;
    c.kind = AccelKind::Bsp;
    c.storage = st;
    out.push_back({std::string("bsp-") + to_string(st), c});
  }
  return out;
}

struct Queries {
  std::vector<Bounds3> boxes;
  std::vector<std::pair<Vec3, float>> spheres;
  std::vector<std::pair<Vec3, uint32_t>> knn;
};

// Checks the walk contract as the walk goes: a node is entered only after its
// box was tested and overlapped (the root's included), and at most once; what
// overlapped is entered or culled, once; each primitive is tested at most
// once (the kD-tree's mailbox).
struct ContractObserver : TraversalHooks {
  static constexpr bool kActive = true;
  enum : uint8_t { kNone, kOverlapped, kEntered, kCulled };
  std::vector<uint8_t> node_state, prim_tests;
  uint32_t overlaps = 0, entered = 0, culls = 0;
  /// A box tested but never entered: the uniform grid's own box, which
  /// leads to its cells (it is no node of a hierarchy).
  uint32_t box_only = ~0u;
  static uint8_t& at(std::vector<uint8_t>& v, uint32_t i) {
    if (i >= v.size()) v.resize(size_t(i) * 2 + 16, 0);
    return v[i];
  }
  void on_box_test(uint32_t node, bool hit) {
    uint8_t& st = at(node_state, node);
    EXPECT_EQ(st, kNone) << "node " << node << " tested twice";
    if (hit && node == box_only)
      st = kEntered;
    else if (hit)
      st = kOverlapped, ++overlaps;
  }
  void on_node(uint32_t node) {
    uint8_t& st = at(node_state, node);
    EXPECT_EQ(st, kOverlapped) << "node " << node << " entered without an overlapping box";
    st = kEntered;
    ++entered;
  }
  void on_cull(uint32_t node) {
    uint8_t& st = at(node_state, node);
    EXPECT_EQ(st, kOverlapped) << "node " << node << " culled but not pushed";
    st = kCulled;
    ++culls;
  }
  void on_prim_test(uint32_t prim) {
    EXPECT_EQ(at(prim_tests, prim)++, 0) << "prim " << prim << " tested twice";
  }
  void finish(const char* what) const {
    EXPECT_EQ(entered + culls, overlaps) << what << ": overlapped nodes neither entered nor culled";
  }
};

// Every structure returns exactly the brute-force result for every query;
// observed queries equal plain ones and keep the walk contract.
void expect_brute_force(Scene scene, const Queries& q, const char* what) {
  // The brute force reads the planes' unit normals from the committed
  // aggregate (commit() keeps the scene's normals as given, and normalizes
  // them the same way on every commit).
  scene.commit();
  std::vector<std::vector<RangeHit>> box_ref, sphere_ref, knn_ref;
  size_t found = 0;
  for (const Bounds3& b : q.boxes) found += box_ref.emplace_back(brute_box(scene, b)).size();
  for (const auto& [c, r] : q.spheres)
    found += sphere_ref.emplace_back(brute_sphere(scene, c, r)).size();
  for (const auto& [p, k] : q.knn) knn_ref.push_back(brute_knn(scene, p, k));
  std::printf("%s: %zu boxes, %zu spheres, %zu k-nearest; %zu objects found by box and sphere\n",
              what, q.boxes.size(), q.spheres.size(), q.knn.size(), found);
  EXPECT_GT(found, q.boxes.size() + q.spheres.size()) << what;
  for (const Structure& st : structures()) {
    scene.commit(st.config);
    const Aggregate& a = scene.accel();
    ASSERT_EQ(a.walks_structure(), st.config.kind != AccelKind::None) << what;
    for (size_t i = 0; i < q.boxes.size(); ++i) {
      ContractObserver obs;
      if (a.kind() == AccelKind::Grid) obs.box_only = a.structure_as<UniformGrid>().box_id();
      const std::vector<RangeHit> got = a.query_box(q.boxes[i], obs);
      obs.finish(what);
      ASSERT_EQ(got, box_ref[i]) << what << ", " << st.name << ", box " << i;
      ASSERT_EQ(a.query_box(q.boxes[i]), got);
    }
    for (size_t i = 0; i < q.spheres.size(); ++i) {
      ContractObserver obs;
      if (a.kind() == AccelKind::Grid) obs.box_only = a.structure_as<UniformGrid>().box_id();
      const auto& [c, r] = q.spheres[i];
      const std::vector<RangeHit> got = a.query_sphere(c, r, obs);
      obs.finish(what);
      EXPECT_EQ(obs.culls, 0u) << "a sphere range does not shrink";
      ASSERT_EQ(got, sphere_ref[i])
          << what << ", " << st.name << ", sphere " << i << " radius " << r;
      ASSERT_EQ(a.query_sphere(c, r), got);
    }
    for (size_t i = 0; i < q.knn.size(); ++i) {
      ContractObserver obs;
      if (a.kind() == AccelKind::Grid) obs.box_only = a.structure_as<UniformGrid>().box_id();
      const auto& [p, k] = q.knn[i];
      const std::vector<RangeHit> got = a.nearest(p, k, obs);
      obs.finish(what);
      ASSERT_EQ(got, knn_ref[i]) << what << ", " << st.name << ", knn " << i << " k " << k;
      ASSERT_EQ(a.nearest(p, k), got);
    }
  }
}

Vec3 random_point(Rng& rng, const Bounds3& world) {
  const DVec3 e = to_d(world.extent());
  return to_f(to_d(world.lo) - 0.1 * e +
              1.2 * e * DVec3(rng.uniform(), rng.uniform(), rng.uniform()));
}

// Random, touching, zero-size and huge ranges about a scene: boxes of sizes
// over four decades, points and segments, flat boxes, boxes from a vertex,
// one box holding everything; spheres of random radius, of radius 0 at
// vertices, inside spheres and at random points, and one holding everything;
// k nearest for k = 1, a few, n, more than n, at random points, at vertices
// and at sphere centers.
Queries make_queries(Rng& rng, const Scene& scene, int n) {
  Bounds3 world;
  std::vector<Vec3> vertices;
  for (const TriangleMesh& m : scene.meshes)
    for (const Vec3& p : m.positions) {
      world.extend(p);
      vertices.push_back(p);
    }
  for (const Sphere& s : scene.spheres) {
    world.extend(s.center - Vec3(s.radius));
    world.extend(s.center + Vec3(s.radius));
  }
  const float size = max_component(world.extent());
  auto vertex = [&] { return vertices[size_t(rng.integer(0, int(vertices.size()) - 1))]; };
  Queries q;
  for (int i = 0; i < n; ++i) {
    const Vec3 c = random_point(rng, world);
    const DVec3 h = size * rng.log_uniform(1e-4, 0.3) *
                    DVec3(rng.uniform(0.1, 1), rng.uniform(0.1, 1), rng.uniform(0.1, 1));
    q.boxes.push_back(Bounds3(to_f(to_d(c) - h), to_f(to_d(c) + h)));
    q.boxes.push_back(Bounds3(random_point(rng, world)));  // a point
    Bounds3 flat(to_f(to_d(c) - h), to_f(to_d(c) + h));
    const int axis = rng.integer(0, 2);
    flat.lo[axis] = flat.hi[axis];
    q.boxes.push_back(flat);
    const Vec3 v = vertex();
    q.boxes.push_back(Bounds3(v));                          // a vertex: its triangles touch it
    q.boxes.push_back(Bounds3(v, v + Vec3(size * 0.01f)));  // a box from a vertex
    Bounds3 seg(v);
    seg.hi[axis] += size * 0.05f;
    q.boxes.push_back(seg);  // a segment
    q.spheres.push_back({c, float(size * rng.log_uniform(1e-4, 0.3))});
    q.spheres.push_back({vertex(), 0.0f});
    q.spheres.push_back({random_point(rng, world), 0.0f});
    q.knn.push_back({random_point(rng, world), 1});
    q.knn.push_back({random_point(rng, world), uint32_t(rng.integer(2, 40))});
    q.knn.push_back({vertex(), uint32_t(rng.integer(1, 8))});
  }
  for (const Sphere& s : scene.spheres) {
    q.spheres.push_back({s.center, 0.0f});  // inside: distance 0
    q.knn.push_back({s.center, 3});
    q.boxes.push_back(Bounds3(s.center));
  }
  const float huge = 1e30f;
  q.boxes.push_back(box(Vec3(-huge), Vec3(huge)));
  q.spheres.push_back({world.center(), huge});
  uint32_t objects = uint32_t(scene.spheres.size() + scene.planes.size());
  for (const TriangleMesh& m : scene.meshes) objects += uint32_t(m.triangles.size());
  q.knn.push_back({world.center(), objects});
  q.knn.push_back({random_point(rng, world), objects + 7});
  q.knn.push_back({random_point(rng, world), std::numeric_limits<uint32_t>::max()});
  return q;
}

TEST(RangeQuery, RandomScenesMatchBruteForce) {
  for (uint32_t seed : {51u, 52u}) {
    Rng rng(seed);
    Scene scene = rstest::soup_scene(rng);
    scene.meshes.push_back(rstest::unit_cube(Vec3(7, 0, 0)));
    const Queries q = make_queries(rng, scene, 40);
    expect_brute_force(std::move(scene), q, "soup scene");
  }
}

// Degenerate input: every object at one point (spheres of one center,
// triangles collapsed to it, zero-area slivers through it), plus a plane
// through it.
TEST(RangeQuery, DegenerateScenesMatchBruteForce) {
  Rng rng(53);
  Scene scene;
  const Vec3 o(1, 2, 3);
  TriangleMesh m;
  m.name = "collapsed";
  for (uint32_t i = 0; i < 40; ++i) {
    m.positions.push_back(o);
    m.positions.push_back(i % 2 ? o : o + to_f(rng.unit_vector()));
    m.positions.push_back(i % 2 ? o : 2.0f * m.positions.back() - o);  // a segment through o
    m.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  scene.meshes.push_back(m);
  for (int i = 0; i < 20; ++i) scene.spheres.push_back(Sphere{"s", o, 0.5f + 0.01f * float(i), 0});
  scene.planes.push_back(Plane{"p", o, Vec3(1, 1, 0), 0});
  Queries q = make_queries(rng, scene, 10);
  q.knn.push_back({o, 5});  // everything at distance 0
  q.spheres.push_back({o, 0.0f});
  q.boxes.push_back(Bounds3(o));
  expect_brute_force(std::move(scene), q, "objects at one point");
}

// Exact ties: six equal spheres at distance 2 along the axes and a plane at
// distance 1 from the origin all lie exactly 1 from it; results order them by
// index, primitives before planes, in every structure.
TEST(RangeQuery, ExactTiesResolvedByIndex) {
  Scene scene;
  const Vec3 centers[6] = {{2, 0, 0}, {-2, 0, 0}, {0, 2, 0}, {0, -2, 0}, {0, 0, 2}, {0, 0, -2}};
  for (const Vec3& c : centers) scene.spheres.push_back(Sphere{"s", c, 1.0f, 0});
  scene.spheres.push_back(Sphere{"far", Vec3(5, 5, 5), 1.0f, 0});
  scene.planes.push_back(Plane{"p", Vec3(0, 0, -1), Vec3(0, 0, 1), 0});
  for (const Structure& st : structures()) {
    scene.commit(st.config);
    const std::vector<RangeHit> k1 = scene.accel().nearest(Vec3(0), 1);
    ASSERT_EQ(k1.size(), 1u);
    EXPECT_EQ(k1[0], (RangeHit{0, -1, 1.0f})) << st.name;
    const std::vector<RangeHit> k7 = scene.accel().nearest(Vec3(0), 7);
    ASSERT_EQ(k7.size(), 7u);
    for (uint32_t i = 0; i < 6; ++i) EXPECT_EQ(k7[i], (RangeHit{i, -1, 1.0f})) << st.name;
    EXPECT_EQ(k7[6], (RangeHit{~0u, 0, 1.0f})) << st.name;
    EXPECT_EQ(scene.accel().query_sphere(Vec3(0), 1.0f), k7) << st.name;
    EXPECT_EQ(scene.accel().query_sphere(Vec3(0), next_float_down(1.0f)).size(), 0u);
    // Every sphere's box touches the box [-1, 1]^3; the plane z = -1 too.
    const std::vector<RangeHit> in_box = scene.accel().query_box(box(Vec3(-1), Vec3(1)));
    ASSERT_EQ(in_box.size(), 7u) << st.name;
    EXPECT_EQ(in_box[5].prim, 5u);
    EXPECT_EQ(in_box[6].plane, 0);
  }
}

// A scene of at most Aggregate::kBruteForceMax primitives skips the structure;
// a scene of planes only has no structure at all.
TEST(RangeQuery, TinyScenes) {
  Scene scene;
  scene.spheres.push_back(Sphere{"a", Vec3(0), 1.0f, 0});
  scene.spheres.push_back(Sphere{"b", Vec3(3, 0, 0), 1.0f, 0});
  scene.planes.push_back(Plane{"floor", Vec3(0, -1, 0), Vec3(0, 2, 0), 0});
  scene.commit();
  ASSERT_FALSE(scene.accel().walks_structure());
  EXPECT_EQ(scene.accel().nearest(Vec3(3, 0, 0), 10),
            (std::vector<RangeHit>{{1, -1, 0.0f}, {~0u, 0, 1.0f}, {0, -1, 2.0f}}));
  EXPECT_EQ(scene.accel().query_box(Bounds3(Vec3(1, 0, 0))),
            (std::vector<RangeHit>{{0, -1, 0.0f}}));
  scene.spheres.clear();
  scene.commit();
  EXPECT_EQ(scene.accel().nearest(Vec3(3, 0, 0), 10), (std::vector<RangeHit>{{~0u, 0, 1.0f}}));
  EXPECT_TRUE(scene.accel().query_sphere(Vec3(0, 5, 0), 1.0f).empty());
}

// The bunny scene (69,666 triangles). Under sanitizers (stress_scale() < 1:
// builds and walks 10-50x slower) every (1 / scale)-th triangle of it, so
// that all structures still build and answer queries on a real mesh within
// the test's time limit (rstest::stress_stride()); the optimised run checks
// the whole bunny.

Scene bunny_scene() {
  const std::filesystem::path file =
      std::filesystem::path(RAYSCOPE_SOURCE_DIR) / "data/scenes/bunny.json";
  Scene scene = load_scene(file.string(), rayscope_vtk::load_mesh).scene;
  if (const size_t stride = rstest::stress_stride(); stride > 1) {
    std::vector<glm::uvec3>& tris = scene.meshes.at(0).triangles;
    std::vector<glm::uvec3> kept;
    for (size_t i = 0; i < tris.size(); i += stride) kept.push_back(tris[i]);
    tris = std::move(kept);
  }
  return scene;
}

TEST(RangeQuery, BunnyMatchesBruteForce) {
  Scene scene = bunny_scene();
  Rng rng(54);
  const Queries q = make_queries(rng, scene, 8);
  expect_brute_force(std::move(scene), q, "bunny scene");
}

// The walks prune: a small box on the bunny enters a small part of the tree;
// k = 1 enters fewer nodes than a sphere holding everything (which enters
// them all), and culls what it pushed before its radius shrank.
TEST(RangeQuery, WalksPruneOnTheBunny) {
  // How much a walk prunes is a property of the whole bunny's trees (a
  // thinned bunny's are shallower); under sanitizers the walks' memory safety
  // and contract on the bunny are checked by BunnyMatchesBruteForce.
  if (rstest::stress_stride() > 1)
    GTEST_SKIP() << "pruning is measured on the whole bunny (optimised run)";
  Scene scene = bunny_scene();
  const TriangleMesh& bunny = scene.meshes.at(0);
  const Vec3 v = bunny.positions[bunny.triangles[1000].x];
  const float s = 0.01f;
  for (const Structure& st : structures()) {
    // Hierarchies only: the grid is flat (its range walk visits the cells in
    // the range's bounds, which for k nearest start unbounded).
    if (st.config.kind == AccelKind::None || st.config.kind == AccelKind::Grid) continue;
    scene.commit(st.config);
    const Aggregate& a = scene.accel();
    const uint32_t nodes = uint32_t(make_accel_view(a).nodes.size());
    PixelCost small, knn, all;
    StatsRecorder::Observer o_small(&small), o_knn(&knn), o_all(&all);
    const std::vector<RangeHit> in_box = a.query_box(Bounds3(v - Vec3(s), v + Vec3(s)), o_small);
    EXPECT_GE(in_box.size(), 3u) << st.name;
    EXPECT_LT(small.nodes, nodes / 100) << st.name;
    // The BSP tree's every-cell and smallest-cell storage hold whole
    // triangles that straddle planes far from their cell (every-cell: 1,058
    // tested for this box in leaves at the depth limit; smallest-cell: the
    // node lists near the root, 2,398); only split storage prunes them (113).
    const bool whole_straddlers =
        st.config.kind == AccelKind::Bsp && st.config.storage != PrimStorage::Split;
    EXPECT_LT(small.prims, a.records().size() / (whole_straddlers ? 20 : 100)) << st.name;
    EXPECT_EQ(small.culled, 0u);
    const std::vector<RangeHit> k1 = a.nearest(v + Vec3(0, 0.05f, 0), 1, o_knn);
    const std::vector<RangeHit> everything = a.query_sphere(v, 1e6f, o_all);
    EXPECT_EQ(everything.size(), a.object_count());
    EXPECT_EQ(all.nodes, nodes) << st.name;
    ASSERT_EQ(k1.size(), 1u);
    EXPECT_LT(knn.nodes * 20, all.nodes) << st.name;
    EXPECT_LT(knn.prims * (whole_straddlers ? 10 : 20), all.prims) << st.name;
    // Both child boxes (cells) of every inner node entered are tested: with
    // every node entered, the root's box and every other box once.
    EXPECT_EQ(all.boxes, nodes) << st.name;
    std::printf(
        "%s (%u nodes): box 2x%g: %u nodes, %u prims; k = 1: %u nodes, %u prims, %u culled; "
        "everything: %u nodes, %u prims\n",
        st.name.c_str(), nodes, double(s), small.nodes, small.prims, knn.nodes, knn.prims,
        knn.culled, all.nodes, all.prims);
  }
}

// A shrinking range culls pushed nodes: over many k-nearest queries on the
// soup scene, some pushed node is skipped when popped.
TEST(RangeQuery, ShrinkingRangeCulls) {
  Rng rng(55);
  Scene scene = rstest::soup_scene(rng);
  for (const Structure& st : structures()) {
    if (st.config.kind == AccelKind::None || st.config.kind == AccelKind::Grid) continue;  // flat
    scene.commit(st.config);
    PixelCost cost;
    StatsRecorder::Observer obs(&cost);
    for (int i = 0; i < 200; ++i)
      scene.accel().nearest(to_f(DVec3(rng.uniform(-6, 6), rng.uniform(-6, 6), rng.uniform(-6, 6))),
                            3, obs);
    EXPECT_GT(cost.culled, 0u) << st.name;
  }
}

}  // namespace
