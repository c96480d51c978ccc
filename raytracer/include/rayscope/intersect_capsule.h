// Ray-capsule intersection: the points within a radius of a segment (a
// cylinder closed by two half-spheres), the primitive of lines drawn as tubes
// (scene.h, TubeSet). Written to the standard of intersect_sphere() (see
// intersect.h and docs/accuracy.md): no epsilon, computed in double from the
// float inputs, a hit point re-projected onto the surface with a bound on its
// distance from it, and a normal from the same quantity as the point.
//
// The capsule is convex and is the union of three convex pieces: the balls
// around its two ends and the finite cylinder between them. The line meets
// each piece in an interval of t, and the capsule in their hull. Taking the
// hull, rather than testing the cylinder's roots against the end planes and
// the balls' roots against the half-spaces beyond them, is what keeps the
// test watertight: where cylinder and cap meet, the pieces overlap, so a ray
// through that circle lies inside one of them by more than their rounding,
// whereas two range tests on the seam can both round the wrong way and let a
// ray through. Consecutive segments of a polyline overlap in the ball around
// their shared point for the same reason.
#pragma once

#include <algorithm>
#include <cmath>

#include "rayscope/intersect.h"
#include "rayscope/math.h"
#include "rayscope/ray.h"

namespace rayscope {

/// The interval [t0, t1] where the line f + t d (f: the origin relative to
/// the center, in the plane or space of the quadric) lies within `r` of the
/// center, a = d.d > 0: the roots of |f + t d|^2 = r^2, computed as in
/// intersect_sphere() (the discriminant as r^2 - |f - (f.d/a) d|^2, the roots
/// as c/q and q/a), so that neither cancels. False when the line stays
/// farther than r.
inline bool quadric_interval(const DVec3& f, const DVec3& d, double a, double r, double& t0,
                             double& t1) {
  const double b = glm::dot(f, d);
  const DVec3 l = f - (b / a) * d;
  const double disc = r * r - glm::dot(l, l);
  if (!(disc >= 0.0)) return false;  // also NaN (a direction too short to square)
  const double c = glm::dot(f, f) - r * r;
  const double q = -(b + std::copysign(std::sqrt(a * disc), b));
  if (q == 0.0) {
    t0 = t1 = -b / a;
  } else {
    t0 = c / q;
    t1 = q / a;
  }
  if (t0 > t1) std::swap(t0, t1);
  return true;
}

/// The interval of t where the line o + t d lies in the capsule around the
/// segment p0 p1 with radius r (the hull of the intervals of its two end
/// balls and of its finite cylinder; see the top of this file). False when
/// the line misses it. In double, from the float inputs: the offsets
/// o - p0, o - p1 and p1 - p0 are exact or within 2^-53 of their size.
inline bool capsule_interval(const Ray& ray, const Vec3& p0, const Vec3& p1, float radius,
                             double& t_in, double& t_out) {
  const DVec3 d(ray.dir);
  const double a = glm::dot(d, d);
  if (!(a > 0.0)) return false;
  const double r = double(radius);
  const DVec3 f0 = DVec3(ray.origin) - DVec3(p0);
  t_in = kInfinity;
  t_out = -double(kInfinity);
  bool hit = false;
  auto take = [&](double lo, double hi) {
    t_in = std::min(t_in, lo);
    t_out = std::max(t_out, hi);
    hit = true;
  };
  double lo, hi;
  if (quadric_interval(f0, d, a, r, lo, hi)) take(lo, hi);
  const DVec3 e = DVec3(p1) - DVec3(p0);
  const double ee = glm::dot(e, e);
  if (!(ee > 0.0)) return hit;  // a segment of length 0: the ball alone
  const DVec3 f1 = DVec3(ray.origin) - DVec3(p1);
  if (quadric_interval(f1, d, a, r, lo, hi)) take(lo, hi);
  // The cylinder: the line and the origin projected onto the plane normal to
  // the axis, then the slab 0 <= (f0 + t d).e <= e.e between the end planes.
  const double de = glm::dot(d, e), fe = glm::dot(f0, e);
  const DVec3 dp = d - (de / ee) * e, fp = f0 - (fe / ee) * e;
  const double ap = glm::dot(dp, dp);
  double c0, c1;
  if (ap > 0.0) {
    if (!quadric_interval(fp, dp, ap, r, c0, c1)) return hit;
  } else {
    // Parallel to the axis: inside the cylinder's side everywhere or nowhere.
    if (!(glm::dot(fp, fp) <= r * r)) return hit;
    c0 = -double(kInfinity);
    c1 = double(kInfinity);
  }
  double s0, s1;
  if (de != 0.0) {
    s0 = -fe / de;
    s1 = (ee - fe) / de;
    if (s0 > s1) std::swap(s0, s1);
  } else {
    // Parallel to the end planes: between them everywhere or nowhere.
    if (!(fe >= 0.0 && fe <= ee)) return hit;
    s0 = -double(kInfinity);
    s1 = double(kInfinity);
  }
  lo = std::max(c0, s0);
  hi = std::min(c1, s1);
  if (lo <= hi) take(lo, hi);
  return hit;
}

/// Ray-capsule test (the segment p0 p1, radius > 0). Returns the nearest
/// crossing of the surface in (0, tmax) as the float the caller compares and
/// stores, or false: the entry, or the exit for an origin inside. Open at
/// tmax like intersect_sphere() (the aggregate passes next_float_up(tmax) to
/// close it). The sign of the distance of a spawned origin from each piece is
/// exact in double for origins at least a float ulp of the capsule's
/// coordinates off its surface (as for the sphere), so a ray leaving the
/// surface outward finds the whole interval behind it.
inline bool intersect_capsule(const Ray& ray, const Vec3& p0, const Vec3& p1, float radius,
                              float tmax, float& t_hit) {
  double t_in, t_out;
  if (!capsule_interval(ray, p0, p1, radius, t_in, t_out)) return false;
  return first_float_root(t_in, t_out, tmax, t_hit);
}

/// A capsule hit's point, error bound and unit normal, from one direction as
/// in sphere_point(): v = o + t d - p0 in double, its closest point on the
/// segment p0 + s (p1 - p0) (s clamped to [0, 1]), the normal n along
/// v - s (p1 - p0), and the point p0 + s (p1 - p0) + radius n, which lies on
/// the surface up to double rounding at any ray length. p_error bounds the
/// distance of the float point from that one per axis, e_i: the rounding to
/// float, 2^-24 |p_i| <= 2^-24 (max(|p0_i|, |p1_i|) + radius), plus the double
/// arithmetic before it (~2^-50 of the same), within gamma(2) of the sum. Its
/// distance from the surface along the normal, which spawn_ray() offsets by,
/// is bounded by the projection of e plus what a move of |e| along the
/// surface adds across a curved one, |e|^2 / (2 radius) (and at most |e|):
/// negligible unless the tube is a few ulps of its coordinates thin, where
/// it is what keeps the bound true (test_self_intersection, tubes at r/|c| =
/// 1e-7). `s` is where along the segment the hit lies (0 at p0, 1 at p1), for
/// interpolating what the ends carry (colors).
inline Vec3 capsule_point(const Ray& ray, float t, const Vec3& p0, const Vec3& p1, float radius,
                          Vec3& p_error, Vec3& n, float& s) {
  const DVec3 e = DVec3(p1) - DVec3(p0);
  const DVec3 v = DVec3(ray.origin) + double(t) * DVec3(ray.dir) - DVec3(p0);
  const double ee = glm::dot(e, e);
  const double sd = ee > 0.0 ? std::clamp(glm::dot(v, e) / ee, 0.0, 1.0) : 0.0;
  const DVec3 w = v - sd * e;
  const double len = glm::length(w);
  // A zero offset (t on the axis of a capsule too thin for float to place a
  // point on it): the side the ray came from.
  const DVec3 nd = len > 0.0 && std::isfinite(len) ? w / len : -glm::normalize(DVec3(ray.dir));
  n = Vec3(nd);
  s = float(sd);
  const Vec3 err = gamma(2) * (glm::max(glm::abs(p0), glm::abs(p1)) + Vec3(radius));
  const float len_err = glm::length(err);
  p_error = err + Vec3(std::min(len_err, len_err * len_err / (2.0f * radius)));
  return Vec3(DVec3(p0) + sd * e + double(radius) * nd);
}

/// The bounds of a capsule as the structures get them (Scene::commit) and as
/// its range tests check them first: the box around the end balls, rounded
/// outward, so that it contains every point of the capsule.
inline Bounds3 capsule_bounds(const Vec3& p0, const Vec3& p1, float radius) {
  const Vec3 lo = glm::min(p0, p1), hi = glm::max(p0, p1);
  Bounds3 b;
  for (int i = 0; i < 3; ++i) {
    b.lo[i] = next_float_down(lo[i] - radius);
    b.hi[i] = next_float_up(hi[i] + radius);
  }
  return b;
}

}  // namespace rayscope
