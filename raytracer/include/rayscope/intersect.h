// Ray-primitive intersection tests from the lecture (plane, triangle, sphere),
// written to be robust in floating point:
//  - the triangle test is watertight (Woop, Benthin and Wald 2013): the ray is
//    translated to the origin, the axes permuted so that the ray runs along +z,
//    and the triangle sheared; the edge functions are then evaluated in 2D and
//    recomputed in double precision when one of them is exactly zero, so a ray
//    through an edge or vertex shared by two triangles hits at least one of them;
//    a hit whose t is within the float error bound of zero (grazing rays, tiny
//    distant triangles), and a miss whose edge functions are within their
//    rounding error of zero (a ray through a vertex or edge on a silhouette),
//    are decided again exactly (intersect_triangle_exact) rather than dropped;
//  - the sphere test avoids the catastrophic cancellation of the textbook
//    discriminant b^2 - 4ac (Haines et al., Ray Tracing Gems ch. 7);
//  - every hit carries a conservative bound on the error of its position, which
//    spawn_ray() uses to offset secondary rays (no hand-tuned epsilon).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/type_ptr.hpp>

#include "rayscope/math.h"
#include "rayscope/ray.h"

namespace rayscope {

/// Per-ray data for the watertight triangle test, computed once per ray.
struct TrianglePrecomp {
  int kx, ky, kz;
  float sx, sy, sz;
  Vec3 origin;
  Vec3 origin_k;  ///< The origin permuted to (kx, ky, kz).
  Vec3 dir_k;     ///< The direction permuted to (kx, ky, kz), for the exact test.

  TrianglePrecomp() = default;  ///< Uninitialised: for arrays filled ray by ray.
  explicit TrianglePrecomp(const Ray& ray) : origin(ray.origin) {
    kz = max_dimension(glm::abs(ray.dir));
    kx = kz + 1 == 3 ? 0 : kz + 1;
    ky = kx + 1 == 3 ? 0 : kx + 1;
    origin_k = permuted(ray.origin);
    Vec3 d = permuted(ray.dir);
    dir_k = d;
    sx = -d.x / d.z;
    sy = -d.y / d.z;
    sz = 1.0f / d.z;
  }

