// No self-intersection: secondary rays spawned at a hit with spawn_ray /
// spawn_ray_to (offset by the hit's error bound, no global epsilon) never hit
// the surface they leave, at any scale. Geometry spans 1e-6..1e6 in
// magnitude, so a fixed epsilon would fail at one end or the other.
//
// Every check here is exact in intent: a ray leaving a convex surface (a
// triangle, a sphere from outside, a plane) on the side it leaves cannot meet
// that surface again in exact arithmetic, so any reported hit is a
// self-intersection. Cases where float rounding made the primary ray miss are
// skipped (and counted; most cases must be used).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "rayscope/material.h"
#include "rayscope/scene.h"
#include "test_util.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

// Random direction in the hemisphere around unit n (double).
DVec3 hemisphere(Rng& rng, const DVec3& n) {
  DVec3 u = rng.unit_vector();
  return glm::dot(u, n) < 0 ? -u : u;
}

// Random unit vector perpendicular to n.
DVec3 tangent(Rng& rng, const DVec3& n) {
  for (;;) {
    DVec3 t = glm::cross(n, rng.unit_vector());
    double l = glm::length(t);
    if (l > 1e-3) return t / l;
  }
}

struct Counts {
  int cases = 0, used = 0, rays = 0;
};

void report(const char* what, const Counts& c) {
  std::printf("%s: %d cases, %d used, %d secondary rays\n", what, c.cases, c.used, c.rays);
  EXPECT_GT(c.used, c.cases * 8 / 10) << what << ": too many primary rays missed";
}

// ---------------------------------------------------------------------------
// Triangles

// A random, not too thin triangle. mode 0: every coordinate independently
// log-uniform in 1e-6..1e6 with random sign (large triangles of wild shapes);
// mode 1: a small triangle far from the origin (size 1e-4..1 times the
// distance), the hard case for absolute rounding errors.
bool random_triangle(Rng& rng, int mode, Vec3 v[3]) {
  if (mode == 0) {
    for (int i = 0; i < 3; ++i)
      v[i] = to_f(DVec3(rng.log_uniform_signed(1e-6, 1e6), rng.log_uniform_signed(1e-6, 1e6),
                        rng.log_uniform_signed(1e-6, 1e6)));
  } else {
    DVec3 base(rng.log_uniform_signed(1e-6, 1e6), rng.log_uniform_signed(1e-6, 1e6),
               rng.log_uniform_signed(1e-6, 1e6));
    double size = rstest::max_abs(base) * rng.log_uniform(1e-4, 1.0);
    for (int i = 0; i < 3; ++i) v[i] = to_f(base + size * rng.in_unit_ball());
  }
  DVec3 a = to_d(v[0]), b = to_d(v[1]), c = to_d(v[2]);
  double area2 = glm::length(glm::cross(b - a, c - a));
  double e = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
  return area2 > 1e-3 * e * e;  // no slivers (smallest angle > ~0.05 degrees)
}

