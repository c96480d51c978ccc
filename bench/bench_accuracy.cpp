// bench_accuracy: how accurate are the ray-plane, ray-triangle, ray-sphere and
// ray-capsule results (t, hit point), measured in ulps against an
// extended-precision reference, for RayScope's robust routines and the naive
// textbook formulas, and how often rays spawned at their hits hit the same
// primitive again.
//
// For every primitive, scale s (primitive size) and distance d (ray origin to
// primitive centre) on a log grid, and for two placements of the whole
// configuration (next to the world origin, or translated far away), random
// float rays aimed at the primitive are intersected by
//   naive     the textbook formulas in float: plane t = (p0 - o).n / (d.n);
//             Moller-Trumbore; sphere from b^2 - 4ac with t = (-b - sqrt)/2a
//             (the + root when that is behind the origin); capsule: the
//             infinite cylinder's quadratic in the same form with its root
//             kept between the end planes, else the end spheres' roots beyond
//             them; hit point o + t*d;
//   rayscope  intersect_plane / intersect_triangle / intersect_sphere from
//             rayscope/intersect.h, intersect_capsule from
//             rayscope/intersect_capsule.h, and the hit point
//             Scene::surface_hit uses (plane_point: o + t*d re-projected onto
//             the plane; triangle_point: barycentric interpolation of the
//             vertices; sphere_point and capsule_point: o + t*d re-projected
//             onto the surface in double),
// and compared with the exact answer for the same float inputs, computed in
// __float128 (long double when libquadmath is missing; the program says which).
//
// Errors, in ulps of float:
//   t        |t - t_ref| / ulp(t_ref)
//   point    max_i |p_i - p_ref_i| / ulp(max_i |p_ref_i|): distance from the
//            exact hit point, in ulps of the point's largest coordinate;
//   surface  distance of the computed point from the exact surface (the plane,
//            the triangle's plane, the sphere, the capsule), in the same unit.
//            This is what matters for self-intersection: a point slid along
//            the surface is harmless, one off the surface is not.
// Statistics per cell over the rays that both the method and the reference
// hit: median, 99th percentile (nearest rank) and max. miss_rate is the
// fraction of all rays on which the method and the reference disagree about
// hit or miss. For rayscope, bound_viol is the fraction of hits whose error
// exceeds the bound the hit carries (p_error): per axis for `point`, and along
// the normal (the offset spawn_ray applies, |n|.p_error) for `surface`.
//
// Re-hits: at every hit both the method and the reference find, two rays
// leave the surface on the side the ray came from (the mirror direction and a
// random one; for a sphere or capsule only from outside, where the normal at
// the point faces the ray: inward rays must hit it again), and the method's
// own test is asked whether they hit the same primitive again: naive rays start at o + t*d with the
// textbook normal (no offset: what needs a hand-tuned epsilon), RayScope's are spawn_ray() from the
// hit point, its error bound and normal. The rate of those re-hits is printed per cell and summed
// per primitive (CSV column rehit_rate).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include "rayscope/intersect.h"
#include "rayscope/intersect_capsule.h"
#include "test_util.h"

#ifdef RAYSCOPE_HAVE_QUADMATH
#include <quadmath.h>
#endif

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::naive_sphere;
using rstest::Rng;
using rstest::round_f;
using rstest::to_f;

// ---------------------------------------------------------------------------
// Extended-precision reference arithmetic.

#ifdef RAYSCOPE_HAVE_QUADMATH
using Real = __float128;
Real real_sqrt(Real x) {
  return sqrtq(x);
}
constexpr const char* kReferenceName = "__float128 (libquadmath, 113-bit significand)";
#else
using Real = long double;
Real real_sqrt(Real x) {
  return std::sqrt(x);
}
constexpr const char* kReferenceName = "long double (x87, 64-bit significand; no libquadmath)";
#endif

Real real_abs(Real x) {
  return x < 0 ? -x : x;
}

