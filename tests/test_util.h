// Helpers shared by the RayScope tests: a seeded random source and
// double-precision reference computations. Every reference takes the float
// inputs the code under test sees, converts them exactly to double and works
// there, so its own error (~1e-16 relative) is negligible against float's
// 6e-8 and the difference to the tested result is the tested code's error.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include "rayscope/math.h"
#include "rayscope/ray.h"
#include "rayscope/render_settings.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define RAYSCOPE_TEST_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer)
#define RAYSCOPE_TEST_SANITIZED 1
#endif
#endif

namespace rstest {

/// How much of its full work a numerical stress test does: tracing is 10-50x
/// slower under sanitizers and without optimisation, so ray counts scale by
/// this factor (every check stays the same; only how many cases are tried
/// changes). RAYSCOPE_STRESS_SCALE from the environment if set (in (0, 1],
/// e.g. 0.1), else 0.1 under AddressSanitizer/ThreadSanitizer or without
/// optimisation, 1 otherwise.
inline double stress_scale() {
  static const double scale = [] {
    if (const char* s = std::getenv("RAYSCOPE_STRESS_SCALE")) {
      char* end = nullptr;
      double v = std::strtod(s, &end);
      if (end != s && std::isfinite(v) && v > 0.0) return std::min(v, 1.0);
    }
#if defined(RAYSCOPE_TEST_SANITIZED) || !defined(__OPTIMIZE__)
    return 0.1;
#else
    return 1.0;
#endif
  }();
  return scale;
}

/// n scaled by stress_scale(), at least 1.
inline size_t stress_scaled(size_t n) {
  return std::max<size_t>(1, size_t(double(n) * stress_scale()));
}

/// Every how many cases a stress test takes when it thins a fixed set (a
/// mesh's triangles or vertices) by stress_scale(): 1 / scale, at least 1.
inline size_t stress_stride() {
  return std::max<size_t>(1, size_t(std::lround(1.0 / stress_scale())));
}

using rayscope::Vec3;
using DVec3 = glm::dvec3;

inline DVec3 to_d(const Vec3& v) {
  return DVec3(v);
}

/// Seeded random numbers (std::mt19937 with a fixed seed: every run of a test
/// sees the same cases, so a failure can be reproduced).
class Rng {
 public:
  explicit Rng(uint32_t seed) : gen_(seed) {}

  double uniform(double lo = 0.0, double hi = 1.0) {
    return std::uniform_real_distribution<double>(lo, hi)(gen_);
  }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(gen_); }
  bool coin() { return integer(0, 1) == 1; }
  /// |x| log-uniform in [lo, hi], random sign.
  double log_uniform_signed(double lo, double hi) {
    double m = std::pow(10.0, uniform(std::log10(lo), std::log10(hi)));
    return coin() ? m : -m;
  }
  double log_uniform(double lo, double hi) {
    return std::pow(10.0, uniform(std::log10(lo), std::log10(hi)));
  }
  /// Uniformly distributed unit vector (double).
  DVec3 unit_vector() {
    std::normal_distribution<double> n(0.0, 1.0);
    for (;;) {
      DVec3 v(n(gen_), n(gen_), n(gen_));
      double l = glm::length(v);
      if (l > 1e-6) return v / l;
    }
  }
  /// Uniform point in the unit ball (double).
  DVec3 in_unit_ball() {
    for (;;) {
      DVec3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
      if (glm::dot(v, v) <= 1.0) return v;
    }
  }
  std::mt19937& engine() { return gen_; }

 private:
  std::mt19937 gen_;
};

/// Ray-triangle intersection in double (Moller-Trumbore). Returns false for a
/// miss or a ray parallel to the plane; fills t and the barycentrics (b0, b1,
/// b2) of p0, p1, p2. `edge_margin` receives the smallest barycentric: negative
/// outside the triangle, its magnitude is the relative distance from the
/// nearest edge line.
struct RefTriHit {
  double t = 0.0, b0 = 0.0, b1 = 0.0, b2 = 0.0;
  double min_bary = 0.0;
  bool front_of_origin = false;
};
inline bool ref_ray_plane_of_triangle(const DVec3& o, const DVec3& d, const DVec3& p0,
                                      const DVec3& p1, const DVec3& p2, RefTriHit& h) {
  DVec3 e1 = p1 - p0, e2 = p2 - p0;
  DVec3 pv = glm::cross(d, e2);
  double det = glm::dot(e1, pv);
  if (det == 0.0) return false;
  double inv = 1.0 / det;
  DVec3 tv = o - p0;
  double u = glm::dot(tv, pv) * inv;
  DVec3 qv = glm::cross(tv, e1);
  double v = glm::dot(d, qv) * inv;
  h.t = glm::dot(e2, qv) * inv;
  h.b1 = u;
  h.b2 = v;
  h.b0 = 1.0 - u - v;
  h.min_bary = std::min(h.b0, std::min(h.b1, h.b2));
  h.front_of_origin = h.t > 0.0;
  return true;
}