void triangle_case(Rng& rng, int mode, Counts& cnt) {
  Vec3 v[3];
  while (!random_triangle(rng, mode, v)) {
  }
  ++cnt.cases;
  const DVec3 a = to_d(v[0]), b = to_d(v[1]), c = to_d(v[2]);
  const DVec3 nexact = glm::normalize(glm::cross(b - a, c - a));
  const double size = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});

  // The triangle as object 0, plus a few distant distractor triangles as
  // object 1 so that the scene is large enough to be traced through the BVH.
  Scene scene;
  TriangleMesh tri;
  tri.positions = {v[0], v[1], v[2]};
  tri.triangles = {{0, 1, 2}};
  TriangleMesh far;
  for (uint32_t i = 0; i < 4; ++i) {
    DVec3 p = a + 100.0 * size * rng.unit_vector();
    for (int k = 0; k < 3; ++k) far.positions.push_back(to_f(p + size * rng.in_unit_ball()));
    far.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  scene.meshes = {tri, far};
  scene.commit();
  ASSERT_TRUE(scene.summary().walks_structure);
  // The triangle alone (traced without a BVH), for any-hit queries, where a
  // distractor found first could hide a self-hit.
  Scene alone;
  alone.meshes = {tri};
  alone.commit();

  // Primary ray toward a random interior point, from distance 1e-3..1e3 times
  // the triangle size, at |cos| 1e-3..1 to the normal.
  double u, w;
  do {
    u = rng.uniform(0.01, 0.98);
    w = rng.uniform(0.01, 0.98);
  } while (u + w > 0.99);
  const DVec3 q = (1 - u - w) * a + u * b + w * c;
  const double cs = rng.log_uniform(1e-3, 1.0);
  DVec3 dir = cs * nexact + std::sqrt(1 - cs * cs) * tangent(rng, nexact);
  if (rng.coin()) dir = -dir;
  const Vec3 o = to_f(q + size * rng.log_uniform(1e-3, 1e3) * dir);
  const Vec3 d = to_f((q - to_d(o)) * rng.log_uniform(1e-2, 1e2));
  SurfaceHit hit;
  if (!scene.intersect(Ray{o, d, kInfinity}, hit) || hit.object != 0) return;
  ++cnt.used;

  // Normal facing the side the ray came from.
  const Vec3 n = glm::dot(d, hit.ng) < 0 ? hit.ng : -hit.ng;
  const DVec3 nside = glm::dot(to_d(n), nexact) > 0 ? nexact : -nexact;
  const Vec3 dn = glm::normalize(d);

  auto expect_no_self_hit = [&](const Ray& r, const char* kind) {
    ++cnt.rays;
    SurfaceHit h2, h3;
    bool again = scene.intersect(r, h2) && h2.object == 0;
    bool again_alone = alone.intersect(r, h3);
    bool blocked = alone.occluded(r);
    EXPECT_FALSE(again) << kind << " ray re-hit its triangle at t=" << h2.t << " (mode " << mode
                        << ", case " << cnt.cases << ")";
    EXPECT_FALSE(again_alone) << kind << " ray re-hit its triangle at t=" << h3.t << " (mode "
                              << mode << ", case " << cnt.cases << ", no BVH)";
    EXPECT_FALSE(blocked) << kind << " ray: triangle occludes itself (mode " << mode << ", case "
                          << cnt.cases << ")";
  };

  // Mirror reflection and random directions on the incoming side.
  Vec3 r = reflect(dn, n);
  if (glm::dot(r, n) > 0) expect_no_self_hit(spawn_ray(hit.p, hit.p_error, n, r), "reflection");
  for (int k = 0; k < 2; ++k) {
    Vec3 wdir = to_f(hemisphere(rng, to_d(n)));
    if (glm::dot(wdir, n) > 0)
      expect_no_self_hit(spawn_ray(hit.p, hit.p_error, n, wdir), "hemisphere");
  }
  // Through the surface: continuing straight on and refracted (offset to the
  // far side by spawn_ray since dot(dir, n) < 0).
  expect_no_self_hit(spawn_ray(hit.p, hit.p_error, n, d), "continuing");
  Vec3 t;
  if (refract(dn, n, 1.0f, 1.5f, t) && glm::dot(t, n) < 0)
    expect_no_self_hit(spawn_ray(hit.p, hit.p_error, n, t), "refraction");
  // Shadow rays to random points on the incoming side (clearly off the plane:
  // height 1e-3..1e3 times the size), which the segment cannot reach through
  // the triangle.
  for (int k = 0; k < 2; ++k) {
    DVec3 target = to_d(hit.p) + size * rng.log_uniform(1e-3, 1e3) * to_d(n) +
                   size * rng.log_uniform(1e-3, 10) * tangent(rng, nside);
    Vec3 tf = to_f(target);
    if (!(glm::dot(to_d(tf) - a, nside) > 1e-4 * size)) continue;
    expect_no_self_hit(spawn_ray_to(hit.p, hit.p_error, n, tf), "shadow");
  }
}

TEST(SelfIntersection, TrianglesOfAnyScale) {
  Rng rng(11);
  for (int mode = 0; mode < 2; ++mode) {
    Counts cnt;
    for (int i = 0; i < 10000; ++i) {
      triangle_case(rng, mode, cnt);
      if (HasFailure()) return;
    }
    report(mode == 0 ? "triangles, log-uniform coordinates" : "small triangles far away", cnt);
  }
}

// ---------------------------------------------------------------------------
// Spheres

