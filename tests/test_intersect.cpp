// Ray-primitive intersection routines (intersect.h) against double-precision
// analytic answers.
//
// Tolerances are written in units of eps = 2^-24 (kMachineEpsilon, the relative
// rounding error of one float operation) times the magnitudes that enter the
// computation, following the usual forward error analysis (gamma(n) ~ n eps
// for n chained operations):
//  - translating a point to the ray origin costs eps * (|p| + |o|) absolutely;
//  - everything after that is a handful of products and sums of magnitude
//    <= the size of the configuration, so the computed hit point is off by
//    K eps * (scale) where K is a small constant (a "few gamma(n)");
//  - an error e in position becomes an error e / |cos| along a ray that meets
//    the surface at angle cos to the normal (grazing rays).
// The constants K below are the bounds from the analysis rounded up to a power
// of two; measured errors are printed so that a reader can see the margin.
#include <gtest/gtest.h>

#include <cstdio>

#include "rayscope/intersect.h"
#include "rayscope/intersect_capsule.h"
#include "rayscope/textbook_intersect.h"
#include "test_util.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::naive_sphere;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

constexpr double kEps = double(kMachineEpsilon);  // 2^-24

double max_abs3(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return std::max(std::max(rstest::max_abs(to_d(a)), rstest::max_abs(to_d(b))),
                  std::max(rstest::max_abs(to_d(c)), rstest::max_abs(to_d(d))));
}

// Distance between the line of the ray and the line through a and b (skew-line
// distance, in double): how far the ray passes from a triangle edge, measured
// across the ray, which is what the watertight test resolves.
double line_line_distance(const DVec3& o, const DVec3& d, const DVec3& a, const DVec3& b) {
  DVec3 n = glm::cross(d, b - a);
  double l = glm::length(n);
  if (l == 0.0) return 0.0;
  return std::abs(glm::dot(a - o, n)) / l;
}

// Random non-degenerate triangle of size ~L around c.
void random_triangle(Rng& rng, const DVec3& c, double L, Vec3& p0, Vec3& p1, Vec3& p2) {
  for (;;) {
    p0 = to_f(c + L * rng.in_unit_ball());
    p1 = to_f(c + L * rng.in_unit_ball());
    p2 = to_f(c + L * rng.in_unit_ball());
    DVec3 n = glm::cross(to_d(p1) - to_d(p0), to_d(p2) - to_d(p0));
    // Reject slivers: area at least 5% of L^2 and every altitude >= 0.1 L.
    double area2 = glm::length(n);
    double e = std::max({glm::length(to_d(p1) - to_d(p0)), glm::length(to_d(p2) - to_d(p1)),
                         glm::length(to_d(p0) - to_d(p2))});
    if (area2 > 0.1 * L * L && area2 / e > 0.1 * L) return;
  }
}

// ---------------------------------------------------------------------------
// Triangles

struct TriangleCase {
  Vec3 p0, p1, p2, o, d;
  double L, D, cosine;
};

// A triangle, and a ray from distance D*L at |cos| in [cos_lo, cos_hi] to the
// normal aimed at a random interior point (barycentrics >= 0.05), or with
// `outside` at a point 0.05..0.5 (in barycentric units) beyond an edge.
TriangleCase make_triangle_case(Rng& rng, double cos_lo, double cos_hi, double extent = 100,
                                double L_lo = 0.01, double D_hi = 20, bool outside = false) {
  TriangleCase k;
  DVec3 c(rng.uniform(-extent, extent), rng.uniform(-extent, extent), rng.uniform(-extent, extent));
  k.L = rng.log_uniform(L_lo, 10.0);
  random_triangle(rng, c, k.L, k.p0, k.p1, k.p2);
  DVec3 a = to_d(k.p0), b = to_d(k.p1), cc = to_d(k.p2);
  DVec3 n = glm::normalize(glm::cross(b - a, cc - a));
  double u, v;
  do {
    u = rng.uniform(0.05, 0.9);
    v = rng.uniform(0.05, 0.9);
  } while (u + v > 0.95);
  if (outside) u = -rng.uniform(0.05, 0.5);  // beyond edge p2-p0
  DVec3 q = (1.0 - u - v) * a + u * b + v * cc;
  // Direction at the requested angle: mix the normal with an in-plane vector.
  double cs = rng.log_uniform(cos_lo, cos_hi);
  DVec3 t1 = glm::normalize(b - a), t2 = glm::cross(n, t1);
  double phi = rng.uniform(0, 2 * kPi);
  DVec3 inplane = std::cos(phi) * t1 + std::sin(phi) * t2;
  DVec3 w = cs * n + std::sqrt(1 - cs * cs) * inplane;  // from q toward the origin
  if (rng.coin()) w = -w;
  k.D = k.L * rng.log_uniform(0.5, D_hi);
  k.o = to_f(q + k.D * w);
  // Direction of random length (t scales accordingly).
  k.d = to_f((q - to_d(k.o)) * rng.log_uniform(0.01, 100.0));
  k.cosine = std::abs(glm::dot(glm::normalize(to_d(k.d)), n));
  return k;
}

// Smallest skew-line distance from the ray to the three edge lines.
double edge_margin(const TriangleCase& k) {
  DVec3 o = to_d(k.o), d = to_d(k.d), a = to_d(k.p0), b = to_d(k.p1), c = to_d(k.p2);
  return std::min({line_line_distance(o, d, a, b), line_line_distance(o, d, b, c),
                   line_line_distance(o, d, c, a)});
}

// Band within which the watertight test may classify a ray either way: the
// sheared 2D coordinates carry an absolute error of about gamma(5) times the
// magnitudes involved (translation eps (|p|+|o|), shear gamma(5) (|x|+|z|)),
// and the edge functions add 2 (gamma(2) + 2 gamma(5)) ~ 24 eps relative.
// 64 eps * (scale) covers that with a factor ~2.
double classification_band(const TriangleCase& k) {
  double S = max_abs3(k.p0, k.p1, k.p2, k.o);
  return 64.0 * kEps * (S + k.D + k.L);
}

TEST(Triangle, RandomHitsMatchDoubleReference) {
  Rng rng(1234);
  const int kCases = 20000;
  double worst_t = 0, worst_p = 0, worst_err_ratio = 0;
  int checked = 0;
  for (int i = 0; i < kCases; ++i) {
    TriangleCase k = make_triangle_case(rng, 0.1, 1.0);
    Ray ray{k.o, k.d, kInfinity};
    rstest::RefTriHit ref;
    ASSERT_TRUE(rstest::ref_ray_plane_of_triangle(to_d(k.o), to_d(k.d), to_d(k.p0), to_d(k.p1),
                                                  to_d(k.p2), ref));
    ASSERT_GT(ref.min_bary, 0.0);
    TriangleHit h;
    ASSERT_TRUE(intersect_triangle(ray, k.p0, k.p1, k.p2, h)) << "case " << i;
    ++checked;
    // Error along the ray, in world units, relative to the scale of the
    // configuration and the angle: 16 eps is ~ gamma(5) (shear) + gamma(3)
    // (edge functions) + gamma(3) (t) + translation, with a margin.
    double S = max_abs3(k.p0, k.p1, k.p2, k.o);
    double dlen = glm::length(to_d(k.d));
    double tol_dist = 16.0 * kEps * (S + k.D + k.L) / k.cosine;
    double err_t = std::abs(double(h.t) - ref.t) * dlen;
    EXPECT_LE(err_t, tol_dist) << "case " << i << " t=" << h.t << " ref=" << ref.t;
    worst_t = std::max(worst_t, err_t / (kEps * (S + k.D + k.L) / k.cosine));

    // Barycentrics sum to 1 and agree with the reference.
    EXPECT_NEAR(double(h.b0) + h.b1 + h.b2, 1.0, 4 * kEps);
    // Barycentric error: position error / triangle size.
    double tol_b = 32.0 * kEps * (S + k.D + k.L) / (k.L * k.cosine);
    EXPECT_NEAR(h.b0, ref.b0, tol_b);
    EXPECT_NEAR(h.b1, ref.b1, tol_b);
    EXPECT_NEAR(h.b2, ref.b2, tol_b);

    // Hit point: close to the analytic ray-plane intersection...
    Vec3 perr;
    Vec3 p = triangle_point(h, k.p0, k.p1, k.p2, perr);
    DVec3 exact_hit = to_d(k.o) + ref.t * to_d(k.d);
    double err_p = rstest::max_abs(to_d(p) - exact_hit);
    EXPECT_LE(err_p, tol_dist) << "case " << i;
    worst_p = std::max(worst_p, err_p / (kEps * (S + k.D + k.L) / k.cosine));
    // ...and p_error bounds the error of the point the barycentrics describe
    // (the exact b0 p0 + b1 p1 + b2 p2 in double), per axis...
    DVec3 exact_bary =
        double(h.b0) * to_d(k.p0) + double(h.b1) * to_d(k.p1) + double(h.b2) * to_d(k.p2);
    EXPECT_TRUE(rstest::within(to_d(p), exact_bary, to_d(perr)))
        << "case " << i << " err=" << rstest::max_abs(to_d(p) - exact_bary)
        << " bound=" << rstest::max_abs(to_d(perr));
    // ...and the distance of p from the triangle's plane, which is what ray
    // spawning relies on, is within the bound projected on the normal.
    DVec3 n = glm::normalize(glm::cross(to_d(k.p1) - to_d(k.p0), to_d(k.p2) - to_d(k.p0)));
    double plane_dist = std::abs(glm::dot(to_d(p) - to_d(k.p0), n));
    double bound = glm::dot(glm::abs(n), to_d(perr));
    EXPECT_LE(plane_dist, bound) << "case " << i;
    if (bound > 0) worst_err_ratio = std::max(worst_err_ratio, plane_dist / bound);
  }
  EXPECT_EQ(checked, kCases);
  std::printf(
      "triangle: worst t error %.2f, point error %.2f (units of eps*scale/cos; "
      "limit 16); plane distance / bound %.3f\n",
      worst_t, worst_p, worst_err_ratio);
}

