// Grazing rays through whole scenes: rays lying in the plane of a flat mesh
// (no hit: every edge function is 0), nearly in it (every one hits, on the
// plane), leaving it at angles down to 1e-7 rad (never a self-intersection);
// rays tangent to spheres and along a closed mesh's edges through the
// integrator (finite results for glass, mirror and diffuse); a camera in the
// plane of the floor and of a mesh (no NaN pixel). (Single triangles at
// grazing angles: test_intersect; spawned rays: test_self_intersection.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "rayscope/integrator.h"
#include "rayscope/render.h"
#include "rayscope/scene.h"
#include "rayscope/shapes.h"
#include "scene_test_util.h"
#include "test_util.h"

namespace {

using namespace rayscope;
using rstest::count_nonfinite;
using rstest::DVec3;
using rstest::finite_color;
using rstest::mesh_scene;
using rstest::render_scene;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

TEST(Grazing, RaysInThePlaneOfTrianglesAndAlongEdges) {
  // A flat grid mesh in the plane z = 0.5 (coordinates multiples of 1/8: all
  // exact). A ray lying exactly in that plane meets every triangle edge-on: in
  // the watertight test all sheared coordinates across the ray vanish, every
  // edge function is 0 and the triangle is rejected, so no hit is reported,
  // whether the ray runs along grid lines through the vertices or at random
  // angles. Rays that only nearly lie in the plane may hit; their hits must be
  // finite and on the plane.
  TriangleMesh grid;
  grid.name = "grid";
  const int n = 8;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      grid.positions.emplace_back(float(i) / 8.0f - 0.5f, float(j) / 8.0f - 0.5f, 0.5f);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      grid.triangles.emplace_back(a, b, d);
      grid.triangles.emplace_back(a, d, c);
    }
  Scene s;
  s.meshes = {grid};
  s.commit();
  ASSERT_TRUE(s.summary().walks_structure);
  Rng rng(5);
  size_t in_plane_hits = 0;
  auto in_plane = [&](const Vec3& o, const Vec3& d) {
    Ray ray{o, d, kInfinity};
    SurfaceHit h;
    if (s.intersect(ray, h) || s.occluded(ray)) ++in_plane_hits;
  };
  for (int k = 0; k <= n; ++k) {
    const float c = float(k) / 8.0f - 0.5f;
    for (float sign : {1.0f, -1.0f}) {
      in_plane(Vec3(-2.0f * sign, c, 0.5f), Vec3(sign, 0.0f, 0.0f));  // along grid lines
      in_plane(Vec3(c, -2.0f * sign, 0.5f), Vec3(0.0f, sign, -0.0f));
      in_plane(Vec3(c, c, 0.5f), Vec3(sign, 0.0f, 0.0f));  // starting on a vertex
    }
  }
  in_plane(Vec3(-1.0f, -1.0f, 0.5f), Vec3(1.0f, 1.0f, 0.0f));  // along the diagonals
  in_plane(Vec3(-0.5f, 0.5f, 0.5f), Vec3(1.0f, -1.0f, 0.0f));  // (not the split edges)
  for (int i = 0; i < 20000; ++i) {
    DVec3 u = rng.unit_vector();
    in_plane(Vec3(float(rng.uniform(-1, 1)), float(rng.uniform(-1, 1)), 0.5f),
             to_f(DVec3(u.x, u.y, 0.0)));
  }
  EXPECT_EQ(in_plane_hits, 0u);

  // Nearly in the plane: rays crossing it at a point q at most 0.45 from the
  // grid's center at grazing angles of 1e-6..1e-2 rad, from 0.1..2 away. The
  // rounding of the origin (<= 3e-8 across the plane) moves the crossing by
  // at most 3e-8 / 1e-6 = 0.03 along it, less than the 0.05 margin to the
  // grid's border: every ray must hit. (Before the fix of the triangle test's
  // t error bound for grazing rays, 10% of the rays at ~1e-4 rad and 90% at
  // ~1e-5 rad passed through the mesh.)
  size_t near_rays = 0, near_hits = 0;
  for (int i = 0; i < 20000; ++i) {
    DVec3 q(rng.uniform(-0.45, 0.45), rng.uniform(-0.45, 0.45), 0.5);
    DVec3 u = rng.unit_vector();
    u.z = 0.0;
    if (glm::length(u) < 1e-3) continue;
    double alpha = rng.log_uniform(1e-6, 1e-2), side = rng.coin() ? 1.0 : -1.0;
    DVec3 d = std::cos(alpha) * glm::normalize(u) - side * std::sin(alpha) * DVec3(0, 0, 1);
    Ray ray{to_f(q - rng.uniform(0.1, 2.0) * d), to_f(d), kInfinity};
    SurfaceHit h;
    ++near_rays;
    if (!s.intersect(ray, h)) continue;
    ++near_hits;
    ASSERT_TRUE(std::isfinite(h.t) && h.t > 0.0f && all_finite(h.p) && all_finite(h.ng));
    // On the plane within the hit's own error bound.
    ASSERT_LE(std::abs(h.p.z - 0.5f), h.p_error.z) << "hit off the plane";
  }
  // Leaving the plane: from a point exactly on it (or up to 1e-6 off it on the
  // side the ray leaves to) at grazing angles of 1e-7..1e-2 rad. The exact t
  // of the plane is <= 0, so a hit would be a self-intersection: the t error
  // bound must reject every one, however small the angle.
  size_t leaving_hits = 0;
  for (int i = 0; i < 20000; ++i) {
    DVec3 u = rng.unit_vector();
    u.z = 0.0;
    if (glm::length(u) < 1e-3) continue;
    double alpha = rng.log_uniform(1e-7, 1e-2), side = rng.coin() ? 1.0 : -1.0;
    DVec3 d = std::cos(alpha) * glm::normalize(u) + side * std::sin(alpha) * DVec3(0, 0, 1);
    Vec3 o(float(rng.uniform(-0.45, 0.45)), float(rng.uniform(-0.45, 0.45)), 0.5f);
    if (i % 2) o.z = to_f(DVec3(0, 0, 0.5 + side * rng.log_uniform(1e-9, 1e-6))).z;
    Ray ray{o, to_f(d), kInfinity};
    SurfaceHit h;
    if (s.intersect(ray, h) || s.occluded(ray)) ++leaving_hits;
  }
  EXPECT_EQ(leaving_hits, 0u);
  std::printf("%zu nearly in-plane rays, %zu hits\n", near_rays, near_hits);
  EXPECT_EQ(near_hits, near_rays);
}