TEST(SelfIntersection, SpheresOfAnyScale) {
  // Centers with log-uniform coordinates (1e-6..1e6), radius 1e-4..10 times
  // the center's magnitude. Rays from outside: the outward reflection must not
  // re-hit the sphere; the inward refraction must hit only the far side, at a
  // distance of at least half the chord 2 r cos(theta_t) (>= 1.49 r for
  // ior 1.5), i.e. not at the entry point. Inside, the internal reflection
  // must again travel a chord, and the ray leaving by refraction must escape.
  Rng rng(12);
  Counts cnt;
  for (int i = 0; i < 20000; ++i) {
    DVec3 center(rng.log_uniform_signed(1e-6, 1e6), rng.log_uniform_signed(1e-6, 1e6),
                 rng.log_uniform_signed(1e-6, 1e6));
    double r = rstest::max_abs(center) * rng.log_uniform(1e-4, 10);
    Scene scene;
    scene.spheres.push_back(rayscope::Sphere{"s", to_f(center), rstest::round_f(r), 0});
    scene.commit();
    const Vec3 cf = scene.spheres[0].center;
    const double rf = scene.spheres[0].radius;
    ++cnt.cases;

    DVec3 wdir = rng.unit_vector();
    Vec3 o = to_f(to_d(cf) + rf * rng.log_uniform(1.1, 1e3) * wdir);
    DVec3 aim = to_d(cf) + 0.99 * rf * std::sqrt(rng.uniform()) * tangent(rng, wdir);
    Vec3 d = to_f((aim - to_d(o)) * rng.log_uniform(1e-2, 1e2));
    SurfaceHit hit;
    if (!scene.intersect(Ray{o, d, kInfinity}, hit)) continue;
    ASSERT_LT(glm::dot(d, hit.ng), 0.0f) << "outside ray must hit the front";
    ++cnt.used;
    const Vec3 n = hit.ng, dn = glm::normalize(d);

    // Outward: reflection and random directions.
    Vec3 refl = reflect(dn, n);
    Vec3 out[3] = {refl, to_f(hemisphere(rng, to_d(n))), to_f(hemisphere(rng, to_d(n)))};
    for (const Vec3& w : out) {
      if (!(glm::dot(w, n) > 0)) continue;
      ++cnt.rays;
      SurfaceHit h2;
      Ray ray = spawn_ray(hit.p, hit.p_error, n, w);
      EXPECT_FALSE(scene.intersect(ray, h2)) << "case " << i << ": outward ray re-hit, t=" << h2.t;
      EXPECT_FALSE(scene.occluded(ray)) << "case " << i;
    }
    // Shadow ray to a point above the tangent plane.
    {
      DVec3 nd = glm::normalize(to_d(n));
      DVec3 target = to_d(hit.p) + rf * rng.log_uniform(1e-3, 1e2) * nd +
                     rf * rng.log_uniform(1e-3, 10) * tangent(rng, nd);
      Vec3 tf = to_f(target);
      if (glm::dot(to_d(tf) - to_d(hit.p), nd) > 1e-3 * rf) {
        ++cnt.rays;
        EXPECT_FALSE(scene.occluded(spawn_ray_to(hit.p, hit.p_error, n, tf))) << "case " << i;
      }
    }
    // Inward refraction: must reach the far side.
    Vec3 t;
    ASSERT_TRUE(refract(dn, n, 1.0f, 1.5f, t));
    ++cnt.rays;
    Ray in = spawn_ray(hit.p, hit.p_error, n, t);
    SurfaceHit far;
    ASSERT_TRUE(scene.intersect(in, far)) << "case " << i << ": refracted ray escaped";
    double chord = 2 * rf * std::abs(glm::dot(glm::normalize(to_d(t)), glm::normalize(to_d(n))));
    EXPECT_GT(double(far.t) * glm::length(to_d(t)), 0.5 * chord)
        << "case " << i << ": refracted ray re-hit near its origin";
    EXPECT_GT(glm::dot(t, far.ng), 0.0f) << "case " << i << ": must hit the far side (exiting)";

    // Inside, at the far side: the normal facing the ray is -ng.
    const Vec3 nin = -far.ng;
    const Vec3 tn = glm::normalize(t);
    Vec3 r2 = reflect(tn, nin);
    if (glm::dot(r2, nin) > 0) {
      ++cnt.rays;
      SurfaceHit h3;
      ASSERT_TRUE(scene.intersect(spawn_ray(far.p, far.p_error, nin, r2), h3))
          << "case " << i << ": internal reflection escaped";
      double chord2 =
          2 * rf * std::abs(glm::dot(glm::normalize(to_d(r2)), glm::normalize(to_d(nin))));
      EXPECT_GT(double(h3.t) * glm::length(to_d(r2)), 0.5 * chord2) << "case " << i;
    }
    Vec3 t2;
    if (refract(tn, nin, 1.5f, 1.0f, t2) && glm::dot(t2, nin) < 0) {
      ++cnt.rays;
      SurfaceHit h4;
      EXPECT_FALSE(scene.intersect(spawn_ray(far.p, far.p_error, nin, t2), h4))
          << "case " << i << ": ray leaving the sphere re-hit it at t=" << h4.t;
    }
    if (HasFailure()) return;
  }
  report("spheres", cnt);
}