TEST(Triangle, GrazingHitsAndNearEdgeRays) {
  // Rays at |cos| down to 1e-4 from the surface normal, aimed at interior
  // points; whenever the ray passes farther than the classification band from
  // every edge line, hit/miss must equal the exact answer, and hits must have
  // the right t (error along the ray grows as 1/cos). Triangles near the
  // origin and rays from nearby, so that the band (64 eps * scale) stays below
  // the projected size of most of these thin-looking triangles.
  Rng rng(777);
  const int kCases = 20000;
  int decided = 0, hits = 0;
  for (int i = 0; i < kCases; ++i) {
    TriangleCase k = make_triangle_case(rng, 1e-4, 0.1, 1.0, 0.1, 5.0, i % 3 == 0);
    rstest::RefTriHit ref;
    ASSERT_TRUE(rstest::ref_ray_plane_of_triangle(to_d(k.o), to_d(k.d), to_d(k.p0), to_d(k.p1),
                                                  to_d(k.p2), ref));
    TriangleHit h;
    bool got = intersect_triangle(Ray{k.o, k.d, kInfinity}, k.p0, k.p1, k.p2, h);
    double margin = edge_margin(k);
    if (margin <= classification_band(k)) continue;  // either answer is correct
    ++decided;
    bool expect = ref.min_bary > 0 && ref.t > 0;
    ASSERT_EQ(got, expect) << "case " << i << " cos=" << k.cosine << " min_bary=" << ref.min_bary
                           << std::hexfloat << " p0=" << k.p0.x << "," << k.p0.y << "," << k.p0.z
                           << " p1=" << k.p1.x << "," << k.p1.y << "," << k.p1.z << " p2=" << k.p2.x
                           << "," << k.p2.y << "," << k.p2.z << " o=" << k.o.x << "," << k.o.y
                           << "," << k.o.z << " d=" << k.d.x << "," << k.d.y << "," << k.d.z
                           << std::defaultfloat << " t=" << ref.t
                           << " margin/band=" << margin / classification_band(k);
    if (!got) continue;
    ++hits;
    double S = max_abs3(k.p0, k.p1, k.p2, k.o);
    double tol_dist = 16.0 * kEps * (S + k.D + k.L) / k.cosine;
    EXPECT_LE(std::abs(double(h.t) - ref.t) * glm::length(to_d(k.d)), tol_dist) << "case " << i;
  }
  // The band must not swallow the test: most cases are decided.
  std::printf("grazing: %d of %d decided, %d hits\n", decided, kCases, hits);
  EXPECT_GT(decided, kCases * 3 / 4);
  EXPECT_GT(hits, kCases / 2);
  EXPECT_GT(decided - hits, kCases / 5);
}

TEST(Triangle, TinyDistantTrianglesAreHitWhereTheExactHitIsInside) {
  // Triangles of size 1 seen from 1e4 to 1e6 away (apparent size 1e-6 to
  // 1e-4 rad), rays at |cos| >= 0.3 aimed at the inner part of the triangle
  // (barycentrics >= 0.25). Float resolves the direction to ~1e-7 relative,
  // i.e. at most ~0.1 triangle sizes here, so the exact answer (checked in
  // double) is a hit for nearly all of them; the watertight test must report
  // it. Its float bound on t's error alone rejected 495 of these 4115
  // before the double-precision fallback (docs/accuracy.md). Rays whose exact
  // hit is within 0.15 (barycentric) of an edge are left out: at 1e6 the float
  // inside test itself resolves only ~0.06.
  Rng rng(2026);
  const int kCases = 5000;
  int exact_hits = 0, missed = 0;
  for (int i = 0; i < kCases; ++i) {
    Vec3 p0, p1, p2;
    random_triangle(rng, DVec3(0.0), 1.0, p0, p1, p2);
    DVec3 a = to_d(p0), b = to_d(p1), c = to_d(p2);
    DVec3 n = glm::normalize(glm::cross(b - a, c - a));
    double u = rng.uniform(0.25, 0.5), v = rng.uniform(0.25, 0.5);
    DVec3 q = (1.0 - u - v) * a + u * b + v * c;
    double cs = rng.uniform(0.3, 1.0), phi = rng.uniform(0, 2 * kPi);
    DVec3 t1 = glm::normalize(b - a), t2 = glm::cross(n, t1);
    DVec3 w = cs * n + std::sqrt(1 - cs * cs) * (std::cos(phi) * t1 + std::sin(phi) * t2);
    if (rng.coin()) w = -w;
    Vec3 o = to_f(q + rng.log_uniform(1e4, 1e6) * w);
    Vec3 d = to_f(glm::normalize(q - to_d(o)));
    rstest::RefTriHit ref;
    ASSERT_TRUE(rstest::ref_ray_plane_of_triangle(to_d(o), to_d(d), a, b, c, ref));
    if (!(ref.min_bary > 0.15 && ref.t > 0)) continue;  // float could not aim it well inside
    ++exact_hits;
    TriangleHit h;
    if (!intersect_triangle(Ray{o, d, kInfinity}, p0, p1, p2, h)) {
      ++missed;
      continue;
    }
    // The hit distance is as accurate as the exact t of the float ray allows.
    EXPECT_NEAR(double(h.t), ref.t, 8.0 * kEps * ref.t / cs) << "case " << i;
  }
  EXPECT_GT(exact_hits, kCases / 2);
  EXPECT_EQ(missed, 0) << "of " << exact_hits << " rays whose exact hit is inside";
}

TEST(Triangle, ResultDoesNotDependOnDirectionLength) {
  // Scaling the direction by a power of two scales every quantity of the
  // watertight test that depends on it exactly (sz, the scaled z, t and its
  // error bound), so hit/miss and barycentrics must be bitwise identical and t
  // must scale exactly. A ray's direction need not be unit length (ray.h);
  // spawn_ray_to makes it as long as the distance to the light.
  Rng rng(606);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    TriangleCase k = make_triangle_case(rng, i % 2 ? 1e-4 : 0.1, i % 2 ? 0.1 : 1.0);
    TriangleHit h0;
    bool got0 = intersect_triangle(Ray{k.o, k.d, kInfinity}, k.p0, k.p1, k.p2, h0);
    hits += got0;
    for (int e : {-20, -10, -4, -1, 1, 4, 10, 20}) {
      Vec3 d = k.d * std::ldexp(1.0f, e);
      TriangleHit h;
      bool got = intersect_triangle(Ray{k.o, d, kInfinity}, k.p0, k.p1, k.p2, h);
      ASSERT_EQ(got, got0) << "case " << i << " direction scaled by 2^" << e
                           << " (|d| = " << glm::length(d) << ", t0 = " << h0.t << ")";
      if (!got) continue;
      EXPECT_EQ(std::ldexp(h.t, e), h0.t) << "case " << i << " 2^" << e;
      EXPECT_EQ(h.b0, h0.b0);
      EXPECT_EQ(h.b1, h0.b1);
      EXPECT_EQ(h.b2, h0.b2);
    }
  }
  EXPECT_GT(hits, 15000);
}