  /// p's components in the order (kx, ky, kz). Read through a pointer, so
  /// that the per-ray axes pick addresses: Vec3's operator[] is a switch,
  /// which compiled into a chain of branches per vertex in the leaf loops.
  Vec3 permuted(const Vec3& p) const {
    const float* f = glm::value_ptr(p);
    return Vec3(f[kx], f[ky], f[kz]);
  }
  /// p - origin in the order (kx, ky, kz): each component the same one
  /// subtraction as permuting p - origin.
  Vec3 translated(const Vec3& p) const {
    const float* f = glm::value_ptr(p);
    return Vec3(f[kx] - origin_k.x, f[ky] - origin_k.y, f[kz] - origin_k.z);
  }
};

struct TriangleHit {
  float t;
  float b0, b1, b2;  // barycentric weights of p0, p1, p2
};

/// The watertight test decided exactly, for rays that pass within the float
/// test's rounding error of an edge or vertex (see intersect_triangle). Woop's
/// shear x' = x - (dx/dz) z rounds even for a vertex exactly on the ray, so
/// a ray through a vertex or an edge on the silhouette of a closed mesh could
/// miss every triangle around it. Here the shear is taken without division,
/// X = x dz - z dx (the edge functions scale by dz^2 and t by dz, signs
/// unchanged), in 113-bit binary128 arithmetic: the translation and the
/// products of floats are exact, so a vertex on the ray maps exactly to the
/// origin and a point on an edge exactly onto that edge (the edge function's
/// products have at most ~2 x 50 bits for the geometry near the ray where this
/// runs). Zeros count as inside, as in the float test. Out of line and slow
/// (software arithmetic): it runs only for near-misses.
[[gnu::noinline]] inline bool intersect_triangle_exact(const TrianglePrecomp& pre, float tmax,
                                                       const Vec3& p0, const Vec3& p1,
                                                       const Vec3& p2, TriangleHit& hit) {
  using Q = __float128;
  const Q dx = pre.dir_k.x, dy = pre.dir_k.y, dz = pre.dir_k.z;
  if (!(dz != 0)) return false;
  Q X[3], Y[3], Z[3];
  const Vec3* p[3] = {&p0, &p1, &p2};
  for (int i = 0; i < 3; ++i) {
    const Q ax = Q((*p[i])[pre.kx]) - Q(pre.origin[pre.kx]);
    const Q ay = Q((*p[i])[pre.ky]) - Q(pre.origin[pre.ky]);
    Z[i] = Q((*p[i])[pre.kz]) - Q(pre.origin[pre.kz]);
    X[i] = ax * dz - Z[i] * dx;
    Y[i] = ay * dz - Z[i] * dy;
  }
  const Q e0 = X[1] * Y[2] - Y[1] * X[2];
  const Q e1 = X[2] * Y[0] - Y[2] * X[0];
  const Q e2 = X[0] * Y[1] - Y[0] * X[1];
  if ((e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0)) return false;
  const Q det = e0 + e1 + e2;
  if (!(det != 0)) return false;
  const float t = float((e0 * Z[0] + e1 * Z[1] + e2 * Z[2]) / (det * dz));
  if (!(t > 0.0f) || !(t <= tmax)) return false;
  hit.t = t;
  hit.b0 = float(e0 / det);
  hit.b1 = float(e1 / det);
  hit.b2 = float(e2 / det);
  return true;
}

/// Bound on the rounding error of the float edge functions of a triangle,
/// given the largest |x'|, |y'| of its sheared vertices and the largest |z|
/// before scaling (world units). x' = (p.x - o.x) + sx (p.z - o.z) in float
/// is off by at most gamma(7) (|x'| + |sx| max|z|) (see intersect_triangle),
/// likewise y'; an edge function x'_i y'_j - y'_i x'_j then by 2 (gamma(2)
/// |x'| |y'| + delta_y |x'| + delta_x |y'|).
[[gnu::always_inline]] inline float edge_error_bound(const TrianglePrecomp& pre, float max_xt,
                                                     float max_yt, float max_z_world) {
  const float delta_x = gamma(7) * (max_xt + std::abs(pre.sx) * max_z_world);
  const float delta_y = gamma(7) * (max_yt + std::abs(pre.sy) * max_z_world);
  return 2.0f * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
}

/// Watertight ray-triangle test. Returns true and fills `hit` when the ray hits
/// the triangle at 0 < t < tmax. Degenerate (zero-area) triangles never hit.
/// (Always inlined: the compiler otherwise calls it out of line from the BVH
/// leaf loops, which measured ~2% slower.)
[[gnu::always_inline]] inline bool intersect_triangle(const TrianglePrecomp& pre, float tmax,
                                                      const Vec3& p0, const Vec3& p1,
                                                      const Vec3& p2, TriangleHit& hit) {
  // Translate to the ray origin, permute so that the ray runs along z, shear.
  Vec3 p0t = pre.translated(p0), p1t = pre.translated(p1), p2t = pre.translated(p2);
  p0t.x += pre.sx * p0t.z;
  p0t.y += pre.sy * p0t.z;
  p1t.x += pre.sx * p1t.z;
  p1t.y += pre.sy * p1t.z;
  p2t.x += pre.sx * p2t.z;
  p2t.y += pre.sy * p2t.z;

  // Edge functions: signed areas of the sheared triangle seen from the ray.
  float e0 = p1t.x * p2t.y - p1t.y * p2t.x;
  float e1 = p2t.x * p0t.y - p2t.y * p0t.x;
  float e2 = p0t.x * p1t.y - p0t.y * p1t.x;
  if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f) [[unlikely]] {
    e0 = float(double(p1t.x) * double(p2t.y) - double(p1t.y) * double(p2t.x));
    e1 = float(double(p2t.x) * double(p0t.y) - double(p2t.y) * double(p0t.x));
    e2 = float(double(p0t.x) * double(p1t.y) - double(p0t.y) * double(p1t.x));
  }
  if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f)) {
    // A miss, unless the signs that disagree are within the edge functions'
    // rounding error: then the ray passes (nearly) through an edge or vertex,
    // which on a mesh's silhouette no neighbour may cover. Decide exactly.
    const Vec3 m = glm::max(glm::abs(p0t), glm::max(glm::abs(p1t), glm::abs(p2t)));
    const float de = edge_error_bound(pre, m.x, m.y, m.z);
    if ((e0 < -de || e1 < -de || e2 < -de) && (e0 > de || e1 > de || e2 > de)) return false;
    return intersect_triangle_exact(pre, tmax, p0, p1, p2, hit);
  }
  float det = e0 + e1 + e2;
  if (det == 0.0f) return false;

  // Largest translated z in world units, before scaling: the error of the
  // sheared x and y is bounded in terms of it (edge_error_bound).
  const float max_z_world = max_component(glm::abs(Vec3(p0t.z, p1t.z, p2t.z)));

  // Scaled hit distance; its sign is checked without dividing.
  p0t.z *= pre.sz;
  p1t.z *= pre.sz;
  p2t.z *= pre.sz;
  float t_scaled = e0 * p0t.z + e1 * p1t.z + e2 * p2t.z;
  if (det < 0.0f && t_scaled >= 0.0f) return false;
  if (det > 0.0f && t_scaled <= 0.0f) return false;

  float inv_det = 1.0f / det;
  float t = t_scaled * inv_det;
  // The range test is on t itself: comparing t_scaled with tmax * det rounds
  // differently, let hits up to an ulp beyond tmax through and made the
  // closest hit depend on the order in which triangles were tested. Written
  // as !(t <= tmax) so that a NaN t (a ray with NaN or infinite components)
  // is rejected rather than reported as a hit.
  if (!(t <= tmax)) return false;

  // Reject hits whose t could be <= 0 within the rounding error of the test.
  float max_zt = max_component(glm::abs(Vec3(p0t.z, p1t.z, p2t.z)));
  float delta_z = gamma(3) * max_zt;
  float max_xt = max_component(glm::abs(Vec3(p0t.x, p1t.x, p2t.x)));
  float max_yt = max_component(glm::abs(Vec3(p0t.y, p1t.y, p2t.y)));
  // x' = (p.x - o.x) + sx (p.z - o.z) in float has an error of at most
  // gamma(2) |p.x - o.x| + gamma(4) |sx (p.z - o.z)|, and |p.x - o.x| <=
  // |x'| + |sx (p.z - o.z)|: with the rounding of sx and of the bound itself,
  // gamma(7) (|x'| + |sx| max|z|) covers it (likewise for y'). Bounding |sx|
  // by 1 instead, as pbrt does, overestimates the error by 1/|sx| for rays
  // nearly in the triangle's plane (sx ~ the grazing angle): the t bound then
  // exceeded t and such hits were rejected; rays at ~1e-5 rad slipped through
  // flat meshes (test_stress, Grazing.*).
  float delta_e = edge_error_bound(pre, max_xt, max_yt, max_z_world);
  float max_e = max_component(glm::abs(Vec3(e0, e1, e2)));
  float delta_t =
      3.0f * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * std::abs(inv_det);
  if (!(t > delta_t)) [[unlikely]] {
    // t may still be positive: the float bound is loose for rays grazing the
    // triangle or far from a tiny one (it rejected 7.8% of real hits on
    // triangles 1e-5..1e-4 rad wide, docs/accuracy.md).
    if (!(t > 0.0f) || std::isnan(delta_t)) return false;
    // Decide exactly: this also rejects triangles of zero area in 3D that
    // the float shear gave a tiny area (their t bound is huge), whose
    // neighbours' near misses the exact test then turns into hits.
    return intersect_triangle_exact(pre, tmax, p0, p1, p2, hit);
  }

  hit.t = t;
  hit.b0 = e0 * inv_det;
  hit.b1 = e1 * inv_det;
  hit.b2 = e2 * inv_det;
  return true;
}