TEST(SelfIntersection, SmallSpheresFarFromTheirOrigin) {
  // Spheres down to the smallest that float still resolves at their position:
  // r/|c| from 1e-7 (the radius is then ~1 ulp of the center's largest
  // coordinate) to 1e-3, one decade at a time, centers with log-uniform
  // coordinates in 1e-6..1e6 (all three, so the sphere sits off every axis).
  // A ray from outside hits the front; rays spawned from the hit on the
  // outside (reflection, random outward directions, a shadow ray to a point
  // above the tangent plane) must never hit the sphere again. (Inward rays are
  // checked by SpheresOfAnyScale, down to r/|c| = 1e-4: below that the hit
  // point's own rounding, ~1 ulp of |c|, is as large as the radius.) Rays per
  // decade: ~4 x stress-scaled 40000 cases. (Issue 11 reported 21 of 348k
  // re-hits at 1e-5..1e-4 and 513 of 332k at 1e-6..1e-5; on main at 3cf09f4
  // this test found none, see docs/accuracy.md.)
  constexpr int kDecades = 4;  // 1e-7..1e-3
  const size_t cases = rstest::stress_scaled(40000);
  std::printf("r/|c| decade      cases  used  outward rays  re-hits\n");
  for (int dec = 0; dec < kDecades; ++dec) {
    Rng rng(1200 + uint32_t(dec));
    size_t used = 0, rays = 0, rehits = 0;
    std::string first;
    for (size_t i = 0; i < cases; ++i) {
      DVec3 center(rng.log_uniform_signed(1e-6, 1e6), rng.log_uniform_signed(1e-6, 1e6),
                   rng.log_uniform_signed(1e-6, 1e6));
      const double lo = std::pow(10.0, -7 + dec);
      double r = rstest::max_abs(center) * rng.log_uniform(lo, 10 * lo);
      Scene scene;
      scene.spheres.push_back(rayscope::Sphere{"s", to_f(center), rstest::round_f(r), 0});
      scene.commit();
      const Vec3 cf = scene.spheres[0].center;
      const double rf = scene.spheres[0].radius;
      DVec3 wdir = rng.unit_vector();
      Vec3 o = to_f(to_d(cf) + rf * rng.log_uniform(2, 1e3) * wdir);
      DVec3 aim = to_d(cf) + 0.99 * rf * std::sqrt(rng.uniform()) * tangent(rng, wdir);
      Vec3 d = to_f((aim - to_d(o)) * rng.log_uniform(1e-2, 1e2));
      SurfaceHit hit;
      if (!scene.intersect(Ray{o, d, kInfinity}, hit) || !(glm::dot(d, hit.ng) < 0.0f)) continue;
      ++used;
      const Vec3 n = hit.ng;
      auto check = [&](const Ray& ray, bool any_hit_only) {
        ++rays;
        SurfaceHit h2;
        bool again = !any_hit_only && scene.intersect(ray, h2);
        bool blocked = scene.occluded(ray);
        if (again || blocked) {
          if (++rehits == 1) {
            char buf[512];
            std::snprintf(buf, sizeof buf,
                          "c=(%.9g, %.9g, %.9g) r=%.9g p=(%.9g, %.9g, %.9g) n=(%g, %g, %g) "
                          "origin=(%.9g, %.9g, %.9g) t=%g",
                          cf.x, cf.y, cf.z, rf, hit.p.x, hit.p.y, hit.p.z, n.x, n.y, n.z,
                          ray.origin.x, ray.origin.y, ray.origin.z, again ? h2.t : -1.0);
            first = buf;
          }
        }
      };
      Vec3 refl = reflect(glm::normalize(d), glm::normalize(n));
      Vec3 out[3] = {refl, to_f(hemisphere(rng, to_d(n))), to_f(hemisphere(rng, to_d(n)))};
      for (const Vec3& w : out)
        if (glm::dot(w, n) > 0) check(spawn_ray(hit.p, hit.p_error, n, w), false);
      DVec3 nd = glm::normalize(to_d(n));
      Vec3 tf = to_f(to_d(hit.p) + rf * rng.log_uniform(1e-1, 1e2) * nd +
                     rf * rng.log_uniform(1e-3, 10) * tangent(rng, nd));
      // The target must lie clearly above the tangent plane at the exact hit
      // point, so that the segment cannot reach the sphere: its distance from
      // the center exceeds r by more than the hit point's rounding.
      if (glm::length(to_d(tf) - to_d(cf)) > rf + 2 * glm::length(to_d(hit.p_error)) &&
          glm::dot(to_d(tf) - to_d(hit.p), nd) > 0)
        check(spawn_ray_to(hit.p, hit.p_error, n, tf), true);
    }
    std::printf("1e%d..1e%d  %8zu %8zu %10zu %8zu\n", dec - 7, dec - 6, cases, used, rays, rehits);
    EXPECT_EQ(rehits, 0u) << "r/|c| in 1e" << dec - 7 << "..1e" << dec - 6 << ", first: " << first;
    EXPECT_GT(used, cases / 2) << "too many primary rays missed";
  }
}

// Long double distances for the checks below: the hit points are floats, so
// long double (64-bit significand on x86-64) decides exactly which side of a
// float-sized sphere they lie on.
using LVec = glm::vec<3, long double>;
LVec to_l(const Vec3& v) {
  return LVec(v);
}