TEST(Triangle, RaysPassingAHairOutsideOrInsideAnEdge) {
  // Aim at a point offset by delta across an edge (outside or inside) with
  // delta log-uniform from 2 to 2000 times the classification band. The exact
  // answer (double, for the float ray) must be reproduced.
  Rng rng(4242);
  const int kCases = 40000;
  int inside = 0, outside = 0;
  for (int i = 0; i < kCases; ++i) {
    TriangleCase k;
    DVec3 c(rng.uniform(-100, 100), rng.uniform(-100, 100), rng.uniform(-100, 100));
    k.L = rng.log_uniform(0.01, 10.0);
    random_triangle(rng, c, k.L, k.p0, k.p1, k.p2);
    DVec3 v[3] = {to_d(k.p0), to_d(k.p1), to_d(k.p2)};
    int e = rng.integer(0, 2);
    DVec3 a = v[e], b = v[(e + 1) % 3], opp = v[(e + 2) % 3];
    DVec3 n = glm::normalize(glm::cross(v[1] - v[0], v[2] - v[0]));
    DVec3 out = glm::normalize(glm::cross(b - a, n));
    if (glm::dot(out, opp - a) > 0) out = -out;  // points away from the triangle
    DVec3 m = a + rng.uniform(0.2, 0.8) * (b - a);
    double cs = rng.uniform(0.2, 1.0);
    DVec3 t1 = glm::normalize(b - a), t2 = glm::cross(n, t1);
    double phi = rng.uniform(0, 2 * kPi);
    DVec3 w = cs * n + std::sqrt(1 - cs * cs) * (std::cos(phi) * t1 + std::sin(phi) * t2);
    if (rng.coin()) w = -w;
    k.D = k.L * rng.log_uniform(0.5, 20.0);
    k.cosine = cs;
    double band = classification_band(k);
    double delta = band * rng.log_uniform(2.0, 2000.0) / cs;  // in-plane offset
    bool want_out = rng.coin();
    DVec3 q = m + (want_out ? delta : -delta) * out;
    k.o = to_f(q + k.D * w);
    k.d = to_f(q - to_d(k.o));
    rstest::RefTriHit ref;
    ASSERT_TRUE(rstest::ref_ray_plane_of_triangle(to_d(k.o), to_d(k.d), v[0], v[1], v[2], ref));
    if (edge_margin(k) <= band) continue;  // rounding of the ray moved it into the band
    bool expect = ref.min_bary > 0;
    TriangleHit h;
    bool got = intersect_triangle(Ray{k.o, k.d, kInfinity}, k.p0, k.p1, k.p2, h);
    ASSERT_EQ(got, expect) << "case " << i << " delta/band=" << delta / band
                           << " min_bary=" << ref.min_bary;
    (expect ? inside : outside)++;
  }
  EXPECT_GT(inside, kCases / 4);
  EXPECT_GT(outside, kCases / 4);
}

TEST(Triangle, OneUlpOutsideAndInsideExactConfigurations) {
  // Configurations where every intermediate value of the watertight test is
  // exactly representable, so even a 1-ulp offset must be classified right.
  const Vec3 p0(0, 0, 0), p1(1, 0, 0), p2(0, 1, 0);
  TriangleHit h;
  const float u = std::ldexp(1.0f, -24);  // ulp of values in [0.5, 1)
  struct Case {
    Vec3 q;  // where the ray crosses z = 0
    bool hit;
  };
  const Case cases[] = {
      {{0.25f, -std::ldexp(1.0f, -30), 0}, false},  // just below edge y = 0
      {{0.25f, std::ldexp(1.0f, -30), 0}, true},
      {{-std::ldexp(1.0f, -30), 0.25f, 0}, false},  // just left of edge x = 0
      {{std::ldexp(1.0f, -30), 0.25f, 0}, true},
      {{0.5f + u, 0.5f, 0}, false},  // x + y = 1 + 2^-24: 1 ulp outside the diagonal
      {{0.5f - u / 2, 0.5f, 0}, true},
      {{0.25f, 0.75f + u, 0}, false},
      {{0.25f, 0.75f - u / 2, 0}, true},
  };
  // Straight down and along two dyadic oblique directions (exact shear). Only
  // rays whose origin q - d is exact (checked in double) are used, so that the
  // ray really crosses z = 0 at q.
  const Vec3 dirs[] = {{0, 0, -1}, {0.5f, 0.25f, -1}, {-0.25f, 0.5f, -1}};
  int checked = 0;
  for (const Vec3& d : dirs) {
    for (const Case& c : cases) {
      Ray ray{c.q - d, d, kInfinity};
      if (to_d(ray.origin) + to_d(d) != to_d(c.q)) continue;
      ++checked;
      EXPECT_EQ(intersect_triangle(ray, p0, p1, p2, h), c.hit)
          << "q=(" << c.q.x << "," << c.q.y << ") d=(" << d.x << "," << d.y << ")";
      if (c.hit) {
        EXPECT_EQ(h.t, 1.0f);
      }
    }
  }
  EXPECT_GE(checked, 12);  // 15 of the 24 combinations have an exact origin
  // Rays through a vertex or along an edge hit (edge functions exactly zero).
  EXPECT_TRUE(intersect_triangle(Ray{{0, 0, 1}, {0, 0, -1}, kInfinity}, p0, p1, p2, h));
  EXPECT_TRUE(intersect_triangle(Ray{{0.5f, 0, 1}, {0, 0, -1}, kInfinity}, p0, p1, p2, h));
  EXPECT_TRUE(intersect_triangle(Ray{{0.5f, 0.5f, 1}, {0, 0, -1}, kInfinity}, p0, p1, p2, h));
}

TEST(Triangle, RangeDegenerateAndParallel) {
  const Vec3 p0(0, 0, 0), p1(1, 0, 0), p2(0, 1, 0);
  TriangleHit h;
  // Behind the origin, beyond tmax, exactly at tmax.
  EXPECT_FALSE(intersect_triangle(Ray{{0.2f, 0.2f, -1}, {0, 0, -1}, kInfinity}, p0, p1, p2, h));
  EXPECT_FALSE(intersect_triangle(Ray{{0.2f, 0.2f, 2}, {0, 0, -1}, 1.5f}, p0, p1, p2, h));
  EXPECT_TRUE(intersect_triangle(Ray{{0.2f, 0.2f, 2}, {0, 0, -1}, 2.5f}, p0, p1, p2, h));
  EXPECT_EQ(h.t, 2.0f);
  // Both windings hit.
  EXPECT_TRUE(intersect_triangle(Ray{{0.2f, 0.2f, 2}, {0, 0, -1}, kInfinity}, p0, p2, p1, h));
  EXPECT_TRUE(intersect_triangle(Ray{{0.2f, 0.2f, -2}, {0, 0, 1}, kInfinity}, p0, p1, p2, h));
  // Ray in the plane of the triangle, and a degenerate triangle.
  EXPECT_FALSE(intersect_triangle(Ray{{-1, 0.2f, 0}, {1, 0, 0}, kInfinity}, p0, p1, p2, h));
  EXPECT_FALSE(
      intersect_triangle(Ray{{0.5f, 0, 1}, {0, 0, -1}, kInfinity}, p0, p1, Vec3(2, 0, 0), h));
  // Origin on the triangle: t would be 0, which is not a hit.
  EXPECT_FALSE(intersect_triangle(Ray{{0.2f, 0.2f, 0}, {0, 0, -1}, kInfinity}, p0, p1, p2, h));
}

// ---------------------------------------------------------------------------
// Spheres

struct SphereCase {
  Vec3 c, o, d;
  float r;
  double impact_rel;  // impact parameter / r
};