/// Convenience overload for a single test.
inline bool intersect_triangle(const Ray& ray, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                               TriangleHit& hit) {
  return intersect_triangle(TrianglePrecomp(ray), ray.tmax, p0, p1, p2, hit);
}

/// Hit point on a triangle from barycentrics, with its error bound.
inline Vec3 triangle_point(const TriangleHit& h, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                           Vec3& p_error) {
  Vec3 q0 = h.b0 * p0, q1 = h.b1 * p1, q2 = h.b2 * p2;
  p_error = gamma(7) * (glm::abs(q0) + glm::abs(q1) + glm::abs(q2));
  return q0 + q1 + q2;
}

/// The first of the roots t0 <= t1 (double) that lies in (0, tmax) as the
/// float the caller compares and stores, in `t_hit`: a root in (0, tmax) in
/// double that rounds to 0 or tmax is outside the range. False when neither
/// does. The last step of the sphere and capsule tests.
inline bool first_float_root(double t0, double t1, float tmax, float& t_hit) {
  for (const double t : {t0, t1}) {
    const float tf = float(t);
    if (tf > 0.0f && tf < tmax) {
      t_hit = tf;
      return true;
    }
  }
  return false;
}

/// Ray-sphere test. Returns the nearest root in (0, tmax), or false. Computed
/// in double from the float inputs: the offset f = origin - center (exact, or
/// within 2^-53 of |f|), the discriminant as r^2 - |f - (f.d/d.d) d|^2, which
/// stays accurate for small or distant spheres, and the roots as c/q and q/a,
/// which avoids subtracting nearly equal numbers. In double the sign of
/// c = |f|^2 - r^2 is exact for every origin at least one float ulp off the
/// surface (its error is ~2^-52 |f|^2, the distance's contribution ~2^-23 r^2),
/// so a ray spawned just outside the sphere (offset_ray_origin) and leaving it
/// finds both roots behind its origin. In float, that sign is lost to
/// rounding for spheres small against their distance from the origin
/// (docs/accuracy.md, "Sphere hits at any distance").
inline bool intersect_sphere(const Ray& ray, const Vec3& center, float radius, float tmax,
                             float& t_hit) {
  const DVec3 f = DVec3(ray.origin) - DVec3(center);
  const DVec3 d(ray.dir);
  const double a = glm::dot(d, d);
  const double b = glm::dot(f, d);  // half of the textbook b
  const DVec3 l = f - (b / a) * d;
  const double r = double(radius);
  const double disc = r * r - glm::dot(l, l);  // (discriminant / 4) / a
  if (disc < 0.0) return false;
  const double c = glm::dot(f, f) - r * r;
  const double q = -(b + std::copysign(std::sqrt(a * disc), b));
  double t0, t1;
  if (q == 0.0) {
    t0 = t1 = -b / a;
  } else {
    t0 = c / q;
    t1 = q / a;
  }
  if (t0 > t1) std::swap(t0, t1);
  return first_float_root(t0, t1, tmax, t_hit);
}