TEST(SelfIntersection, SphereHitsAtAnyDistance) {
  // The property of sphere hits at every scale the issue names: r/|c| in
  // every decade from 1e-8 to 1 (down to spheres smaller than the float
  // spacing at their center) and rays that travel 1 to 1e7 radii before they
  // hit. For each hit:
  //  - the normal and the point agree: p lies within p_error (per axis) of
  //    center + r n, measured in long double (a float point o + t d next to
  //    a normal computed from the exact offset disagreed by degrees after
  //    1e6 radii);
  //  - origins spawned outward by offset_ray_origin lie outside the sphere;
  //  - rays spawned outward (mirror reflection, two random directions) and a
  //    shadow ray to a point above the tangent plane never hit the sphere.
  // Every count must be 0. The table goes to docs/accuracy.md ("Sphere hits
  // at any distance").
  constexpr int kBands = 8;    // r/|c| 1e-8..1
  constexpr int kTravels = 7;  // travel 1..1e7 radii
  const size_t cases = rstest::stress_scaled(20000);
  size_t total_rays = 0;
  std::printf("r/|c| band    travel (radii)   used  rays  inconsistent  inside  re-hits\n");
  for (int band = 0; band < kBands; ++band) {
    for (int travel = 0; travel < kTravels; ++travel) {
      Rng rng(3100 + uint32_t(band * kTravels + travel));
      size_t used = 0, rays = 0, inconsistent = 0, inside = 0, rehits = 0;
      std::string first;
      for (size_t i = 0; i < cases; ++i) {
        DVec3 center(rng.log_uniform_signed(1e-6, 1e6), rng.log_uniform_signed(1e-6, 1e6),
                     rng.log_uniform_signed(1e-6, 1e6));
        const double lo = std::pow(10.0, -8 + band);
        const double r = rstest::max_abs(center) * rng.log_uniform(lo, 10 * lo);
        Scene scene;
        scene.spheres.push_back(rayscope::Sphere{"s", to_f(center), rstest::round_f(r), 0});
        scene.commit();
        const Vec3 cf = scene.spheres[0].center;
        const double rf = scene.spheres[0].radius;
        const DVec3 wdir = rng.unit_vector();
        const double dist =
            1.0 + rng.log_uniform(std::pow(10.0, travel), std::pow(10.0, travel + 1));
        const Vec3 o = to_f(to_d(cf) + rf * dist * wdir);
        const DVec3 aim = to_d(cf) + 0.99 * rf * std::sqrt(rng.uniform()) * tangent(rng, wdir);
        const Vec3 d = to_f((aim - to_d(o)) * rng.log_uniform(1e-2, 1e2));
        SurfaceHit hit;
        if (!scene.intersect(Ray{o, d, kInfinity}, hit) || !(glm::dot(d, hit.ng) < 0.0f)) continue;
        ++used;
        const Vec3 n = hit.ng;
        const LVec lc = to_l(cf);
        const LVec on_surface = lc + (long double)rf * to_l(n) / glm::length(to_l(n));
        const LVec off = glm::abs(to_l(hit.p) - on_surface);
        // The normal's own rounding (2^-24 r per axis) is within p_error too.
        if (!(off.x <= hit.p_error.x && off.y <= hit.p_error.y && off.z <= hit.p_error.z) &&
            ++inconsistent == 1 && first.empty())
          first = "p off center + r n by (" + std::to_string(double(off.x)) + ", " +
                  std::to_string(double(off.y)) + ", " + std::to_string(double(off.z)) + ")";
        auto check = [&](const Ray& ray, bool any_hit_only) {
          ++rays;
          if (glm::length(to_l(ray.origin) - lc) <= (long double)rf && ++inside == 1 &&
              first.empty())
            first = "spawned origin inside the sphere";
          SurfaceHit h2;
          const bool again = !any_hit_only && scene.intersect(ray, h2);
          const bool blocked = scene.occluded(ray);
          if ((again || blocked) && ++rehits == 1) {
            char buf[512];
            std::snprintf(buf, sizeof buf,
                          "re-hit: c=(%.9g, %.9g, %.9g) r=%.9g o=(%.9g, %.9g, %.9g) "
                          "p=(%.9g, %.9g, %.9g) origin=(%.9g, %.9g, %.9g) t=%g",
                          cf.x, cf.y, cf.z, rf, o.x, o.y, o.z, hit.p.x, hit.p.y, hit.p.z,
                          ray.origin.x, ray.origin.y, ray.origin.z, again ? h2.t : -1.0);
            first = buf;
          }
        };
        const Vec3 refl = reflect(glm::normalize(d), n);
        const Vec3 out[3] = {refl, to_f(hemisphere(rng, to_d(n))), to_f(hemisphere(rng, to_d(n)))};
        for (const Vec3& w : out)
          if (glm::dot(w, n) > 0) check(spawn_ray(hit.p, hit.p_error, n, w), false);
        const DVec3 nd = glm::normalize(to_d(n));
        const Vec3 tf = to_f(to_d(hit.p) + rf * rng.log_uniform(1e-1, 1e2) * nd +
                             rf * rng.log_uniform(1e-3, 10) * tangent(rng, nd));
        // A target clearly above the tangent plane at the exact hit point
        // (beyond the hit point's rounding), so that the segment cannot
        // reach the sphere.
        if (glm::length(to_d(tf) - to_d(cf)) > rf + 2 * glm::length(to_d(hit.p_error)) &&
            glm::dot(to_d(tf) - to_d(hit.p), nd) > 0)
          check(spawn_ray_to(hit.p, hit.p_error, n, tf), true);
      }
      total_rays += rays;
      std::printf("1e%d..1e%d   1e%d..1e%d  %8zu %8zu %6zu %6zu %6zu\n", band - 8, band - 7, travel,
                  travel + 1, used, rays, inconsistent, inside, rehits);
      const std::string where = "r/|c| 1e" + std::to_string(band - 8) + ", travel 1e" +
                                std::to_string(travel) + " radii: ";
      EXPECT_EQ(inconsistent, 0u) << where << first;
      EXPECT_EQ(inside, 0u) << where << first;
      EXPECT_EQ(rehits, 0u) << where << first;
      // Float cannot aim at a sphere much smaller than the spacing of the
      // origin's coordinates: the far travels of the smallest bands lose
      // most primary rays, the rest must keep most.
      if (band >= 2 && travel <= 4) {
        EXPECT_GT(used, cases / 2) << where << "too many misses";
      }
    }
  }
  std::printf("%zu spawned rays in all\n", total_rays);
}