SphereCase make_sphere_case(Rng& rng, const DVec3& center, double r, double dist_lo, double dist_hi,
                            double impact_max) {
  SphereCase k;
  k.c = to_f(center);
  k.r = rstest::round_f(r);
  DVec3 w = rng.unit_vector();
  double D = double(k.r) * rng.log_uniform(dist_lo, dist_hi);
  k.o = to_f(to_d(k.c) + D * w);
  // Aim at a point at distance b from the center, perpendicular to w.
  DVec3 t1 = glm::normalize(glm::cross(w, std::abs(w.x) < 0.9 ? DVec3(1, 0, 0) : DVec3(0, 1, 0)));
  DVec3 t2 = glm::cross(w, t1);
  double phi = rng.uniform(0, 2 * kPi);
  double b = double(k.r) * impact_max * std::sqrt(rng.uniform());
  DVec3 aim = to_d(k.c) + b * (std::cos(phi) * t1 + std::sin(phi) * t2);
  k.d = to_f((aim - to_d(k.o)) * rng.log_uniform(0.1, 10.0));
  k.impact_rel = b / double(k.r);
  return k;
}

// Checks a hit against the double reference. Returns the relative t error.
double check_sphere_hit(const SphereCase& k, float t, int i) {
  double t0 = 0, t1 = 0, impact = 0;
  EXPECT_TRUE(rstest::ref_ray_sphere(to_d(k.o), to_d(k.d), to_d(k.c), k.r, t0, t1, impact));
  double rel = std::abs(double(t) - t0) / t0;
  Ray ray{k.o, k.d, kInfinity};
  Vec3 perr, ng;
  Vec3 p = sphere_point(ray, t, k.c, k.r, perr, ng);
  // p_error is a per-axis bound: some exact surface point lies in the box
  // [p - p_error, p + p_error], i.e. the box meets the sphere (its nearest
  // point is no farther than r from the center and its farthest no nearer).
  DVec3 lo = to_d(p) - to_d(perr), hi = to_d(p) + to_d(perr), cd = to_d(k.c);
  DVec3 nearest = glm::clamp(cd, lo, hi);
  DVec3 farthest(0);
  for (int a = 0; a < 3; ++a)
    farthest[a] = std::abs(lo[a] - cd[a]) > std::abs(hi[a] - cd[a]) ? lo[a] : hi[a];
  EXPECT_LE(glm::length(nearest - cd), double(k.r)) << "case " << i;
  EXPECT_GE(glm::length(farthest - cd), double(k.r)) << "case " << i;
  // Along the normal, which is what spawn_ray offsets by, the distance from
  // the surface is within the bound projected on the normal.
  DVec3 v = to_d(p) - cd;
  DVec3 n = glm::normalize(v);
  EXPECT_LE(std::abs(glm::length(v) - double(k.r)), glm::dot(glm::abs(n), to_d(perr)))
      << "case " << i;
  // The normal is the point's direction from the center: p lies within its
  // bound of center + r ng.
  const DVec3 off = glm::abs(to_d(p) - (cd + double(k.r) * to_d(ng)));
  EXPECT_TRUE(off.x <= perr.x && off.y <= perr.y && off.z <= perr.z) << "case " << i;
  return rel;
}

TEST(Sphere, RandomHitsMatchDoubleReference) {
  // Spheres of radius 0.1..10 near the origin, rays from 1.5..20 radii away
  // with impact parameter <= 0.95 r. The root's condition number is
  // r / sqrt(r^2 - b^2) <= 3.2; the computed t is within
  // 16 eps * (|c| + |o| + |f|) * cond / |d| (f = o - c rounded: eps (|o| + |c|);
  // closest-approach vector l: gamma(5) |f|; root: gamma(3)).
  Rng rng(99);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    DVec3 c(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10));
    SphereCase k = make_sphere_case(rng, c, rng.log_uniform(0.1, 10), 1.5, 20, 0.95);
    float t;
    ASSERT_TRUE(intersect_sphere(Ray{k.o, k.d, kInfinity}, k.c, k.r, kInfinity, t)) << "case " << i;
    double t0 = 0, t1 = 0, impact = 0;
    rstest::ref_ray_sphere(to_d(k.o), to_d(k.d), to_d(k.c), k.r, t0, t1, impact);
    double cond = double(k.r) / std::sqrt(std::max(0.0, double(k.r) * k.r - impact * impact));
    double scale = rstest::max_abs(to_d(k.c)) + rstest::max_abs(to_d(k.o)) +
                   glm::length(to_d(k.o) - to_d(k.c));
    double err = std::abs(double(t) - t0) * glm::length(to_d(k.d));
    EXPECT_LE(err, 16 * kEps * scale * cond) << "case " << i;
    worst = std::max(worst, err / (kEps * scale * cond));
    check_sphere_hit(k, t, i);
  }
  std::printf("sphere: worst t error %.2f eps*scale*cond (limit 16)\n", worst);
}

TEST(Sphere, RaysFromInsideHitTheFarSide) {
  Rng rng(5);
  for (int i = 0; i < 5000; ++i) {
    DVec3 c(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10));
    float r = rstest::round_f(rng.log_uniform(0.1, 10));
    Vec3 o = to_f(c + 0.9 * double(r) * rng.in_unit_ball());
    Vec3 d = to_f(rng.unit_vector() * rng.log_uniform(0.1, 10));
    float t;
    ASSERT_TRUE(intersect_sphere(Ray{o, d, kInfinity}, to_f(c), r, kInfinity, t));
    double t0 = 0, t1 = 0, impact = 0;
    ASSERT_TRUE(rstest::ref_ray_sphere(to_d(o), to_d(d), to_d(to_f(c)), r, t0, t1, impact));
    ASSERT_LT(t0, 0.0);
    // Far root: well conditioned; 16 eps * scale as above.
    double scale = rstest::max_abs(c) + rstest::max_abs(to_d(o)) + r;
    EXPECT_LE(std::abs(double(t) - t1) * glm::length(to_d(d)), 16 * kEps * scale);
  }
}

TEST(Sphere, SilhouetteHairMissesAndHits) {
  // Impact parameter r +- delta, delta log-uniform in 2..2000 times the band
  // 32 eps * scale (scale = |c| + |o| + |o - c| + r) within which the rounding
  // of f = o - c (eps (|o| + |c|)) and of the closest-approach vector l
  // (gamma(5) |f|) may decide either way. Outside the band the exact answer
  // must come out.
  Rng rng(31337);
  int hits = 0, misses = 0;
  for (int i = 0; i < 40000; ++i) {
    DVec3 c(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10));
    double r = rstest::round_f(rng.log_uniform(0.1, 10));
    DVec3 w = rng.unit_vector();
    double D = r * rng.log_uniform(1.5, 20);
    Vec3 o = to_f(to_d(to_f(c)) + D * w);
    double scale = rstest::max_abs(c) + rstest::max_abs(to_d(o)) + D + r;
    double band = 32 * kEps * scale;
    double delta = band * rng.log_uniform(2, 2000);
    double b = r + (rng.coin() ? delta : -delta);
    // Direction at angle asin(b / |o - c|) from the line to the center: the
    // line then passes at distance b from the center.
    DVec3 f = to_d(o) - to_d(to_f(c));
    double Df = glm::length(f);
    DVec3 wf = f / Df;
    DVec3 t1 = glm::normalize(glm::cross(wf, DVec3(0.3, 0.5, 0.8)));
    double sn = b / Df;
    Vec3 d = to_f((-std::sqrt(1 - sn * sn) * wf + sn * t1) * rng.log_uniform(0.1, 10));
    double t0r = 0, t1r = 0, impact = 0;
    bool ref = rstest::ref_ray_sphere(to_d(o), to_d(d), to_d(to_f(c)), r, t0r, t1r, impact);
    if (std::abs(impact - r) <= band) continue;
    float t;
    bool got = intersect_sphere(Ray{o, d, kInfinity}, to_f(c), float(r), kInfinity, t);
    ASSERT_EQ(got, ref) << "case " << i << " (impact - r)/band=" << (impact - r) / band;
    (got ? hits : misses)++;
  }
  std::printf("silhouette: %d hits %d misses\n", hits, misses);
  EXPECT_GT(hits, 10000);
  EXPECT_GT(misses, 10000);
}