TEST(Grazing, TangentRaysAndEdgeRaysThroughTheIntegrator) {
  // Rays tangent to spheres (impact parameter r within a few ulps) and rays
  // running along the edges of a closed icosphere, outside it: hit or not,
  // every result is finite, and the integrator returns a finite color for
  // glass, mirror and diffuse materials.
  Scene s;
  Material diffuse, mirror, glass;
  mirror.reflectivity = 0.9f;
  glass.transparency = 1.0f;
  glass.ambient = 0.0f;
  glass.ior = 1.5f;
  s.materials = {diffuse, mirror, glass};
  s.background = Color(0.5f);
  s.spheres = {Sphere{"diffuse", Vec3(0.0f), 1.0f, 0},
               Sphere{"mirror", Vec3(3.0f, 0.0f, 0.0f), 1.0f, 1},
               Sphere{"glass", Vec3(-3.0f, 0.5f, 0.25f), 1.5f, 2}};
  TriangleMesh ico = make_icosphere(Vec3(0.0f, 4.0f, 0.0f), 1.0f, 2);
  ico.material = 2;
  s.meshes = {ico};
  Light l;
  l.position = Vec3(0.0f, 10.0f, 10.0f);
  s.lights = {l};
  s.commit();
  RenderSettings rs;
  rs.max_depth = 8;
  RayCounters counters;
  NullRecorder rec;
  WhittedIntegrator<NullRecorder> integrator(s, rs, counters, rec);
  Rng rng(8);
  size_t rays = 0, hits = 0;
  auto check = [&](const Vec3& o, const Vec3& d) {
    Ray ray{o, d, kInfinity};
    SurfaceHit h;
    ++rays;
    if (s.intersect(ray, h)) {
      ++hits;
      ASSERT_TRUE(std::isfinite(h.t) && h.t > 0.0f && all_finite(h.p) && all_finite(h.ng) &&
                  all_finite(h.ns));
      ASSERT_NEAR(glm::length(h.ng), 1.0f, 1e-5f);
    }
    Color c = integrator.trace(ray, RayKind::Primary, 0, Color(1.0f), -1);
    ASSERT_TRUE(finite_color(c)) << "o=(" << o.x << "," << o.y << "," << o.z << ") d=(" << d.x
                                 << "," << d.y << "," << d.z << ")";
  };
  for (const Sphere& sp : s.spheres)
    for (int i = 0; i < 2000; ++i) {
      DVec3 d = rng.unit_vector(), side = glm::normalize(glm::cross(d, rng.unit_vector()));
      double b = double(sp.radius) * (1.0 + double(rng.integer(-8, 8)) * 6e-8);
      DVec3 o = to_d(sp.center) + b * side - 5.0 * double(sp.radius) * d;
      check(to_f(o), to_f(d));
    }
  for (const glm::uvec3& t : ico.triangles)
    for (int e = 0; e < 3; ++e) {
      const Vec3 a = ico.positions[t[e]], b = ico.positions[t[(e + 1) % 3]];
      check(a - (b - a), b - a);  // along the edge, from outside
      check(b + 0.5f * (b - a), a - b);
    }
  std::printf("%zu tangent and edge rays, %zu hits\n", rays, hits);
  EXPECT_GT(hits, rays / 10);
}

TEST(Grazing, CameraInThePlaneOfTheFloorAndOfAMesh) {
  // The default scene seen from an eye exactly on the floor plane (every
  // floor hit would have t = 0: none is reported) and from exactly the plane
  // of a flat mesh: no pixel is NaN.
  Scene s = make_default_scene();
  s.camera.eye = Vec3(0.0f, 0.0f, 7.0f);
  s.camera.look_at = Vec3(0.0f, 0.0f, 0.0f);
  Framebuffer fb = render_scene(s, 64, 48, 2);
  EXPECT_EQ(count_nonfinite(fb), 0u);

  TriangleMesh quad;
  quad.positions = {{-1, 0.25f, -1}, {1, 0.25f, -1}, {1, 0.25f, 1}, {-1, 0.25f, 1}};
  quad.triangles = {{0, 2, 1}, {0, 3, 2}};
  Scene q = mesh_scene(quad);
  q.camera.eye = Vec3(0.0f, 0.25f, 4.0f);
  q.camera.look_at = Vec3(0.0f, 0.25f, 0.0f);
  fb = render_scene(q, 64, 48, 2);
  EXPECT_EQ(count_nonfinite(fb), 0u);
}

}  // namespace