TEST(SelfIntersection, TubeHitsAtAnyScaleAndDistance) {
  // Tube segments (capsules) of every scale the issue names, with the sphere
  // test's scrutiny (SphereHitsAtAnyDistance): segment centres with
  // log-uniform coordinates 1e-6..1e6, radius r with r/|c| in every other
  // decade from 1e-7 to 1, lengths 0.1..100 r, rays that travel 1 to 1e6
  // radii before they hit (side or cap). For each hit:
  //  - the point lies on the surface within its bound along the normal
  //    (|distance to the segment - r| <= |n| . p_error, long double);
  //  - origins spawned outward by offset_ray_origin lie outside the capsule;
  //  - rays spawned outward (mirror reflection, two random directions) and a
  //    shadow ray to a point above the tangent plane never hit the tube.
  // Every count must be 0.
  using rstest::ref_segment_distance;
  const size_t cases = rstest::stress_scaled(4000);
  size_t total_rays = 0;
  std::printf("r/|c|   travel (radii)   used    rays  off-surface  inside  re-hits\n");
  for (int band = 0; band < 4; ++band) {
    for (int travel = 0; travel < 6; ++travel) {
      Rng rng(3300 + uint32_t(band * 6 + travel));
      size_t used = 0, rays = 0, off_surface = 0, inside = 0, rehits = 0;
      std::string first;
      for (size_t i = 0; i < cases; ++i) {
        const DVec3 center(rng.log_uniform_signed(1e-6, 1e6), rng.log_uniform_signed(1e-6, 1e6),
                           rng.log_uniform_signed(1e-6, 1e6));
        const double rel = std::pow(10.0, -7 + 2 * band);
        const double r = rstest::max_abs(center) * rng.log_uniform(rel, 10 * rel);
        const double len = r * rng.log_uniform(0.1, 100);
        const DVec3 axis = rng.unit_vector();
        TubeSet ts;
        ts.name = "t";
        ts.positions = {to_f(center - 0.5 * len * axis), to_f(center + 0.5 * len * axis)};
        ts.segments = {{0, 1}};
        ts.radius = rstest::round_f(r);
        Scene scene;
        scene.tubes = {ts};
        scene.commit();
        const Vec3 a = scene.tubes[0].positions[0], b = scene.tubes[0].positions[1];
        const float rf = scene.tubes[0].radius;
        const LVec la = to_l(a), lb = to_l(b);
        // Aim at a point within 0.99 r of the segment (or past an end, for
        // the caps), from `travel` decades of radii away.
        const DVec3 aim = to_d(a) + rng.uniform(-0.2, 1.2) * (to_d(b) - to_d(a)) +
                          0.99 * double(rf) * rng.in_unit_ball();
        const double dist =
            1.0 + rng.log_uniform(std::pow(10.0, travel), std::pow(10.0, travel + 1));
        const Vec3 o = to_f(aim + double(rf) * dist * rng.unit_vector());
        const Vec3 d = to_f((aim - to_d(o)) * rng.log_uniform(1e-2, 1e2));
        if (ref_segment_distance(to_l(o), la, lb) <= (long double)rf) continue;
        SurfaceHit hit;
        if (!scene.intersect(Ray{o, d, kInfinity}, hit) || !(glm::dot(d, hit.ng) < 0.0f)) continue;
        ++used;
        const Vec3 n = hit.ng;
        const long double off = std::abs(ref_segment_distance(to_l(hit.p), la, lb) - rf);
        if (off > glm::dot(glm::abs(to_l(n)), to_l(hit.p_error)) && ++off_surface == 1 &&
            first.empty())
          first = "p off the surface by " + std::to_string(double(off));
        auto check = [&](const Ray& ray, bool any_hit_only) {
          ++rays;
          if (ref_segment_distance(to_l(ray.origin), la, lb) <= (long double)rf && ++inside == 1 &&
              first.empty())
            first = "spawned origin inside the capsule";
          SurfaceHit h2;
          const bool again = !any_hit_only && scene.intersect(ray, h2);
          const bool blocked = scene.occluded(ray);
          if ((again || blocked) && ++rehits == 1) {
            char buf[512];
            std::snprintf(buf, sizeof buf,
                          "re-hit: a=(%.9g, %.9g, %.9g) b=(%.9g, %.9g, %.9g) r=%.9g "
                          "p=(%.9g, %.9g, %.9g) origin=(%.9g, %.9g, %.9g) t=%g",
                          a.x, a.y, a.z, b.x, b.y, b.z, rf, hit.p.x, hit.p.y, hit.p.z, ray.origin.x,
                          ray.origin.y, ray.origin.z, again ? h2.t : -1.0);
            first = buf;
          }
        };
        const Vec3 refl = reflect(glm::normalize(d), n);
        const Vec3 out[3] = {refl, to_f(hemisphere(rng, to_d(n))), to_f(hemisphere(rng, to_d(n)))};
        for (const Vec3& w : out)
          if (glm::dot(w, n) > 0) check(spawn_ray(hit.p, hit.p_error, n, w), false);
        // A light clearly above the tangent plane at the hit (beyond the
        // point's rounding): the segment to it cannot reach the capsule.
        const DVec3 nd = glm::normalize(to_d(n));
        const Vec3 target = to_f(to_d(hit.p) + double(rf) * rng.log_uniform(1e-1, 1e2) * nd +
                                 double(rf) * rng.log_uniform(1e-3, 10) * tangent(rng, nd));
        if (ref_segment_distance(to_l(target), la, lb) > rf + 2 * glm::length(to_l(hit.p_error)) &&
            glm::dot(to_d(target) - to_d(hit.p), nd) > 0)
          check(spawn_ray_to(hit.p, hit.p_error, n, target), true);
      }
      total_rays += rays;
      std::printf("1e%d..1e%d  1e%d..1e%d  %8zu %8zu %6zu %6zu %6zu\n", 2 * band - 7, 2 * band - 6,
                  travel, travel + 1, used, rays, off_surface, inside, rehits);
      const std::string where = "r/|c| 1e" + std::to_string(2 * band - 7) + ", travel 1e" +
                                std::to_string(travel) + " radii: ";
      EXPECT_EQ(off_surface, 0u) << where << first;
      EXPECT_EQ(inside, 0u) << where << first;
      EXPECT_EQ(rehits, 0u) << where << first;
      // Float cannot aim at a tube much thinner than the spacing of the
      // origin's coordinates: only the nearer travels must keep most rays.
      if (band >= 1 && travel <= 3) {
        EXPECT_GT(used, cases / 2) << where << "too many misses";
      }
    }
  }
  std::printf("%zu spawned rays in all\n", total_rays);
}