/// A sphere hit's point, error bound and unit normal, all from one direction:
/// the offset v = o + t d - center in double, normalized to n, gives the
/// normal and the point center + radius n (re-projected onto the surface), so
/// that the normal is the direction from the center to the point at any ray
/// length and any distance from the origin (a point o + t d in float lies
/// ~2^-24 t |d| off the sphere, degrees off the normal's direction after 1e6
/// radii of travel). p_error bounds |p - (center + radius n)| per axis:
/// the rounding of p to float (2^-24 |p_i| <= 2^-24 (|c_i| + r)) plus the
/// double arithmetic before it (~2^-50 (|c_i| + r)) and this bound's own
/// rounding, all within gamma(2) (|c_i| + r).
inline Vec3 sphere_point(const Ray& ray, float t, const Vec3& center, float radius, Vec3& p_error,
                         Vec3& n) {
  const DVec3 v = DVec3(ray.origin) + double(t) * DVec3(ray.dir) - DVec3(center);
  const double len = glm::length(v);
  // A zero offset (t at the center of a sphere too small for float to place a
  // point on it): the side the ray came from.
  const DVec3 nd = len > 0.0 && std::isfinite(len) ? v / len : -glm::normalize(DVec3(ray.dir));
  n = Vec3(nd);
  p_error = gamma(2) * (glm::abs(center) + Vec3(radius));
  return Vec3(DVec3(center) + double(radius) * nd);
}

