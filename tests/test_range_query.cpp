// Range queries (range_query.h): the exact primitive tests against
// hand-computed cases and sampling, bad ranges, the k-nearest range, and tiny
// scenes that skip the structure. The queries through every structure (==
// brute force on random, degenerate and mesh scenes, ties, the walk contract,
// pruning) are test_accel_conformance's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "accel_test_util.h"
#include "rayscope/range_query.h"

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
// Through the aggregate (box, sphere and k-nearest queries of every
// structure == brute force, ties, the walk contract, pruning and culling:
// test_accel_conformance).

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

}  // namespace