TEST(SelfIntersection, TrianglesAndPlanesAfterLongTravel) {
  // The same scrutiny for the other primitives' hits after rays travel 1 to
  // 1e7 times the primitive's size: their normals come from the geometry
  // (the triangle's corners, the plane's normal), not from the ray, and the
  // point is interpolated (triangle) or re-projected (plane), so the point's
  // distance from the exact surface stays within the bound it carries, and
  // outward rays never come back.
  const size_t cases = rstest::stress_scaled(4000);
  for (int travel = 0; travel < 7; ++travel) {
    Rng rng(3200 + uint32_t(travel));
    size_t used = 0, rays = 0, off_surface = 0, rehits = 0;
    for (size_t i = 0; i < cases; ++i) {
      const DVec3 base(rng.log_uniform_signed(1e-6, 1e6), rng.log_uniform_signed(1e-6, 1e6),
                       rng.log_uniform_signed(1e-6, 1e6));
      const double size = rstest::max_abs(base) * rng.log_uniform(1e-4, 1.0);
      const bool plane = i % 2 == 1;
      Scene scene;
      DVec3 a, b, c;
      if (plane) {
        scene.planes.push_back(Plane{"p", to_f(base), to_f(rng.unit_vector()), 0});
        scene.commit();
        const DVec3 nd = glm::normalize(to_d(scene.planes[0].normal));
        a = to_d(scene.planes[0].point);
        const DVec3 t1 = tangent(rng, nd), t2 = glm::cross(nd, t1);
        b = a + size * t1;
        c = a + size * t2;
      } else {
        Vec3 v[3];
        do {
          for (Vec3& p : v) p = to_f(base + size * rng.in_unit_ball());
        } while (glm::length(glm::cross(to_d(v[1]) - to_d(v[0]), to_d(v[2]) - to_d(v[0]))) <
                 0.1 * size * size);
        TriangleMesh m;
        m.positions = {v[0], v[1], v[2]};
        m.triangles = {{0, 1, 2}};
        scene.meshes = {m};
        scene.commit();
        a = to_d(v[0]);
        b = to_d(v[1]);
        c = to_d(v[2]);
      }
      const DVec3 nexact = glm::normalize(glm::cross(b - a, c - a));
      const DVec3 q = (a + b + c) / 3.0 + 0.2 * ((b - a) * rng.uniform() + (c - a) * rng.uniform() -
                                                 0.5 * (b - a) - 0.5 * (c - a));
      const double cs = rng.log_uniform(1e-2, 1.0);
      DVec3 w = cs * nexact + std::sqrt(1 - cs * cs) * tangent(rng, nexact);
      if (rng.coin()) w = -w;
      const double dist = rng.log_uniform(std::pow(10.0, travel), std::pow(10.0, travel + 1));
      const Vec3 o = to_f(q + size * dist * w);
      const Vec3 d = to_f((q - to_d(o)) * rng.log_uniform(1e-2, 1e2));
      SurfaceHit hit;
      if (!scene.intersect(Ray{o, d, kInfinity}, hit)) continue;
      ++used;
      const Vec3 n = glm::dot(d, hit.ng) < 0 ? hit.ng : -hit.ng;
      // Distance of p from the exact plane against the bound along the normal.
      const long double dist_off = std::abs(glm::dot(to_l(hit.p) - to_l(to_f(a)), LVec(nexact)));
      if (dist_off > glm::dot(glm::abs(to_l(hit.ng)), to_l(hit.p_error)) * 1.0001L) ++off_surface;
      const Vec3 refl = reflect(glm::normalize(d), n);
      const Vec3 out[2] = {refl, to_f(hemisphere(rng, to_d(n)))};
      for (const Vec3& wo : out) {
        if (!(glm::dot(wo, n) > 0)) continue;
        ++rays;
        SurfaceHit h2;
        const Ray r = spawn_ray(hit.p, hit.p_error, n, wo);
        if (scene.intersect(r, h2) || scene.occluded(r)) ++rehits;
      }
    }
    std::printf(
        "triangles and planes, travel 1e%d..1e%d sizes: %zu used, %zu rays, %zu off "
        "the surface, %zu re-hits\n",
        travel, travel + 1, used, rays, off_surface, rehits);
    EXPECT_EQ(off_surface, 0u) << "travel 1e" << travel;
    EXPECT_EQ(rehits, 0u) << "travel 1e" << travel;
    EXPECT_GT(used, cases / 2) << "travel 1e" << travel;
  }
}