struct R3 {
  Real x, y, z;
};
R3 rv(const Vec3& v) {
  return {Real(v.x), Real(v.y), Real(v.z)};
}
R3 operator+(const R3& a, const R3& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
R3 operator-(const R3& a, const R3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
R3 operator*(Real s, const R3& a) {
  return {s * a.x, s * a.y, s * a.z};
}
Real dot(const R3& a, const R3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
R3 cross(const R3& a, const R3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Real norm(const R3& a) {
  return real_sqrt(dot(a, a));
}
Real max_abs(const R3& a) {
  return std::max(real_abs(a.x), std::max(real_abs(a.y), real_abs(a.z)));
}

/// The spacing of floats at |x| (the ulp of the float nearest x), as a double.
double float_ulp(double x) {
  x = std::abs(x);
  if (!(x >= std::numeric_limits<float>::min())) return std::ldexp(1.0, -149);
  int e;
  std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1)
  return std::ldexp(1.0, e - 24);
}

/// |a - ref| in ulps of `unit`.
double ulps(Real a, Real ref, Real unit) {
  return double(real_abs(a - ref)) / float_ulp(double(unit));
}

// ---------------------------------------------------------------------------
// Configurations.

enum Prim { kPlane, kTriangle, kSphere, kCapsule, kPrimCount };
const char* const kPrimName[kPrimCount] = {"plane", "triangle", "sphere", "capsule"};
enum Method { kNaive, kRayScope, kMethodCount };
const char* const kMethodName[kMethodCount] = {"naive", "rayscope"};
enum Quantity { kT, kPoint, kSurface, kQuantityCount };
const char* const kQuantityName[kQuantityCount] = {"t", "point", "surface"};
enum Placement { kAtOrigin, kFar, kPlacementCount };
const char* const kPlacementName[kPlacementCount] = {"origin", "far"};

struct Cell {
  Prim prim;
  Placement placement;
  double scale, distance, offset;
};

/// Fewer hits than this in a cell print '-' in the tables (the CSV has all).
constexpr size_t kMinTableSamples = 100;

struct Stats {
  size_t n = 0;
  double median = NAN, p99 = NAN, max = NAN;
};

Stats summarize(std::vector<double>& v) {
  Stats s;
  s.n = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  auto rank = [&](double p) {
    return v[size_t(std::max(1.0, std::ceil(p * double(v.size())))) - 1];
  };
  s.median = rank(0.5);
  s.p99 = rank(0.99);
  s.max = v.back();
  return s;
}

/// Apparent size bins (radians, decades): < 1e-8, [1e-8, 1e-7), ..., >= 1e-2.
constexpr int kSizeBins = 8;
int size_bin(double alpha) {
  return std::clamp(int(std::floor(std::log10(std::max(alpha, 1e-300)))) + 9, 0, kSizeBins - 1);
}

struct CellResult {
  size_t rays = 0, ref_hits = 0;
  // Reference hits and false misses by apparent size of the primitive.
  // [0]: all hits; [1]: triangle hits at |cos incidence| >= 0.3 only.
  size_t size_hits[2][kSizeBins] = {}, size_false_miss[2][kMethodCount][kSizeBins] = {};
  size_t false_miss[kMethodCount] = {}, false_hit[kMethodCount] = {};
  size_t both_hit[kMethodCount] = {};
  size_t bound_viol[kQuantityCount] = {};  // rayscope only
  size_t spawned[kMethodCount] = {}, rehits[kMethodCount] = {};
  Stats stats[kMethodCount][kQuantityCount];
};

// One random primitive and ray, all in float (what the code under test sees).
struct Sample {
  Ray ray;
  // plane: a = point, b = unit normal; triangle: vertices; sphere: a = centre;
  // capsule: a, b = the segment's ends.
  Vec3 a, b, c;
  float radius = 0.0f;
};

DVec3 perpendicular(const DVec3& n) {
  DVec3 h = std::abs(n.x) > 0.9 ? DVec3(0, 1, 0) : DVec3(1, 0, 0);
  return glm::normalize(glm::cross(n, h));
}

/// Uniform point in the unit disc spanned by t, b.
DVec3 disc_point(Rng& rng, const DVec3& t, const DVec3& b) {
  double r = std::sqrt(rng.uniform()), phi = 2.0 * std::numbers::pi * rng.uniform();
  return r * std::cos(phi) * t + r * std::sin(phi) * b;
}

/// A primitive of size `s` centred at `offset` times a random direction, and a
/// ray from a point at distance `d` from its centre toward a random point of it.
/// Positions are rounded to float first and the aim is computed from the
/// rounded values, so the ray misses only when float cannot aim it (d/s beyond
/// ~1e7) or at a silhouette/edge.
Sample make_sample(Rng& rng, const Cell& cell) {
  const double s = cell.scale, d = cell.distance;
  const DVec3 centre = cell.offset * rng.unit_vector();
  const DVec3 n = rng.unit_vector(), t = perpendicular(n), b = glm::cross(n, t);
  Sample sm;
  const Vec3 o = to_f(centre + d * rng.unit_vector());
  DVec3 target;
  switch (cell.prim) {
    case kPlane: {
      sm.a = to_f(centre);
      sm.b = glm::normalize(to_f(n));  // as Scene::commit normalises plane normals
      target = DVec3(sm.a) + 0.5 * s * disc_point(rng, t, b);
      break;
    }
    case kTriangle: {
      Vec3* v[3] = {&sm.a, &sm.b, &sm.c};
      for (int k = 0; k < 3; ++k) {
        double phi = 2.0 * std::numbers::pi * k / 3.0 + rng.uniform(-0.4, 0.4);
        *v[k] = to_f(centre + 0.5 * s * (std::cos(phi) * t + std::sin(phi) * b));
      }
      double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
      target = (1.0 - r1) * DVec3(sm.a) + r1 * (1.0 - r2) * DVec3(sm.b) + r1 * r2 * DVec3(sm.c);
      break;
    }
    case kCapsule: {
      // Length s/2 and radius s/4 (its extent is s), along n; aimed at a
      // point of its silhouette: a point of the segment plus a point of the
      // disc of radius r facing the origin.
      sm.a = to_f(centre - 0.25 * s * n);
      sm.b = to_f(centre + 0.25 * s * n);
      sm.radius = round_f(0.25 * s);
      const DVec3 on_axis = DVec3(sm.a) + rng.uniform() * (DVec3(sm.b) - DVec3(sm.a));
      DVec3 view = DVec3(o) - on_axis;
      if (glm::dot(view, view) == 0.0) view = t;
      view = glm::normalize(view);
      DVec3 vt = perpendicular(view), vb = glm::cross(view, vt);
      target = on_axis + double(sm.radius) * disc_point(rng, vt, vb);
      break;
    }
    default: {
      sm.a = to_f(centre);
      sm.radius = round_f(0.5 * s);
      DVec3 view = DVec3(o) - DVec3(sm.a);
      if (glm::dot(view, view) == 0.0) view = n;
      view = glm::normalize(view);
      DVec3 vt = perpendicular(view), vb = glm::cross(view, vt);
      target = DVec3(sm.a) + double(sm.radius) * disc_point(rng, vt, vb);
      break;
    }
  }
  DVec3 dir = target - DVec3(o);
  if (glm::dot(dir, dir) == 0.0) dir = n;
  sm.ray = Ray{o, to_f(glm::normalize(dir)), kInfinity};
  return sm;
}

// ---------------------------------------------------------------------------
// The naive textbook formulas, in float (the sphere's, shared with
// test_intersect, is rstest::naive_sphere in tests/test_util.h).

bool naive_plane(const Ray& r, const Vec3& p0, const Vec3& n, float& t) {
  float denom = glm::dot(r.dir, n);
  if (denom == 0.0f) return false;
  t = glm::dot(p0 - r.origin, n) / denom;
  return t > 0.0f;
}

// Moller-Trumbore (1997), with exact-zero tests instead of the paper's
// EPSILON = 1e-6 (which would reject every triangle with det < 1e-6, i.e.
// all triangles smaller than ~1e-3 for unit directions).
bool naive_triangle(const Ray& r, const Vec3& p0, const Vec3& p1, const Vec3& p2, float& t) {
  Vec3 e1 = p1 - p0, e2 = p2 - p0;
  Vec3 pv = glm::cross(r.dir, e2);
  float det = glm::dot(e1, pv);
  if (det == 0.0f) return false;
  float inv = 1.0f / det;
  Vec3 tv = r.origin - p0;
  float u = glm::dot(tv, pv) * inv;
  if (u < 0.0f || u > 1.0f) return false;
  Vec3 qv = glm::cross(tv, e1);
  float v = glm::dot(r.dir, qv) * inv;
  if (v < 0.0f || u + v > 1.0f) return false;
  t = glm::dot(e2, qv) * inv;
  return t > 0.0f;
}

// The capsule the textbook way: the infinite cylinder around the segment
// a b, |(f + t d) x e|^2 = r^2 |e|^2 with f = o - a, e = b - a, expanded into
// a quadratic in float, its root kept where it lies between the end planes;
// else the end spheres (naive_sphere), each root kept beyond its end plane.
bool naive_capsule(const Ray& r, const Vec3& a, const Vec3& b, float radius, float& t) {
  const Vec3 e = b - a, f = r.origin - a;
  const float ee = glm::dot(e, e), de = glm::dot(r.dir, e), fe = glm::dot(f, e);
  const float qa = ee * glm::dot(r.dir, r.dir) - de * de;
  const float qb = ee * glm::dot(f, r.dir) - fe * de;
  const float qc = ee * glm::dot(f, f) - fe * fe - radius * radius * ee;
  const float disc = qb * qb - qa * qc;
  float best = kInfinity;
  if (qa != 0.0f && disc >= 0.0f) {
    for (const float tc : {(-qb - std::sqrt(disc)) / qa, (-qb + std::sqrt(disc)) / qa}) {
      const float y = fe + tc * de;
      if (tc > 0.0f && y >= 0.0f && y <= ee) {
        best = std::min(best, tc);
        break;
      }
    }
  }
  for (int end = 0; end < 2; ++end) {
    float ts;
    if (!naive_sphere(r, end ? b : a, radius, ts)) continue;
    const float y = fe + ts * de;
    if (end ? y >= ee : y <= 0.0f) best = std::min(best, ts);
  }
  if (!(best < kInfinity)) return false;
  t = best;
  return true;
}

// ---------------------------------------------------------------------------
// The exact answer for the float inputs, in Real.

/// The interval of the line o + t d in the capsule around a b with radius r:
/// the hull of the end balls' intervals and of the infinite cylinder's cut
/// to the slab between the end planes (textbook formulas: Real has the bits).
bool ref_capsule(const R3& o, const R3& d, const R3& a, const R3& b, Real r, Real& t_in,
                 Real& t_out) {
  bool hit = false;
  auto take = [&](Real lo, Real hi) {
    if (!hit || lo < t_in) t_in = lo;
    if (!hit || hi > t_out) t_out = hi;
    hit = true;
  };
  auto quadric = [&](const R3& f, const R3& v, Real& lo, Real& hi) {
    const Real qa = dot(v, v), qb = dot(f, v), qc = dot(f, f) - r * r;
    const Real disc = qb * qb - qa * qc;
    if (!(qa > 0) || disc < 0) return false;
    lo = (-qb - real_sqrt(disc)) / qa;
    hi = (-qb + real_sqrt(disc)) / qa;
    return true;
  };
  Real lo = 0, hi = 0;
  if (quadric(o - a, d, lo, hi)) take(lo, hi);
  const R3 e = b - a;
  const Real ee = dot(e, e);
  if (!(ee > 0)) return hit;
  if (quadric(o - b, d, lo, hi)) take(lo, hi);
  const R3 f = o - a;
  const Real de = dot(d, e), fe = dot(f, e);
  const R3 dp = d - (de / ee) * e, fp = f - (fe / ee) * e;
  Real c0, c1;
  if (!quadric(fp, dp, c0, c1)) return hit;  // parallel to the axis: the balls decide
  if (de == 0) return hit;
  Real s0 = -fe / de, s1 = (ee - fe) / de;
  if (s0 > s1) std::swap(s0, s1);
  lo = std::max(c0, s0);
  hi = std::min(c1, s1);
  if (lo <= hi) take(lo, hi);
  return hit;
}

/// Distance from p to the segment a b.
Real segment_distance(const R3& p, const R3& a, const R3& b) {
  const R3 e = b - a;
  const Real ee = dot(e, e);
  Real s = ee > 0 ? dot(p - a, e) / ee : Real(0);
  s = s < 0 ? Real(0) : (s > 1 ? Real(1) : s);
  return norm(p - (a + s * e));
}

struct RefHit {
  Real t;
  R3 p;
};

bool reference(const Sample& sm, Prim prim, RefHit& h) {
  const R3 o = rv(sm.ray.origin), d = rv(sm.ray.dir);
  switch (prim) {
    case kPlane: {
      const R3 p0 = rv(sm.a), n = rv(sm.b);
      Real denom = dot(d, n);
      if (denom == 0) return false;
      h.t = dot(p0 - o, n) / denom;
      break;
    }
    case kTriangle: {  // Moller-Trumbore in Real; inside test with exact signs.
      const R3 p0 = rv(sm.a), e1 = rv(sm.b) - p0, e2 = rv(sm.c) - p0;
      R3 pv = cross(d, e2);
      Real det = dot(e1, pv);
      if (det == 0) return false;
      R3 tv = o - p0, qv = cross(tv, e1);
      Real u = dot(tv, pv) / det, v = dot(d, qv) / det;
      if (u < 0 || v < 0 || u + v > 1) return false;
      h.t = dot(e2, qv) / det;
      break;
    }
    case kCapsule: {
      Real t_in = 0, t_out = 0;
      if (!ref_capsule(o, d, rv(sm.a), rv(sm.b), Real(sm.radius), t_in, t_out)) return false;
      h.t = t_in > 0 ? t_in : t_out;
      break;
    }
    default: {  // closest approach of the line to the centre, then +-half chord
      const R3 f = o - rv(sm.a);
      Real a = dot(d, d), tc = -dot(f, d) / a;
      R3 l = f + tc * d;
      Real r = Real(sm.radius), h2 = r * r - dot(l, l);
      if (h2 < 0) return false;
      Real half = real_sqrt(h2 / a);
      h.t = tc - half > 0 ? tc - half : tc + half;
      break;
    }
  }
  if (!(h.t > 0)) return false;
  h.p = o + h.t * d;
  return true;
}

/// Distance of p from the exact surface of the primitive (for the triangle,
/// from its plane).
Real surface_distance(const Sample& sm, Prim prim, const R3& p) {
  switch (prim) {
    case kPlane: {
      R3 n = rv(sm.b);
      return real_abs(dot(p - rv(sm.a), n)) / norm(n);
    }
    case kTriangle: {
      R3 p0 = rv(sm.a), n = cross(rv(sm.b) - p0, rv(sm.c) - p0);
      return real_abs(dot(p - p0, n)) / norm(n);
    }
    case kCapsule:
      return real_abs(segment_distance(p, rv(sm.a), rv(sm.b)) - Real(sm.radius));
    default:
      return real_abs(norm(p - rv(sm.a)) - Real(sm.radius));
  }
}

/// The method's own test of the sample's primitive against another ray
/// (t > 0, any distance).
bool hits_again(Method m, const Sample& sm, Prim prim, const Ray& r) {
  float t;
  switch (prim) {
    case kPlane:
      return m == kNaive ? naive_plane(r, sm.a, sm.b, t)
                         : intersect_plane(r, sm.a, sm.b, kInfinity, t);
    case kTriangle: {
      if (m == kNaive) return naive_triangle(r, sm.a, sm.b, sm.c, t);
      TriangleHit th;
      return intersect_triangle(TrianglePrecomp(r), kInfinity, sm.a, sm.b, sm.c, th);
    }
    case kCapsule:
      return m == kNaive ? naive_capsule(r, sm.a, sm.b, sm.radius, t)
                         : intersect_capsule(r, sm.a, sm.b, sm.radius, kInfinity, t);
    default:
      return m == kNaive ? naive_sphere(r, sm.a, sm.radius, t)
                         : intersect_sphere(r, sm.a, sm.radius, kInfinity, t);
  }
}

/// The textbook normal at a naive hit point (unit, not face-forwarded).
Vec3 naive_normal(const Sample& sm, Prim prim, const Vec3& p) {
  switch (prim) {
    case kPlane:
      return sm.b;
    case kTriangle:
      return glm::normalize(glm::cross(sm.b - sm.a, sm.c - sm.a));
    case kCapsule: {
      const Vec3 e = sm.b - sm.a;
      const float ee = glm::dot(e, e);
      const float s = ee > 0.0f ? std::clamp(glm::dot(p - sm.a, e) / ee, 0.0f, 1.0f) : 0.0f;
      return glm::normalize(p - (sm.a + s * e));
    }
    default:
      return glm::normalize(p - sm.a);
  }
}

// ---------------------------------------------------------------------------

CellResult run_cell(const Cell& cell, int rays, uint32_t seed) {
  Rng rng(seed);
  // The spawned rays' random directions come from a stream of their own, so
  // that the samples are those of the runs before re-hits were counted.
  Rng spawn_rng(seed ^ 0x9e3779b9u);
  CellResult res;
  std::vector<double> err[kMethodCount][kQuantityCount];
  for (int i = 0; i < rays; ++i) {
    const Sample sm = make_sample(rng, cell);
    const Ray& ray = sm.ray;
    RefHit ref{};
    const bool ref_hit = reference(sm, cell.prim, ref);
    const bool origin_inside =
        cell.prim == kSphere ? norm(rv(ray.origin) - rv(sm.a)) < Real(sm.radius)
        : cell.prim == kCapsule
            ? segment_distance(rv(ray.origin), rv(sm.a), rv(sm.b)) < Real(sm.radius)
            : false;
    res.rays++;
    res.ref_hits += ref_hit;

    bool hit[kMethodCount];
    float t[kMethodCount] = {0.0f, 0.0f};
    Vec3 p[kMethodCount], p_error(0.0f), ng(0.0f);
    switch (cell.prim) {
      case kPlane:
        hit[kNaive] = naive_plane(ray, sm.a, sm.b, t[kNaive]);
        hit[kRayScope] = intersect_plane(ray, sm.a, sm.b, kInfinity, t[kRayScope]);
        if (hit[kRayScope]) p[kRayScope] = plane_point(ray, t[kRayScope], sm.a, sm.b, p_error);
        ng = sm.b;
        break;
      case kTriangle: {
        hit[kNaive] = naive_triangle(ray, sm.a, sm.b, sm.c, t[kNaive]);
        TriangleHit th{};
        hit[kRayScope] = intersect_triangle(TrianglePrecomp(ray), kInfinity, sm.a, sm.b, sm.c, th);
        if (hit[kRayScope]) {
          t[kRayScope] = th.t;
          p[kRayScope] = triangle_point(th, sm.a, sm.b, sm.c, p_error);
        }
        ng = glm::normalize(glm::cross(sm.b - sm.a, sm.c - sm.a));  // as Scene::surface_hit
        break;
      }
      case kCapsule:
        hit[kNaive] = naive_capsule(ray, sm.a, sm.b, sm.radius, t[kNaive]);
        hit[kRayScope] = intersect_capsule(ray, sm.a, sm.b, sm.radius, kInfinity, t[kRayScope]);
        if (hit[kRayScope]) {
          float along;
          p[kRayScope] =
              capsule_point(ray, t[kRayScope], sm.a, sm.b, sm.radius, p_error, ng, along);
        }
        break;
      default:
        hit[kNaive] = naive_sphere(ray, sm.a, sm.radius, t[kNaive]);
        hit[kRayScope] = intersect_sphere(ray, sm.a, sm.radius, kInfinity, t[kRayScope]);
        if (hit[kRayScope]) {
          p[kRayScope] = sphere_point(ray, t[kRayScope], sm.a, sm.radius, p_error, ng);
        }
        break;
    }
    if (hit[kNaive]) p[kNaive] = ray.origin + t[kNaive] * ray.dir;

    // Apparent size seen from the origin, in radians: for the triangle its
    // apparent height over its longest edge, 2 area |cos| / (longest edge * t),
    // ~ s/t head-on and ~ s |cos| / t at grazing incidence; for the sphere its
    // angular radius (the plane is unbounded).
    int bin = -1;
    bool head_on = false;
    if (ref_hit && cell.prim == kTriangle) {
      const DVec3 a(sm.a), b(sm.b), c(sm.c), dir(ray.dir);
      const DVec3 n = glm::cross(b - a, c - a);  // |n| = 2 area
      const double longest =
          std::max(glm::length(b - a), std::max(glm::length(c - b), glm::length(a - c)));
      const double cos_incidence = std::abs(glm::dot(n, dir)) / (glm::length(n) * glm::length(dir));
      bin = size_bin(glm::length(n) * cos_incidence / (longest * double(ref.t)));
      head_on = cos_incidence >= 0.3;
    } else if (ref_hit && cell.prim == kSphere) {
      bin = size_bin(double(sm.radius) / glm::length(DVec3(ray.origin) - DVec3(sm.a)));
    } else if (ref_hit && cell.prim == kCapsule) {
      const Real dist = segment_distance(rv(ray.origin), rv(sm.a), rv(sm.b));
      bin = size_bin(double(sm.radius) / double(dist));
    }
    if (bin >= 0) res.size_hits[0][bin]++;
    if (head_on) res.size_hits[1][bin]++;
    for (int m = 0; m < kMethodCount; ++m) {
      if (hit[m] != ref_hit) {
        if (ref_hit && bin >= 0) res.size_false_miss[0][m][bin]++;
        if (ref_hit && head_on) res.size_false_miss[1][m][bin]++;
        (ref_hit ? res.false_miss : res.false_hit)[m]++;
        continue;
      }
      if (!ref_hit) continue;
      res.both_hit[m]++;
      const R3 pm = rv(p[m]);
      const Real unit = max_abs(ref.p);
      const Real dp = max_abs(pm - ref.p), ds = surface_distance(sm, cell.prim, pm);
      err[m][kT].push_back(ulps(Real(t[m]), ref.t, ref.t));
      err[m][kPoint].push_back(double(dp) / float_ulp(double(unit)));
      err[m][kSurface].push_back(double(ds) / float_ulp(double(unit)));
      if (m == kRayScope) {
        const R3 e = pm - ref.p;
        if (real_abs(e.x) > p_error.x || real_abs(e.y) > p_error.y || real_abs(e.z) > p_error.z)
          res.bound_viol[kPoint]++;
        if (ds > Real(glm::dot(glm::abs(ng), p_error))) res.bound_viol[kSurface]++;
      }
      // Two rays leaving the surface on the ray's side: the mirror direction
      // and a random one. Not from inside a sphere or capsule (rays leaving
      // its surface inward must hit it again), nor where its outward normal
      // at the point faces away from the ray (beyond d/s ~ 1e7 the rounding
      // of t exceeds the primitive and the point may land on its far side,
      // which test_self_intersection skips alike).
      if (origin_inside) continue;
      Vec3 n = m == kRayScope ? ng : naive_normal(sm, cell.prim, p[m]);
      if (!all_finite(n)) continue;
      const bool closed = cell.prim == kSphere || cell.prim == kCapsule;
      if (closed && !(glm::dot(n, ray.dir) < 0.0f)) continue;
      if (glm::dot(n, ray.dir) > 0.0f) n = -n;
      Vec3 w[2] = {ray.dir - 2.0f * glm::dot(ray.dir, n) * n, to_f(spawn_rng.unit_vector())};
      if (glm::dot(w[1], n) < 0.0f) w[1] = -w[1];
      for (const Vec3& wk : w) {
        if (!(glm::dot(wk, n) > 0.0f)) continue;
        const Ray out = m == kRayScope ? spawn_ray(p[m], p_error, n, wk) : Ray{p[m], wk, kInfinity};
        res.spawned[m]++;
        res.rehits[m] += hits_again(Method(m), sm, cell.prim, out);
      }
    }
  }
  for (int m = 0; m < kMethodCount; ++m)
    for (int q = 0; q < kQuantityCount; ++q) res.stats[m][q] = summarize(err[m][q]);
  return res;
}

// ---------------------------------------------------------------------------
// Output.

/// Compact number: 2 significant digits, exponent without '+' and leading zeros.
std::string fmt(double x) {
  if (std::isnan(x)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", x);
  std::string s = buf;
  auto e = s.find('e');
  if (e != std::string::npos) {
    std::string mant = s.substr(0, e), ex = s.substr(e + 1);
    bool neg = ex[0] == '-';
    ex = ex.substr(1);
    while (ex.size() > 1 && ex[0] == '0') ex.erase(0, 1);
    s = mant + "e" + (neg ? "-" : "") + ex;
  }
  return s;
}

/// Percentages: whole numbers from 10 up, else as fmt().
std::string fmt_pct(double x) {
  if (x < 10.0) return fmt(x);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f", x);
  return buf;
}

std::string csv_num(double x) {
  if (std::isnan(x)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

void write_csv(const std::filesystem::path& path, const std::vector<Cell>& cells,
               const std::vector<CellResult>& results) {
  namespace fs = std::filesystem;
  fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  fs::path tmp = dir / ("." + path.filename().string() + ".tmp" + std::to_string(::getpid()));
  {
    std::ofstream out(tmp);
    if (!out) throw std::runtime_error(path.string() + ": cannot create temporary file");
    out << "primitive,method,quantity,scale,distance,placement,offset,rays,ref_hits,n,"
           "median_ulps,p99_ulps,max_ulps,miss_rate,false_miss,false_hit,bound_viol,rehit_rate\n";
    for (size_t i = 0; i < cells.size(); ++i) {
      const Cell& c = cells[i];
      const CellResult& r = results[i];
      for (int m = 0; m < kMethodCount; ++m)
        for (int q = 0; q < kQuantityCount; ++q) {
          const Stats& s = r.stats[m][q];
          double miss = double(r.false_miss[m] + r.false_hit[m]) / double(r.rays);
          std::string viol;
          if (m == kRayScope && q != kT)
            viol = csv_num(r.both_hit[m] ? double(r.bound_viol[q]) / double(r.both_hit[m]) : NAN);
          out << kPrimName[c.prim] << ',' << kMethodName[m] << ',' << kQuantityName[q] << ','
              << csv_num(c.scale) << ',' << csv_num(c.distance) << ','
              << kPlacementName[c.placement] << ',' << csv_num(c.offset) << ',' << r.rays << ','
              << r.ref_hits << ',' << s.n << ',' << csv_num(s.median) << ',' << csv_num(s.p99)
              << ',' << csv_num(s.max) << ',' << csv_num(miss) << ',' << r.false_miss[m] << ','
              << r.false_hit[m] << ',' << viol << ','
              << csv_num(r.spawned[m] ? double(r.rehits[m]) / double(r.spawned[m]) : NAN) << '\n';
        }
    }
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error(path.string() + ": write failed");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    const std::string why = ec.message();
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": cannot rename temporary file: " + why);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "bench_accuracy: error of ray-plane/triangle/sphere/capsule t and hit points in ulps "
      "against an extended-precision reference, naive textbook formulas vs RayScope, and "
      "re-hits of spawned rays"};
  int rays = 10000;
  uint32_t seed = 1;
  int step = 2;
  double far_factor = 1e4;
  std::string csv;
  app.add_option("--rays", rays, "random rays per grid cell")->check(CLI::Range(1, 10000000));
  app.add_option("--seed", seed, "random seed");
  app.add_option("--step", step, "grid step in decades (scales and distances 1e-6..1e6)")
      ->check(CLI::Range(1, 12));
  app.add_option("--far", far_factor,
                 "'far' placement: offset of the configuration = FAR * max(scale, distance)")
      ->check(CLI::Range(1.0, 1e12));
  app.add_option("--csv", csv, "write every cell to this CSV file (atomically)");
  CLI11_PARSE(app, argc, argv);

  if (!csv.empty()) {
    std::filesystem::path dir = std::filesystem::path(csv).parent_path();
    if (!dir.empty() && !std::filesystem::is_directory(dir)) {
      std::fprintf(stderr, "bench_accuracy: %s: directory does not exist\n", csv.c_str());
      return 1;
    }
    if (std::filesystem::is_directory(csv)) {
      std::fprintf(stderr, "bench_accuracy: %s: is a directory\n", csv.c_str());
      return 1;
    }
  }

  std::vector<double> grid;
  for (int e = -6; e <= 6; e += step) grid.push_back(std::pow(10.0, e));
  std::vector<Cell> cells;
  for (int pr = 0; pr < kPrimCount; ++pr)
    for (int pl = 0; pl < kPlacementCount; ++pl)
      for (double s : grid)
        for (double d : grid)
          cells.push_back(Cell{Prim(pr), Placement(pl), s, d,
                               pl == kAtOrigin ? s : far_factor * std::max(s, d)});

  const auto start = std::chrono::steady_clock::now();
  std::vector<CellResult> results(cells.size());
  tbb::parallel_for(size_t(0), cells.size(), [&](size_t i) {
    results[i] = run_cell(cells[i], rays, seed * 2654435761u + uint32_t(i));
  });
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::printf("bench_accuracy: %d rays per cell, %zu cells, seed %u, %.1f s\n", rays, cells.size(),
              seed, secs);
  std::printf("reference: %s\n", kReferenceName);
  std::printf(
      "placement 'origin': primitive centre at distance = scale from the world origin;\n"
      "placement 'far': at %g * max(scale, distance).\n"
      "ref hit%%: rays that hit according to the reference. Other entries: naive/rayscope.\n"
      "Errors are 99th percentiles in ulps (t: of t; point: distance to the exact hit point;\n"
      "surface: distance from the exact surface; both in ulps of the point's largest\n"
      "coordinate), '-' with fewer than %zu hits. miss%%: rays where method and reference\n"
      "disagree about hit or miss.\n",
      far_factor, kMinTableSamples);

  const size_t ng = grid.size();
  // One matrix per quantity: rows are scales, columns distances.
  auto matrix = [&](size_t base, const char* title, auto&& entry) {
    std::printf("\n  %-14s", title);
    for (double d : grid) std::printf("%13s", ("d=" + fmt(d)).c_str());
    std::printf("\n");
    for (size_t si = 0; si < ng; ++si) {
      std::printf("  s=%-12s", fmt(grid[si]).c_str());
      for (size_t di = 0; di < ng; ++di)
        std::printf("%13s", entry(results[base + si * ng + di]).c_str());
      std::printf("\n");
    }
  };
  auto both = [](auto&& f) {
    return [f](const CellResult& r) { return f(r, kNaive) + "/" + f(r, kRayScope); };
  };
  for (int pr = 0; pr < kPrimCount; ++pr)
    for (int pl = 0; pl < kPlacementCount; ++pl) {
      const size_t base = (size_t(pr) * kPlacementCount + size_t(pl)) * ng * ng;
      std::printf("\n== %s, placement %s ==\n", kPrimName[pr], kPlacementName[pl]);
      matrix(base, "ref hit%", [](const CellResult& r) {
        return fmt_pct(100.0 * double(r.ref_hits) / double(r.rays));
      });
      for (int q = 0; q < kQuantityCount; ++q) {
        std::string title = std::string(kQuantityName[q]) + " p99";
        matrix(base, title.c_str(), both([q](const CellResult& r, int m) {
                 const Stats& st = r.stats[m][q];
                 return st.n >= kMinTableSamples ? fmt(st.p99) : std::string("-");
               }));
      }
      matrix(base, "miss%", both([](const CellResult& r, int m) {
               return fmt_pct(100.0 * double(r.false_miss[m] + r.false_hit[m]) / double(r.rays));
             }));
      matrix(base, "re-hit%", both([](const CellResult& r, int m) {
               return r.spawned[m] ? fmt_pct(100.0 * double(r.rehits[m]) / double(r.spawned[m]))
                                   : std::string("-");
             }));
    }

  // Re-hits of spawned rays, summed over each primitive's cells.
  std::printf(
      "\nRe-hits of rays spawned at hits (the mirror direction and a random one, leaving on the\n"
      "ray's side; spheres and capsules: rays from outside at points facing the ray; naive:\n"
      "from o + t*d with no offset, rayscope: spawn_ray), all cells:\n");
  std::printf("  %-10s %-9s %12s %12s %10s\n", "primitive", "placement", "spawned", "re-hits",
              "re-hit %");
  for (int pr = 0; pr < kPrimCount; ++pr)
    for (int pl = 0; pl < kPlacementCount; ++pl)
      for (int m = 0; m < kMethodCount; ++m) {
        size_t spawned = 0, rehits = 0;
        for (size_t i = 0; i < cells.size(); ++i) {
          if (cells[i].prim != pr || cells[i].placement != pl) continue;
          spawned += results[i].spawned[m];
          rehits += results[i].rehits[m];
        }
        std::printf("  %-10s %-9s %12zu %12zu %10s  %s\n", kPrimName[pr], kPlacementName[pl],
                    spawned, rehits,
                    spawned ? fmt_pct(100.0 * double(rehits) / double(spawned)).c_str() : "-",
                    kMethodName[m]);
      }

  // False misses by apparent size, over all cells of the 'origin' placement.
  std::printf(
      "\nFalse misses (reference hits, method misses) by apparent size of the primitive seen\n"
      "from the ray origin, placement origin, all cells (radians; triangle: projected height over\n"
      "its longest edge / t = 2 area |cos| / (longest edge * t); sphere: radius / distance;\n"
      "capsule: radius / distance to its segment). |cos|>=0.3: only rays within 72 degrees of\n"
      "the normal. Columns: reference hits, naive %%, rayscope %%.\n");
  std::printf("  %-18s%28s%28s%28s%28s\n", "apparent size", "triangle", "triangle |cos|>=0.3",
              "sphere", "capsule");
  for (int b = 0; b < kSizeBins; ++b) {
    std::string label = b == 0 ? "< 1e-8"
                        : b == kSizeBins - 1
                            ? ">= 1e-2"
                            : fmt(std::pow(10.0, b - 9)) + " .. " + fmt(std::pow(10.0, b - 8));
    std::printf("  %-18s", label.c_str());
    for (auto [pr, subset] : {std::pair{kTriangle, 0}, std::pair{kTriangle, 1},
                              std::pair{kSphere, 0}, std::pair{kCapsule, 0}}) {
      size_t hits = 0, fm[kMethodCount] = {};
      for (size_t i = 0; i < cells.size(); ++i) {
        if (cells[i].prim != pr || cells[i].placement != kAtOrigin) continue;
        hits += results[i].size_hits[subset][b];
        for (int m = 0; m < kMethodCount; ++m) fm[m] += results[i].size_false_miss[subset][m][b];
      }
      auto pct = [&](size_t k) { return hits ? fmt_pct(100.0 * double(k) / double(hits)) : "-"; };
      std::printf("%12zu%8s%8s", hits, pct(fm[kNaive]).c_str(), pct(fm[kRayScope]).c_str());
    }
    std::printf("\n");
  }

  if (!csv.empty()) {
    try {
      write_csv(csv, cells, results);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_accuracy: %s\n", e.what());
      return 1;
    }
    std::printf("\nwrote %s\n", csv.c_str());
  }
  return 0;
}