// Small (r = 1e-4, seen from ~1..10 away) and distant (center ~1e4 from the
// origin, r ~ 1) spheres. The robust formula keeps the relative t error at a
// few eps (limit 16 eps * cond, cond <= 2.3 for impact <= 0.9 r). The textbook
// b^2 - 4ac in float loses everything here: b^2 and 4ac agree in all but
// their last digits, so the computed discriminant's error (~eps b^2 ~ eps D^2)
// exceeds its true value (~r^2), and the root is off by up to ~sqrt(eps) D,
// a relative error of ~1e-4 instead of ~1e-7; the last check below shows that
// the same tolerance rejects it.
void small_or_distant(bool small, uint32_t seed) {
  Rng rng(seed);
  double worst = 0;
  int naive_bad = 0;
  const int kCases = 20000;
  for (int i = 0; i < kCases; ++i) {
    SphereCase k;
    if (small) {
      DVec3 c(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      k = make_sphere_case(rng, c, 1e-4, 1e4, 1e5, 0.9);
    } else {
      DVec3 c = 1e4 * rng.unit_vector();
      k = make_sphere_case(rng, c, rng.uniform(0.5, 5), 1.0, 2.0, 0.9);
      k.o = to_f(rng.in_unit_ball());  // ray from near the world origin
      DVec3 aim = to_d(k.c) + k.impact_rel * double(k.r) *
                                  glm::normalize(glm::cross(to_d(k.c), rng.unit_vector()));
      k.d = to_f(aim - to_d(k.o));
    }
    Ray ray{k.o, k.d, kInfinity};
    double t0 = 0, t1 = 0, impact = 0;
    ASSERT_TRUE(rstest::ref_ray_sphere(to_d(k.o), to_d(k.d), to_d(k.c), k.r, t0, t1, impact));
    double cond = double(k.r) / std::sqrt(double(k.r) * k.r - impact * impact);
    float t;
    ASSERT_TRUE(intersect_sphere(ray, k.c, k.r, kInfinity, t)) << "case " << i;
    double rel = check_sphere_hit(k, t, i);
    EXPECT_LE(rel, 16 * kEps * cond) << "case " << i << " t=" << t << " ref=" << t0;
    worst = std::max(worst, rel / (kEps * cond));
    float tn;
    if (!naive_sphere(ray, k.c, k.r, tn) || std::abs(double(tn) - t0) / t0 > 16 * kEps * cond)
      ++naive_bad;
  }
  std::printf(
      "%s sphere: worst relative t error %.2f eps*cond (limit 16); textbook formula "
      "fails %d of %d\n",
      small ? "small" : "distant", worst, naive_bad, kCases);
  EXPECT_GT(naive_bad, kCases / 2);  // the tolerance is tight enough to matter
}

TEST(Sphere, SmallSphereAccuracy) {
  small_or_distant(true, 2024);
}
TEST(Sphere, DistantSphereAccuracy) {
  small_or_distant(false, 2025);
}

TEST(Sphere, RangeChecks) {
  float t;
  const Vec3 c(0, 0, 0);
  EXPECT_FALSE(intersect_sphere(Ray{{0, 0, 5}, {0, 0, 1}, kInfinity}, c, 1, kInfinity, t));
  EXPECT_FALSE(intersect_sphere(Ray{{0, 0, 5}, {0, 0, -1}, kInfinity}, c, 1, 3.5f, t));
  EXPECT_TRUE(intersect_sphere(Ray{{0, 0, 5}, {0, 0, -1}, kInfinity}, c, 1, 4.5f, t));
  EXPECT_EQ(t, 4.0f);
  EXPECT_TRUE(intersect_sphere(Ray{{0, 0, 5}, {0, 0, -2}, kInfinity}, c, 1, kInfinity, t));
  EXPECT_EQ(t, 2.0f);
  // Tangent ray: impact parameter exactly r.
  EXPECT_TRUE(intersect_sphere(Ray{{1, 0, 5}, {0, 0, -1}, kInfinity}, c, 1, kInfinity, t));
  EXPECT_EQ(t, 5.0f);
  EXPECT_FALSE(intersect_sphere(Ray{{next_float_up(1.0f), 0, 5}, {0, 0, -1}, kInfinity}, c, 1,
                                kInfinity, t));
}

// ---------------------------------------------------------------------------
// Capsules (tube segments)

using rstest::LDVec3;
using rstest::to_ld;

struct CapsuleCase {
  Vec3 p0, p1, o, d;
  float r;
};

// A capsule around a center within `spread` of the origin, radius 0.1..10,
// length 0 (every tenth case) or 0.01..20 radii, seen from 1.5..20 of its
// half extent away, aimed at a point within 0.95 r of its segment (so the
// line meets the solid).
CapsuleCase make_capsule_case(Rng& rng, double spread, int i) {
  CapsuleCase k;
  const DVec3 c(rng.uniform(-spread, spread), rng.uniform(-spread, spread),
                rng.uniform(-spread, spread));
  k.r = rstest::round_f(rng.log_uniform(0.1, 10));
  const double len = i % 10 == 0 ? 0.0 : double(k.r) * rng.log_uniform(0.01, 20);
  const DVec3 axis = rng.unit_vector();
  k.p0 = to_f(c - 0.5 * len * axis);
  k.p1 = to_f(c + 0.5 * len * axis);
  const double extent = 0.5 * len + double(k.r);
  k.o = to_f(c + extent * rng.log_uniform(1.5, 20) * rng.unit_vector());
  const DVec3 aim = to_d(k.p0) + rng.uniform() * (to_d(k.p1) - to_d(k.p0)) +
                    0.95 * double(k.r) * rng.in_unit_ball();
  k.d = to_f((aim - to_d(k.o)) * rng.log_uniform(0.1, 10));
  return k;
}

// Checks a capsule hit at t against the long double reference root `ref`:
// the distance along the ray within 16 eps * scale / |cos|, where |cos| is
// the angle between the ray and the exact normal there (the root's
// condition), and the hit point within its bound of the surface along the
// normal. Returns the error in units of eps * scale / |cos|.
double check_capsule_hit(const CapsuleCase& k, float t, long double ref, int i) {
  const LDVec3 o = to_ld(k.o), d = to_ld(k.d), a = to_ld(k.p0), b = to_ld(k.p1);
  const LDVec3 q = o + ref * d;
  const LDVec3 e = b - a;
  const long double ee = glm::dot(e, e);
  const long double s = ee > 0 ? std::clamp(glm::dot(q - a, e) / ee, 0.0L, 1.0L) : 0.0L;
  const LDVec3 n = glm::normalize(q - (a + s * e));
  const double cosine = double(std::abs(glm::dot(n, d)) / glm::length(d));
  const double scale = std::max(rstest::max_abs(to_d(k.p0)), rstest::max_abs(to_d(k.p1))) +
                       rstest::max_abs(to_d(k.o)) + glm::length(to_d(k.o) - to_d(k.p0)) +
                       glm::length(to_d(k.p1) - to_d(k.p0)) + double(k.r);
  const double err = double(std::abs((long double)t - ref) * glm::length(d));
  EXPECT_LE(err, 16 * kEps * scale / cosine) << "case " << i << " t=" << t;
  Vec3 perr, ng;
  float along;
  const Vec3 p = capsule_point(Ray{k.o, k.d, kInfinity}, t, k.p0, k.p1, k.r, perr, ng, along);
  const long double off = rstest::ref_segment_distance(to_ld(p), a, b) - k.r;
  EXPECT_LE(std::abs(off), glm::dot(glm::abs(to_ld(ng)), to_ld(perr))) << "case " << i;
  EXPECT_NEAR(glm::length(to_d(ng)), 1.0, 4 * kEps) << "case " << i;
  EXPECT_TRUE(along >= 0.0f && along <= 1.0f) << "case " << i;
  return err / (kEps * scale / cosine);
}

TEST(Capsule, RandomHitsMatchLongDoubleReference) {
  // Entry roots: t within 16 eps * scale / |cos| of the exact root (the
  // offsets o - p0, o - p1, p1 - p0 are exact or within eps of their size;
  // the projections and the closest approach add a few roundings in double),
  // hit points on the surface within their bound.
  Rng rng(71);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const CapsuleCase k = make_capsule_case(rng, 10, i);
    long double t_in, t_out;
    ASSERT_TRUE(rstest::ref_capsule_interval(to_ld(k.o), to_ld(k.d), to_ld(k.p0), to_ld(k.p1), k.r,
                                             t_in, t_out));
    float t;
    ASSERT_TRUE(intersect_capsule(Ray{k.o, k.d, kInfinity}, k.p0, k.p1, k.r, kInfinity, t))
        << "case " << i;
    ASSERT_GT(t_in, 0.0L);
    worst = std::max(worst, check_capsule_hit(k, t, t_in, i));
    if (HasFailure()) return;
  }
  std::printf("capsule: worst t error %.2f eps*scale/|cos| (limit 16)\n", worst);
}