TEST(SelfIntersection, OffsetIsNotLostToRounding) {
  // offset_ray_origin's guarantee, which the ray tests above cannot isolate
  // (the hit points' error bounds are several ulps, rounding costs at most
  // half of one): the spawned origin lies at least the error bound
  // d = |n| . p_error beyond p along n (on the side of w), measured exactly in
  // double. The one-ulp outward step after rounding p + d n is what makes
  // this hold; rounding to nearest alone loses up to half an ulp, and when d
  // is below half an ulp of a coordinate (p_error from 1e-10 to 1e-5 of |p|
  // here) p + d n rounds back to p itself.
  Rng rng(14);
  int fails = 0;
  for (int i = 0; i < 100000; ++i) {
    const Vec3 p = to_f(DVec3(rng.log_uniform_signed(1e-6, 1e6), rng.log_uniform_signed(1e-6, 1e6),
                              rng.log_uniform_signed(1e-6, 1e6)));
    const double rel = rng.log_uniform(1e-10, 1e-5);
    const Vec3 p_error = to_f(rel * glm::abs(to_d(p)));
    const Vec3 n = to_f(rng.unit_vector());
    const Vec3 w = to_f(rng.unit_vector());
    const Vec3 po = offset_ray_origin(p, p_error, n, w);
    const DVec3 side = glm::dot(w, n) < 0.0f ? -to_d(n) : to_d(n);
    const double d = glm::dot(glm::abs(to_d(n)), to_d(p_error));
    const DVec3 moved = to_d(po) - to_d(p);
    // Every coordinate moves by at least its share of the offset, outward.
    for (int k = 0; k < 3; ++k)
      if (side[k] != 0.0 &&
          !(moved[k] * (side[k] > 0 ? 1 : -1) >= std::abs(d * side[k]) * 0.999999)) {
        if (++fails <= 5)
          ADD_FAILURE() << "coordinate " << k << " moved " << moved[k] << ", needs " << d * side[k]
                        << " (p=" << p[k] << ", p_error=" << p_error[k] << ")";
        break;
      }
  }
  EXPECT_EQ(fails, 0);
}

// ---------------------------------------------------------------------------
// Planes

TEST(SelfIntersection, PlanesOfAnyScale) {
  Rng rng(13);
  Counts cnt;
  for (int i = 0; i < 20000; ++i) {
    DVec3 point(rng.log_uniform_signed(1e-6, 1e6), rng.log_uniform_signed(1e-6, 1e6),
                rng.log_uniform_signed(1e-6, 1e6));
    Scene scene;
    scene.planes.push_back(Plane{"p", to_f(point), to_f(rng.unit_vector()), 0});
    scene.commit();  // normalizes the normal
    const Plane& pl = scene.planes[0];
    const DVec3 nd = glm::normalize(to_d(pl.normal));
    ++cnt.cases;
    double scale = std::max(rstest::max_abs(point), 1e-3);
    DVec3 q = to_d(pl.point) + scale * rng.log_uniform(1e-3, 10) * tangent(rng, nd);
    double cs = rng.log_uniform(1e-3, 1.0);
    DVec3 w = cs * nd + std::sqrt(1 - cs * cs) * tangent(rng, nd);
    if (rng.coin()) w = -w;
    Vec3 o = to_f(q + scale * rng.log_uniform(1e-4, 10) * w);
    Vec3 d = to_f((q - to_d(o)) * rng.log_uniform(1e-2, 1e2));
    SurfaceHit hit;
    if (!scene.intersect(Ray{o, d, kInfinity}, hit)) continue;
    ++cnt.used;
    const Vec3 n = glm::dot(d, hit.ng) < 0 ? hit.ng : -hit.ng;
    const DVec3 nside = glm::dot(to_d(n), nd) > 0 ? nd : -nd;
    const Vec3 dn = glm::normalize(d);
    auto expect_miss = [&](const Ray& r, const char* kind) {
      ++cnt.rays;
      SurfaceHit h2;
      EXPECT_FALSE(scene.intersect(r, h2)) << kind << " ray re-hit the plane, case " << i;
      EXPECT_FALSE(scene.occluded(r)) << kind << " case " << i;
    };
    Vec3 r = reflect(dn, n);
    if (glm::dot(r, n) > 0) expect_miss(spawn_ray(hit.p, hit.p_error, n, r), "reflection");
    Vec3 hw = to_f(hemisphere(rng, to_d(n)));
    if (glm::dot(hw, n) > 0) expect_miss(spawn_ray(hit.p, hit.p_error, n, hw), "hemisphere");
    expect_miss(spawn_ray(hit.p, hit.p_error, n, d), "continuing");
    Vec3 t;
    if (refract(dn, n, 1.0f, 1.5f, t) && glm::dot(t, n) < 0)
      expect_miss(spawn_ray(hit.p, hit.p_error, n, t), "refraction");
    DVec3 target = to_d(hit.p) + scale * rng.log_uniform(1e-3, 1e2) * nside +
                   scale * rng.log_uniform(1e-3, 10) * tangent(rng, nside);
    Vec3 tf = to_f(target);
    if (glm::dot(to_d(tf) - to_d(pl.point), nside) > 1e-4 * scale)
      expect_miss(spawn_ray_to(hit.p, hit.p_error, n, tf), "shadow");
    if (HasFailure()) return;
  }
  report("planes", cnt);
}

}  // namespace