/// Ray-plane test (lecture: lambda = (P0 - Pr).n / (tr.n), tr.n != 0). Returns a
/// hit in (0, tmax). A ray parallel to the plane never hits.
inline bool intersect_plane(const Ray& ray, const Vec3& point, const Vec3& normal, float tmax,
                            float& t_hit) {
  float denom = glm::dot(ray.dir, normal);
  if (denom == 0.0f) return false;
  float t = glm::dot(point - ray.origin, normal) / denom;
  if (!(t > 0.0f && t < tmax)) return false;
  t_hit = t;
  return true;
}

/// Hit point on a plane, re-projected onto it, with its error bound.
inline Vec3 plane_point(const Ray& ray, float t, const Vec3& point, const Vec3& normal,
                        Vec3& p_error) {
  Vec3 p = ray.origin + t * ray.dir;
  p -= glm::dot(p - point, normal) * normal;
  p_error = gamma(8) * (glm::abs(point) + glm::abs(p));
  return p;
}

/// Factor by which box tests round exit distances up (robust traversal, see
/// intersect_box). Traversal culls a node only when its entry distance exceeds
/// the closest hit times this factor, i.e. only when the box test itself,
/// repeated with that closest hit as tmax, would reject the node.
inline constexpr float kBoxFarScale = 1.0f + 2.0f * gamma(3);

/// Slab test of a ray against a box, with precomputed reciprocal direction:
/// the ray's interval [tnear, tfar] in the box within [0, tmax]; the box is
/// hit when tnear <= tfar. The exit distance is rounded up by 2 gamma(3) so
/// that rays touching a box face never miss the primitives inside (robust
/// traversal).
inline void box_interval(const Vec3& lo, const Vec3& hi, const Vec3& origin, const Vec3& inv_dir,
                         float tmax, float& tnear, float& tfar) {
  // Near and far planes chosen by the sign of the direction. A ray lying in a
  // slab plane (zero direction component, origin on the plane) gets 0 * inf =
  // NaN for that plane only; the comparisons below ignore NaN, so such a ray,
  // which touches the box, is not culled.
  // The components through float pointers: Vec3's operator[] is a switch,
  // which left this loop as a chain of branches (one call per ray, 4% of a
  // bunny render's CPU time).
  const float *l = &lo.x, *h = &hi.x, *o = &origin.x, *inv = &inv_dir.x;
  tnear = 0.0f;
  tfar = tmax;
  for (int i = 0; i < 3; ++i) {
    const bool neg = std::signbit(inv[i]);
    const float tn = ((neg ? h[i] : l[i]) - o[i]) * inv[i];
    const float tf = ((neg ? l[i] : h[i]) - o[i]) * inv[i];
    if (tn > tnear) tnear = tn;
    if (tf < tfar) tfar = tf;
  }
  tfar *= kBoxFarScale;
}

/// box_interval() as a hit test: the entry distance, or +inf when the box is
/// missed within [0, tmax].
inline float intersect_box(const Vec3& lo, const Vec3& hi, const Vec3& origin, const Vec3& inv_dir,
                           float tmax) {
  float tnear, tfar;
  box_interval(lo, hi, origin, inv_dir, tmax, tnear, tfar);
  return tnear <= tfar ? tnear : kInfinity;
}

}  // namespace rayscope