TEST(Capsule, RaysFromInsideHitTheFarSide) {
  Rng rng(72);
  for (int i = 0; i < 5000; ++i) {
    CapsuleCase k = make_capsule_case(rng, 10, i);
    k.o = to_f(to_d(k.p0) + rng.uniform() * (to_d(k.p1) - to_d(k.p0)) +
               0.9 * double(k.r) * rng.in_unit_ball());
    k.d = to_f(rng.unit_vector() * rng.log_uniform(0.1, 10));
    long double t_in, t_out;
    ASSERT_TRUE(rstest::ref_capsule_interval(to_ld(k.o), to_ld(k.d), to_ld(k.p0), to_ld(k.p1), k.r,
                                             t_in, t_out));
    ASSERT_LT(t_in, 0.0L);
    float t;
    ASSERT_TRUE(intersect_capsule(Ray{k.o, k.d, kInfinity}, k.p0, k.p1, k.r, kInfinity, t))
        << "case " << i;
    check_capsule_hit(k, t, t_out, i);
    if (HasFailure()) return;
  }
}

TEST(Capsule, ZeroLengthIsTheSphereTestBitForBit) {
  // A segment of length 0 is its end's ball, tested with the sphere's
  // formulas: the same answer, the same t.
  Rng rng(73);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 c = to_f(DVec3(rng.log_uniform_signed(1e-3, 1e3), rng.log_uniform_signed(1e-3, 1e3),
                              rng.log_uniform_signed(1e-3, 1e3)));
    const float r = rstest::round_f(rng.log_uniform(1e-3, 1e3));
    const Vec3 o = to_f(to_d(c) + double(r) * rng.log_uniform(0.5, 100) * rng.unit_vector());
    const Vec3 d = to_f(to_d(c) + 1.2 * double(r) * rng.in_unit_ball() - to_d(o));
    const float tmax = i % 3 == 0 ? kInfinity : float(rng.uniform(0, 2));
    float ts = -1, tc = -1;
    const bool s = intersect_sphere(Ray{o, d, kInfinity}, c, r, tmax, ts);
    ASSERT_EQ(intersect_capsule(Ray{o, d, kInfinity}, c, c, r, tmax, tc), s) << "case " << i;
    if (s) {
      EXPECT_EQ(tc, ts) << "case " << i;
    }
    hits += s;
  }
  EXPECT_GT(hits, 5000);
}

TEST(Capsule, SilhouetteHairMissesAndHits) {
  // A ray in the tangent plane at a point of the surface (side or cap),
  // moved off it by delta along the normal: outward it misses the solid by
  // delta (the tangent plane supports the convex capsule), inward it passes
  // delta deep. delta is 2..2000 times the band 32 eps * scale in which the
  // rounding of the inputs and of the test may decide either way; outside it
  // the exact answer must come out.
  Rng rng(74);
  int hits = 0, misses = 0;
  for (int i = 0; i < 40000; ++i) {
    const DVec3 c(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10));
    const float r = rstest::round_f(rng.log_uniform(0.1, 10));
    const double len = double(r) * rng.log_uniform(0.1, 10);
    const DVec3 axis = rng.unit_vector();
    const Vec3 p0 = to_f(c - 0.5 * len * axis), p1 = to_f(c + 0.5 * len * axis);
    const DVec3 a = to_d(p0), e = to_d(p1) - a, u = glm::normalize(e);
    // The surface point: on the side (s in [0, 1], normal across the axis)
    // or on a cap (normal pointing away from the other end).
    DVec3 nrm = rng.unit_vector(), base;
    const int where = rng.integer(0, 2);
    if (where == 0) {
      nrm = glm::normalize(nrm - glm::dot(nrm, u) * u);
      base = a + rng.uniform() * e;
    } else {
      if ((glm::dot(nrm, u) > 0) == (where == 1)) nrm = -nrm;
      base = where == 1 ? a : to_d(p1);
    }
    const DVec3 q = base + double(r) * nrm;
    const DVec3 tan = glm::normalize(glm::cross(nrm, rng.unit_vector()));
    const double scale = rstest::max_abs(c) + len + 40.0 * double(r);
    const double band = 32 * kEps * scale;
    const double delta = band * rng.log_uniform(2, 2000);
    if (delta > 0.5 * double(r)) continue;
    const bool inward = rng.coin();
    const DVec3 through = q + (inward ? -delta : delta) * nrm;
    const Vec3 o = to_f(through - double(r) * rng.log_uniform(1.5, 20) * tan);
    const Vec3 d = to_f((through - to_d(o)) * rng.log_uniform(0.1, 10));
    float t;
    const bool got = intersect_capsule(Ray{o, d, kInfinity}, p0, p1, r, kInfinity, t);
    ASSERT_EQ(got, inward) << "case " << i << " (" << (where ? "cap" : "side")
                           << "), delta/band=" << delta / band;
    (got ? hits : misses)++;
  }
  std::printf("capsule silhouette: %d hits %d misses\n", hits, misses);
  EXPECT_GT(hits, 10000);
  EXPECT_GT(misses, 10000);
}

TEST(Capsule, RangeChecksAndExactConfigurations) {
  // The capsule around (0,0,0)-(4,0,0), radius 1.
  const Vec3 a(0, 0, 0), b(4, 0, 0);
  float t;
  // Across the side: t = 4 exactly; open at tmax like the sphere.
  EXPECT_TRUE(intersect_capsule(Ray{{2, 0, 5}, {0, 0, -1}, kInfinity}, a, b, 1, kInfinity, t));
  EXPECT_EQ(t, 4.0f);
  EXPECT_FALSE(intersect_capsule(Ray{{2, 0, 5}, {0, 0, -1}, kInfinity}, a, b, 1, 4.0f, t));
  EXPECT_TRUE(intersect_capsule(Ray{{2, 0, 5}, {0, 0, -1}, kInfinity}, a, b, 1, 4.5f, t));
  EXPECT_FALSE(intersect_capsule(Ray{{2, 0, 5}, {0, 0, 1}, kInfinity}, a, b, 1, kInfinity, t));
  // Along the axis into a cap (x = -1), and from inside out through the other (x = 5).
  EXPECT_TRUE(intersect_capsule(Ray{{-5, 0, 0}, {1, 0, 0}, kInfinity}, a, b, 1, kInfinity, t));
  EXPECT_EQ(t, 4.0f);
  EXPECT_TRUE(intersect_capsule(Ray{{2, 0, 0}, {2, 0, 0}, kInfinity}, a, b, 1, kInfinity, t));
  EXPECT_EQ(t, 1.5f);
  // Through the circle where side and cap meet (x = 4, z = 1), head on and
  // along the side: the pieces overlap there, no gap.
  EXPECT_TRUE(intersect_capsule(Ray{{4, 0, 5}, {0, 0, -1}, kInfinity}, a, b, 1, kInfinity, t));
  EXPECT_EQ(t, 4.0f);
  EXPECT_TRUE(intersect_capsule(Ray{{next_float_down(4.0f), 0, 5}, {0, 0, -1}, kInfinity}, a, b, 1,
                                kInfinity, t));
  EXPECT_EQ(t, 4.0f);
  EXPECT_TRUE(intersect_capsule(Ray{{next_float_up(4.0f), 0, 5}, {0, 0, -1}, kInfinity}, a, b, 1,
                                kInfinity, t));
  EXPECT_EQ(t, 4.0f);
  // Tangent to the side (touching counts, as for the sphere), a hair beyond.
  EXPECT_TRUE(intersect_capsule(Ray{{2, 1, 5}, {0, 0, -1}, kInfinity}, a, b, 1, kInfinity, t));
  EXPECT_EQ(t, 5.0f);
  EXPECT_FALSE(intersect_capsule(Ray{{2, next_float_up(1.0f), 5}, {0, 0, -1}, kInfinity}, a, b, 1,
                                 kInfinity, t));
  // Along the side, in the tangent line: it touches the whole side and the
  // first cap's rim; the first contact is at x = 0.
  EXPECT_TRUE(intersect_capsule(Ray{{-5, 1, 0}, {1, 0, 0}, kInfinity}, a, b, 1, kInfinity, t));
  EXPECT_EQ(t, 5.0f);
  EXPECT_FALSE(intersect_capsule(Ray{{-5, next_float_up(1.0f), 0}, {1, 0, 0}, kInfinity}, a, b, 1,
                                 kInfinity, t));
  // Parallel to the end planes inside the slab, and outside it.
  EXPECT_TRUE(intersect_capsule(Ray{{1, -5, 0}, {0, 1, 0}, kInfinity}, a, b, 1, kInfinity, t));
  EXPECT_EQ(t, 4.0f);
  EXPECT_TRUE(intersect_capsule(Ray{{-0.5f, -5, 0}, {0, 1, 0}, kInfinity}, a, b, 1, kInfinity, t));
  EXPECT_FALSE(intersect_capsule(Ray{{-1.5f, -5, 0}, {0, 1, 0}, kInfinity}, a, b, 1, kInfinity, t));
  // Non-finite rays and a zero direction never hit.
  EXPECT_FALSE(intersect_capsule(Ray{{2, 0, 5}, {0, 0, 0}, kInfinity}, a, b, 1, kInfinity, t));
  EXPECT_FALSE(intersect_capsule(Ray{{NAN, 0, 5}, {0, 0, -1}, kInfinity}, a, b, 1, kInfinity, t));
  EXPECT_FALSE(
      intersect_capsule(Ray{{2, 0, 5}, {0, kInfinity, -1}, kInfinity}, a, b, 1, kInfinity, t));
  // The hit point's normal and place along the segment.
  Vec3 perr, n;
  float s;
  const Vec3 p = capsule_point(Ray{{3, 0, 5}, {0, 0, -1}, kInfinity}, 4.0f, a, b, 1, perr, n, s);
  EXPECT_EQ(p, Vec3(3, 0, 1));
  EXPECT_EQ(n, Vec3(0, 0, 1));
  EXPECT_EQ(s, 0.75f);
  capsule_point(Ray{{-5, 0, 0}, {1, 0, 0}, kInfinity}, 4.0f, a, b, 1, perr, n, s);
  EXPECT_EQ(n, Vec3(-1, 0, 0));
  EXPECT_EQ(s, 0.0f);
}