/// Ray-sphere in double, via the closest approach of the line to the center.
/// Returns false if the line misses; t0 <= t1 are the two roots, `impact` is the
/// distance of the line from the center.
inline bool ref_ray_sphere(const DVec3& o, const DVec3& d, const DVec3& c, double r, double& t0,
                           double& t1, double& impact) {
  DVec3 f = o - c;
  double a = glm::dot(d, d);
  double tc = -glm::dot(f, d) / a;  // parameter of the closest approach
  DVec3 l = f + tc * d;
  impact = glm::length(l);
  double h2 = r * r - glm::dot(l, l);
  if (h2 < 0.0) return false;
  double h = std::sqrt(h2 / a);
  t0 = tc - h;
  t1 = tc + h;
  return true;
}

/// Long double vectors for the capsule references (64-bit significands: 40
/// bits beyond float, room for the cancellations of the textbook formulas).
using LDVec3 = glm::vec<3, long double>;
inline LDVec3 to_ld(const Vec3& v) {
  return LDVec3(v.x, v.y, v.z);
}

/// Distance from p to the segment a b, in long double.
inline long double ref_segment_distance(const LDVec3& p, const LDVec3& a, const LDVec3& b) {
  const LDVec3 e = b - a;
  const long double ee = glm::dot(e, e);
  const long double s = ee > 0 ? std::clamp(glm::dot(p - a, e) / ee, 0.0L, 1.0L) : 0.0L;
  return glm::length(p - (a + s * e));
}

/// The interval [t_in, t_out] of the line o + t d in the capsule around the
/// segment p0 p1 with radius r, in long double by the textbook formulas: the
/// hull of the end balls' intervals and of the infinite cylinder's interval
/// cut to the slab between the end planes. False when the line misses it.
inline bool ref_capsule_interval(const LDVec3& o, const LDVec3& d, const LDVec3& p0,
                                 const LDVec3& p1, long double r, long double& t_in,
                                 long double& t_out) {
  bool hit = false;
  t_in = INFINITY;
  t_out = -INFINITY;
  auto take = [&](long double lo, long double hi) {
    t_in = std::min(t_in, lo);
    t_out = std::max(t_out, hi);
    hit = true;
  };
  // Roots of |f + t v|^2 = r^2.
  auto quadric = [&](const LDVec3& f, const LDVec3& v, long double& lo, long double& hi) {
    const long double a = glm::dot(v, v), b = glm::dot(f, v), c = glm::dot(f, f) - r * r;
    const long double disc = b * b - a * c;
    if (!(a > 0) || disc < 0) return false;
    lo = (-b - std::sqrt(disc)) / a;
    hi = (-b + std::sqrt(disc)) / a;
    return true;
  };
  long double lo, hi;
  if (quadric(o - p0, d, lo, hi)) take(lo, hi);
  if (quadric(o - p1, d, lo, hi)) take(lo, hi);
  const LDVec3 e = p1 - p0;
  const long double ee = glm::dot(e, e);
  if (!(ee > 0)) return hit;
  const LDVec3 f = o - p0;
  const LDVec3 dp = d - (glm::dot(d, e) / ee) * e, fp = f - (glm::dot(f, e) / ee) * e;
  long double c0 = -INFINITY, c1 = INFINITY;
  if (glm::dot(dp, dp) > 0) {
    if (!quadric(fp, dp, c0, c1)) return hit;
  } else if (glm::dot(fp, fp) > r * r) {
    return hit;
  }
  const long double de = glm::dot(d, e), fe = glm::dot(f, e);
  long double s0 = -INFINITY, s1 = INFINITY;
  if (de != 0) {
    s0 = -fe / de;
    s1 = (ee - fe) / de;
    if (s0 > s1) std::swap(s0, s1);
  } else if (fe < 0 || fe > ee) {
    return hit;
  }
  lo = std::max(c0, s0);
  hi = std::min(c1, s1);
  if (lo <= hi) take(lo, hi);
  return hit;
}