// ---------------------------------------------------------------------------
// Planes

TEST(Plane, RandomHitsMatchDoubleReference) {
  // t = (P0 - o).n / (d.n): the numerator's error is eps (|P0| + |o|) (the
  // subtraction) + gamma(3) |P0 - o| (dot); the denominator's relative error is
  // gamma(3) / cos (cancellation in the dot when d is nearly in the plane).
  // Along the ray that is <= 16 eps (|P0| + |o| + |P0 - o|) / cos.
  Rng rng(8);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    Vec3 point =
        to_f(DVec3(rng.uniform(-100, 100), rng.uniform(-100, 100), rng.uniform(-100, 100)));
    Vec3 n = glm::normalize(to_f(rng.unit_vector()));
    DVec3 nd = glm::normalize(to_d(n));
    DVec3 t1 = glm::normalize(glm::cross(nd, rng.unit_vector())), t2 = glm::cross(nd, t1);
    double cs = rng.log_uniform(1e-3, 1.0);
    double side = rng.coin() ? 1.0 : -1.0;
    DVec3 q = to_d(point) + rng.uniform(-50, 50) * t1 + rng.uniform(-50, 50) * t2;
    double D = rng.log_uniform(1e-2, 1e3);
    DVec3 w = side * (cs * nd + std::sqrt(1 - cs * cs) * t2);
    Vec3 o = to_f(q + D * w);
    Vec3 d = to_f(-w * rng.log_uniform(0.1, 10));
    double t_ref = glm::dot(to_d(point) - to_d(o), to_d(n)) / glm::dot(to_d(d), to_d(n));
    ASSERT_GT(t_ref, 0);
    float t;
    Ray ray{o, d, kInfinity};
    ASSERT_TRUE(intersect_plane(ray, point, n, kInfinity, t)) << "case " << i;
    double scale = rstest::max_abs(to_d(point)) + rstest::max_abs(to_d(o)) +
                   glm::length(to_d(point) - to_d(o));
    double cosine = std::abs(glm::dot(glm::normalize(to_d(d)), nd));
    double err = std::abs(double(t) - t_ref) * glm::length(to_d(d));
    EXPECT_LE(err, 16 * kEps * scale / cosine) << "case " << i;
    worst = std::max(worst, err / (kEps * scale / cosine));
    // The re-projected point is on the plane within its bound.
    Vec3 perr;
    Vec3 p = plane_point(ray, t, point, n, perr);
    // (For a plane, "the box [p - p_error, p + p_error] meets the plane" and
    // "the distance along the normal is within the projected bound" coincide.)
    double dist = glm::dot(to_d(p) - to_d(point), nd);
    EXPECT_LE(std::abs(dist), glm::dot(glm::abs(nd), to_d(perr))) << "case " << i;
    // And it is where the ray meets the plane.
    EXPECT_LE(rstest::max_abs(to_d(p) - (to_d(o) + t_ref * to_d(d))), 16 * kEps * scale / cosine);
  }
  std::printf("plane: worst t error %.2f eps*scale/cos (limit 16)\n", worst);
}

TEST(Plane, MissesAndRange) {
  const Vec3 point(0, 1, 0), n(0, 1, 0);
  float t;
  EXPECT_FALSE(intersect_plane(Ray{{0, 2, 0}, {1, 0, 0}, kInfinity}, point, n, kInfinity, t));
  EXPECT_FALSE(intersect_plane(Ray{{0, 2, 0}, {0, 1, 0}, kInfinity}, point, n, kInfinity, t));
  EXPECT_FALSE(intersect_plane(Ray{{0, 2, 0}, {0, -1, 0}, kInfinity}, point, n, 0.5f, t));
  EXPECT_TRUE(intersect_plane(Ray{{0, 2, 0}, {0, -1, 0}, kInfinity}, point, n, 1.5f, t));
  EXPECT_EQ(t, 1.0f);
  EXPECT_TRUE(intersect_plane(Ray{{0, 0, 0}, {0, 4, 0}, kInfinity}, point, n, kInfinity, t));
  EXPECT_EQ(t, 0.25f);
  // A ray starting on the plane does not hit it (t = 0 is excluded).
  EXPECT_FALSE(intersect_plane(Ray{{3, 1, 0}, {0, -1, 0}, kInfinity}, point, n, kInfinity, t));
  // Grazing but not parallel: hits far away.
  EXPECT_TRUE(intersect_plane(Ray{{0, 2, 0}, {1, -1e-6f, 0}, kInfinity}, point, n, kInfinity, t));
  EXPECT_NEAR(t, 1e6, 1e6 * 1e-6);
}

// ---------------------------------------------------------------------------
// Boxes

// Slab test in double: entry/exit parameters of the line, clipped to [0, tmax].
bool ref_box(const DVec3& lo, const DVec3& hi, const DVec3& o, const DVec3& d, double tmax,
             double& tn, double& tf) {
  tn = 0;
  tf = tmax;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return false;
      continue;
    }
    double t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    tn = std::max(tn, t0);
    tf = std::min(tf, t1);
  }
  return tn <= tf;
}