/// Componentwise |a - b| <= bound.
inline bool within(const DVec3& a, const DVec3& b, const DVec3& bound) {
  DVec3 e = glm::abs(a - b);
  return e.x <= bound.x && e.y <= bound.y && e.z <= bound.z;
}

inline double max_abs(const DVec3& v) {
  return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z)));
}

/// Rounds a double to float. The volatile store is a barrier: GCC 12.2's SLP
/// vectorizer was seen to fold double(float(x)) back to x for pairs of
/// components (-O2 and up), which would silently hand the double references
/// unrounded inputs that the float code under test never saw.
inline float round_f(double x) {
  volatile float f = float(x);
  return f;
}
inline Vec3 to_f(const DVec3& v) {
  return Vec3(round_f(v.x), round_f(v.y), round_f(v.z));
}

/// Random rays for a scene with bounds `world`: origins inside and outside,
/// random directions, some with zero components, some lying exactly in the
/// plane of a primitive box face (origin coordinate on the plane, zero
/// direction component).
inline rayscope::Ray random_ray(Rng& rng, const rayscope::Bounds3& world,
                                const std::vector<rayscope::Bounds3>& boxes) {
  DVec3 lo = to_d(world.lo), hi = to_d(world.hi), ext = hi - lo;
  DVec3 o = lo - 0.5 * ext + 2.0 * ext * DVec3(rng.uniform(), rng.uniform(), rng.uniform());
  DVec3 target = lo + ext * DVec3(rng.uniform(), rng.uniform(), rng.uniform());
  if (!boxes.empty() && rng.coin())  // aim at a primitive
    target = to_d(boxes[size_t(rng.integer(0, int(boxes.size()) - 1))].center());
  DVec3 d = rng.integer(0, 3) ? target - o : rng.unit_vector();
  rayscope::Ray ray{to_f(o), to_f(d * rng.log_uniform(0.01, 100)), rayscope::kInfinity};
  int mode = rng.integer(0, 5);
  if (mode == 1) ray.dir[rng.integer(0, 2)] = 0.0f;
  if (mode == 2) {
    int a = rng.integer(0, 2);
    ray.dir[a] = 0.0f;
    ray.dir[(a + 1) % 3] = 0.0f;
  }
  if (mode == 3 && !boxes.empty()) {
    const rayscope::Bounds3& b = boxes[size_t(rng.integer(0, int(boxes.size()) - 1))];
    int a = rng.integer(0, 2);
    ray.origin[a] = rng.coin() ? b.lo[a] : b.hi[a];
    ray.dir[a] = rng.coin() ? 0.0f : -0.0f;
  }
  if (ray.dir == rayscope::Vec3(0.0f)) ray.dir.z = 1.0f;
  if (rng.integer(0, 3) == 0)
    ray.tmax = round_f(rng.uniform(0, 3) * glm::length(ext) / glm::length(to_d(ray.dir)));
  return ray;
}

/// The textbook ray-sphere test: a t^2 + b t + c = 0 with the discriminant
/// b^2 - 4ac in float, nearest root with t > 0. The formula RayScope's
/// intersect_sphere replaces; the accuracy test and bench_accuracy measure it.
inline bool naive_sphere(const rayscope::Ray& ray, const rayscope::Vec3& center, float r,
                         float& t) {
  rayscope::Vec3 f = ray.origin - center;
  float a = glm::dot(ray.dir, ray.dir);
  float b = 2.0f * glm::dot(f, ray.dir);
  float c = glm::dot(f, f) - r * r;
  float disc = b * b - 4.0f * a * c;
  if (disc < 0.0f) return false;
  float s = std::sqrt(disc);
  float t0 = (-b - s) / (2.0f * a), t1 = (-b + s) / (2.0f * a);
  t = t0 > 0.0f ? t0 : t1;
  return t > 0.0f;
}

/// Settings of a small test render: w x h, spp x spp samples, two threads.
inline rayscope::RenderSettings small_render(int w, int h, int spp) {
  rayscope::RenderSettings s;
  s.width = w;
  s.height = h;
  s.samples = spp;
  s.threads = 2;
  return s;
}

}  // namespace rstest