TEST(Box, RandomRaysMatchDoubleSlabs) {
  // Random boxes and rays, some with zero direction components. The float
  // slab test computes each t with 2 roundings (subtraction, product with the
  // rounded reciprocal: 3 in all, gamma(3)); decisions closer than 8 eps *
  // (|o| + |box| + t |d|) are not checked. Entry distances must agree with
  // that tolerance, and a box the exact line clearly touches is never missed.
  Rng rng(17);
  int hits = 0, misses = 0;
  for (int i = 0; i < 50000; ++i) {
    DVec3 a(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10));
    DVec3 b =
        a + DVec3(rng.log_uniform(1e-3, 10), rng.log_uniform(1e-3, 10), rng.log_uniform(1e-3, 10));
    Vec3 lo = to_f(a), hi = to_f(b);
    Vec3 o = to_f(DVec3(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20)));
    DVec3 dd = rng.unit_vector();
    if (rng.coin())  // aim at a point of the box
      dd = glm::normalize(a + (b - a) * DVec3(rng.uniform(), rng.uniform(), rng.uniform()) -
                          to_d(o));
    dd *= rng.log_uniform(0.1, 10);
    for (int k = 0; k < 3; ++k)
      if (rng.integer(0, 5) == 0) dd[k] = 0;
    if (dd == DVec3(0)) dd.z = 1;
    Vec3 d = to_f(dd);
    float tmax = rng.coin() ? kInfinity : rstest::round_f(rng.uniform(0, 40));
    double tn, tf;
    bool ref = ref_box(to_d(lo), to_d(hi), to_d(o), to_d(d), double(tmax), tn, tf);
    double scale = rstest::max_abs(to_d(o)) + rstest::max_abs(to_d(lo)) + rstest::max_abs(to_d(hi));
    double dl = glm::length(to_d(d));
    double tol = 8 * kEps * (scale / dl + (std::isfinite(tf) ? tf : tn));
    float got = intersect_box(lo, hi, o, 1.0f / d, tmax);
    if (ref && tf - tn > tol) {
      EXPECT_NE(got, kInfinity) << "case " << i;
      EXPECT_NEAR(double(got), tn, tol)
          << "case " << i << std::hexfloat << " lo=" << lo.x << "," << lo.y << "," << lo.z
          << " hi=" << hi.x << "," << hi.y << "," << hi.z << " o=" << o.x << "," << o.y << ","
          << o.z << " d=" << d.x << "," << d.y << "," << d.z << " tmax=" << tmax;
      ++hits;
    } else if (!ref) {
      // Clear misses: separated by more than the tolerance on some axis.
      double t0, t1;
      bool grown = ref_box(to_d(lo) - DVec3(tol * dl + 8 * kEps * scale),
                           to_d(hi) + DVec3(tol * dl + 8 * kEps * scale), to_d(o), to_d(d),
                           double(tmax) * (1 + tol), t0, t1);
      if (!grown) {
        EXPECT_EQ(got, kInfinity) << "case " << i;
        ++misses;
      }
    }
  }
  EXPECT_GT(hits, 5000);
  EXPECT_GT(misses, 5000);
}

TEST(Box, RaysTouchingAFaceOrParallelInsideTheSlab) {
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  auto test = [&](Vec3 o, Vec3 d) { return intersect_box(lo, hi, o, 1.0f / d, kInfinity); };
  // Origin inside: entry at 0.
  EXPECT_EQ(test({0.5f, 0.5f, 0.5f}, {0, 0, 1}), 0.0f);
  // Parallel to an axis, inside the slab / outside it.
  EXPECT_EQ(test({0.5f, 0.5f, -1}, {0, 0, 1}), 1.0f);
  EXPECT_EQ(test({1.5f, 0.5f, -1}, {0, 0, 1}), kInfinity);
  EXPECT_EQ(test({0.5f, 0.5f, -1}, {0, 0, -1}), kInfinity);
  // Through an edge and a corner of the box.
  EXPECT_EQ(test({1, 1, -1}, {0, 0, 1}), 1.0f);
  EXPECT_EQ(test({-1, -1, -1}, {1, 1, 1}), 1.0f);
  // Running exactly in the plane of a face (origin on the face plane, zero
  // direction component: (lo - o) / 0 = 0 * inf = NaN on that axis). The ray
  // touches the box, so the box must be reported; a robust BVH relies on it
  // (a triangle edge lying in that face can be hit).
  EXPECT_EQ(test({0, 0.5f, -1}, {0, 0, 1}), 1.0f);
  EXPECT_EQ(test({1, 0.5f, -1}, {0, 0, 1}), 1.0f);
  EXPECT_EQ(test({0.5f, 0, -1}, {0, 0, 1}), 1.0f);
  EXPECT_EQ(test({0.5f, 1, -1}, {0, 0, 1}), 1.0f);
  EXPECT_EQ(test({0, 1, -1}, {0, 0, 1}), 1.0f);
  EXPECT_EQ(test({-1, 0.5f, 0}, {1, 0, 0}), 1.0f);
  EXPECT_EQ(test({-1, 0.5f, 1}, {1, 0, -0.0f}), 1.0f);
  // Beyond tmax / behind the origin.
  EXPECT_EQ(intersect_box(lo, hi, Vec3(0.5f, 0.5f, -2), Vec3(kInfinity, kInfinity, 1), 1.5f),
            kInfinity);
  EXPECT_EQ(test({0.5f, 0.5f, 2}, {0, 0, 1}), kInfinity);
}

// The lecture's tests (textbook_intersect.h) on cases worked by hand, with
// inputs whose every value is exact in binary, so the answers are exact.
TEST(TextbookIntersect, PlaneLambdaAndTheParallelRay) {
  // Plane y = 2 (P_0 = (0, 2, 0), n = (0, 1, 0)); ray from the origin along
  // (0, 4, 0): t_r.n = 4, lambda = (P_0 - P_r).n / t_r.n = 2 / 4.
  const TextbookPlane p = textbook_plane(Vec3(0.0f), Vec3(0, 4, 0), Vec3(0, 2, 0), Vec3(0, 1, 0));
  EXPECT_EQ(p.tr_dot_n, 4.0);
  EXPECT_EQ(p.lambda, 0.5);
  EXPECT_TRUE(p.hit());
  // Parallel to the plane: t_r.n = 0, no lambda.
  const TextbookPlane q = textbook_plane(Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, 2, 0), Vec3(0, 1, 0));
  EXPECT_EQ(q.tr_dot_n, 0.0);
  EXPECT_FALSE(q.hit());
  // Behind the ray: lambda < 0.
  EXPECT_FALSE(textbook_plane(Vec3(0.0f), Vec3(0, -1, 0), Vec3(0, 2, 0), Vec3(0, 1, 0)).hit());
}

TEST(TextbookIntersect, TriangleLambdasInsideAndOutside) {
  const Vec3 p0(1, 0, 0), p1(5, 0, 0), p2(1, 8, 0);  // t_1 = (4, 0, 0), t_2 = (0, 8, 0)
  // Through P_0 + 0.25 t_1 + 0.5 t_2 = (2, 4, 0), from z = 3 along (0, 0, -1).
  const TextbookTriangle t = textbook_triangle(Vec3(2, 4, 3), Vec3(0, 0, -1), p0, p1, p2);
  EXPECT_EQ(t.n, DVec3(0, 0, 32));
  EXPECT_EQ(t.plane.tr_dot_n, -32.0);
  EXPECT_EQ(t.plane.lambda, 3.0);
  EXPECT_EQ(t.lambda1, 0.25);
  EXPECT_EQ(t.lambda2, 0.5);
  EXPECT_TRUE(t.inside());
  // Through P_0 + 0.75 t_1 + 0.5 t_2: in the plane, lambda1 + lambda2 > 1.
  const TextbookTriangle u = textbook_triangle(Vec3(4, 4, 3), Vec3(0, 0, -1), p0, p1, p2);
  EXPECT_EQ(u.lambda1, 0.75);
  EXPECT_EQ(u.lambda2, 0.5);
  EXPECT_FALSE(u.inside());
  // Through P_0 - 0.25 t_1: lambda1 < 0.
  EXPECT_FALSE(textbook_triangle(Vec3(0, 0, 3), Vec3(0, 0, -1), p0, p1, p2).inside());
}

TEST(TextbookIntersect, SphereQuadraticAndItsRoots) {
  // Unit sphere at the origin, ray from (0, 0, -5) along (0, 0, 1):
  // lambda^2 - 10 lambda + 24 = 0, discriminant 4, lambda = 4 or 6.
  const TextbookSphere s = textbook_sphere(Vec3(0, 0, -5), Vec3(0, 0, 1), Vec3(0.0f), 1.0f);
  EXPECT_EQ(s.a, 1.0);
  EXPECT_EQ(s.b, -10.0);
  EXPECT_EQ(s.c, 24.0);
  EXPECT_EQ(s.discriminant, 4.0);
  EXPECT_EQ(s.lambda_near, 4.0);
  EXPECT_EQ(s.lambda_far, 6.0);
  EXPECT_EQ(s.lambda(), 4.0);
  // From the center: c < 0, the roots are -1 and 1, the ray leaves at 1.
  const TextbookSphere inside = textbook_sphere(Vec3(0.0f), Vec3(1, 0, 0), Vec3(0.0f), 1.0f);
  EXPECT_EQ(inside.lambda_near, -1.0);
  EXPECT_EQ(inside.lambda(), 1.0);
  // Passing by at distance 2: discriminant < 0, no real roots.
  const TextbookSphere miss = textbook_sphere(Vec3(2, 0, -5), Vec3(0, 0, 1), Vec3(0.0f), 1.0f);
  EXPECT_LT(miss.discriminant, 0.0);
  EXPECT_FALSE(miss.real_roots());
  EXPECT_EQ(miss.lambda(), -1.0);
}

}  // namespace
