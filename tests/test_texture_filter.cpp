// The box-filtered checkerboard (material_color_filtered, material.h) and
// the footprints of primary samples (footprint, ray.h; the
// camera's differentials): the closed form against a brute-force average of
// the unfiltered checker over the same box, exactness for zero and
// single-cell footprints, the footprint of a known camera, and what the
// filter does to a render (closer to the converged image than point
// sampling at the same sample count; replays and thread counts unchanged).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>

#include "rayscope/camera.h"
#include "rayscope/material.h"
#include "rayscope/render.h"
#include "rayscope/replay.h"
#include "rayscope/shapes.h"
#include "test_util.h"

namespace {

using namespace rayscope;

// Midpoints per axis of the brute-force means: fewer under the sanitizers
// (the bound on the midpoint rule's error follows the count).
#ifdef RAYSCOPE_SANITIZE
constexpr int kFloorGrid = 400, kBoxGrid = 80;
#else
constexpr int kFloorGrid = 1000, kBoxGrid = 200;
#endif

Material checker(float size) {
  Material m;
  m.checker = true;
  m.color = Color(0.9f, 0.8f, 0.7f);
  m.checker_color = Color(0.1f, 0.2f, 0.3f);
  m.checker_size = size;
  return m;
}

// The mean of the unfiltered checker over the box p +- h, by the midpoint
// rule on a g[0] x g[1] x g[2] grid (an axis with h == 0 is sampled once, at
// p). The checker is a product of square waves, so on a tensor grid the
// midpoint rule's error is at most the sum over the axes of (faces inside
// the box's side) / g: a grid cell holding a face misjudges at most its whole
// width, 1/g of the side, by a jump of 2 in a wave of mean |.| <= 1, and the
// color is (a + b)/2 + (a - b)/2 * product. Returns that bound too.
Color brute_mean(const Material& m, const Vec3& p, const Vec3& h, const DVec3& origin,
                 const int g[3], double& bound) {
  DVec3 sum(0.0);
  const int gx = h.x > 0 ? g[0] : 1, gy = h.y > 0 ? g[1] : 1, gz = h.z > 0 ? g[2] : 1;
  auto at = [](float c, float hw, int i, int n) {
    return n == 1 ? c : float(double(c) - hw + (2.0 * hw) * (i + 0.5) / n);
  };
  for (int i = 0; i < gx; ++i)
    for (int j = 0; j < gy; ++j)
      for (int k = 0; k < gz; ++k)
        sum += DVec3(material_color(
            m, Vec3(at(p.x, h.x, i, gx), at(p.y, h.y, j, gy), at(p.z, h.z, k, gz)), origin));
  const double s = double(m.checker_size);
  bound = 0.0;
  const int gg[3] = {gx, gy, gz};
  for (int a = 0; a < 3; ++a)
    if (h[a] > 0) bound += (std::ceil(2.0 * double(h[a]) / s) + 1.0) / gg[a];
  bound *= 0.5 * double(max_component(glm::abs(m.color - m.checker_color)));
  return Color(sum / double(gx * gy * gz));
}

TEST(TextureFilter, ClosedFormEqualsBruteForceOnAFloor) {
  // Footprints on a floor (y = 0, no extent along y, as the render gives):
  // kFloorGrid^2 midpoints per box.
  rstest::Rng rng(7);
  const Material m = checker(1.0f);
  const int g[3] = {kFloorGrid, 1, kFloorGrid};
  for (int c = 0; c < 12; ++c) {
    const Vec3 p(float(rng.uniform(-20, 20)), 0.0f, float(rng.uniform(-40, 5)));
    const Vec3 h(float(rng.log_uniform(1e-3, 3.0)), 0.0f, float(rng.log_uniform(1e-3, 3.0)));
    double bound;
    const Color want = brute_mean(m, p, h, DVec3(0.0), g, bound);
    const Color got = material_color_filtered(m, p, h, DVec3(0.0));
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(got[ch], want[ch], bound + 1e-5)
          << "p " << p.x << "," << p.z << " half width " << h.x << "," << h.z;
  }
}

TEST(TextureFilter, ClosedFormEqualsBruteForceIn3D) {
  // Boxes with extent on all three axes, cells of other sizes, a scene
  // origin far away (the checker lives in world space): kBoxGrid^3 midpoints.
  rstest::Rng rng(11);
  const int g[3] = {kBoxGrid, kBoxGrid, kBoxGrid};
  for (int c = 0; c < 6; ++c) {
    const Material m = checker(float(rng.uniform(0.3, 2.0)));
    const DVec3 origin = c % 2 ? DVec3(1e5, -3e4, 2e5) : DVec3(0.0);
    const Vec3 p(float(rng.uniform(-5, 5)), float(rng.uniform(-5, 5)), float(rng.uniform(-5, 5)));
    const Vec3 h(float(rng.uniform(0.05, 1.5)), float(rng.uniform(0.05, 1.5)),
                 float(rng.uniform(0.05, 1.5)));
    double bound;
    const Color want = brute_mean(m, p, h, origin, g, bound);
    const Color got = material_color_filtered(m, p, h, origin);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got[ch], want[ch], bound + 1e-5) << "case " << c;
  }
}

TEST(TextureFilter, WideFootprintTendsToTheMeanColor) {
  const Material m = checker(1.0f);
  const Color mean = 0.5f * (m.color + m.checker_color);
  const Color got =
      material_color_filtered(m, Vec3(0.3f, 0.0f, -7.2f), Vec3(400.0f, 0.0f, 400.0f), DVec3(0.0));
  // Per axis the mean of the square wave over 800 cells plus a fraction is
  // at most 1/800 away from 0.
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got[ch], mean[ch], 0.5 * 0.8 / 800.0 + 1e-6);
  EXPECT_NE(got, m.color);
}

TEST(TextureFilter, ZeroFootprintIsTheUnfilteredValueExactly) {
  rstest::Rng rng(3);
  for (int c = 0; c < 2000; ++c) {
    const Material m = checker(float(rng.log_uniform(0.01, 10.0)));
    // Points on cell faces too (a floor at y = 0, multiples of the size),
    // where the unfiltered checker's face rule decides.
    Vec3 p(float(rng.uniform(-50, 50)), float(rng.uniform(-50, 50)), float(rng.uniform(-50, 50)));
    if (c % 3 == 0) p.y = 0.0f;
    if (c % 5 == 0) p.x = float(rng.integer(-20, 20)) * m.checker_size;
    const DVec3 origin = c % 7 == 0 ? DVec3(3e6, 0.0, -1e6) : DVec3(0.0);
    EXPECT_EQ(material_color_filtered(m, p, Vec3(0.0f), origin), material_color(m, p, origin))
        << "case " << c;
  }
  // Not a checker: the color, whatever the footprint.
  Material plain;
  EXPECT_EQ(material_color_filtered(plain, Vec3(1.0f), Vec3(5.0f), DVec3(0.0)), plain.color);
}

TEST(TextureFilter, FootprintInsideOneCellIsTheUnfilteredValueExactly) {
  const Material m = checker(1.0f);
  for (float x : {0.25f, 0.5f, 1.5f, -2.5f})
    for (float z : {0.5f, -0.5f, 3.75f}) {
      const Vec3 p(x, 0.0f, z);
      EXPECT_EQ(material_color_filtered(m, p, Vec3(0.2f, 0.0f, 0.2f), DVec3(0.0)),
                material_color(m, p, DVec3(0.0)));
    }
}

TEST(TextureFilter, FootprintOfAParallelCameraLookingDown) {
  // A parallel projection straight down onto the floor: a pixel of a 100 x
  // 100 image of half-height 1 is 0.02 wide, so the differentials one pixel
  // over hit 0.02 apart along x and z: half-widths 0.01 on x and z, exactly 0
  // on y (the offsets are projected onto the plane).
  Camera cam;
  cam.eye = Vec3(0.3f, 5.0f, 0.2f);
  cam.look_at = Vec3(0.3f, 0.0f, 0.2f);
  cam.up = Vec3(0.0f, 0.0f, -1.0f);
  cam.parallel = true;
  cam.parallel_scale = 1.0f;
  cam.prepare(100, 100);
  const Ray r = cam.generate_ray(37.5f, 61.25f);
  const float t = -r.origin.y / r.dir.y;
  const Vec3 p = r.origin + t * r.dir;
  const Vec3 up(0.0f, 1.0f, 0.0f);
  const Footprint f = footprint(cam.generate_differential(37.5f, 61.25f, 1.0f), p, up);
  EXPECT_NEAR(f.half_width.x, 0.01f, 1e-6f);
  EXPECT_NEAR(f.half_width.z, 0.01f, 1e-6f);
  EXPECT_EQ(f.half_width.y, 0.0f);
  EXPECT_NEAR(glm::length(f.center - p), 0.0f, 1e-6f);
  // A quarter of the side, a quarter of the footprint; a cell centred
  // elsewhere (half a pixel left and up of the ray) moves the box's centre
  // on the plane by half a pixel's world size, 0.01, along -x and +z (the
  // image's y grows toward -up = +z here).
  const Footprint q = footprint(cam.generate_differential(37.0f, 60.75f, 0.25f), p, up);
  EXPECT_NEAR(q.half_width.x, 0.0025f, 1e-6f);
  EXPECT_NEAR(q.half_width.z, 0.0025f, 1e-6f);
  EXPECT_EQ(q.center.y, p.y);
  EXPECT_NEAR(q.center.x - p.x, -0.01f, 1e-6f);
  EXPECT_NEAR(std::abs(q.center.z - p.z), 0.01f, 1e-6f);
  // A ray that misses the plane (parallel to it): the point itself, no box.
  RayDifferential miss{Ray{Vec3(0, 1, 0), Vec3(1, 0, 0)}, Ray{Vec3(0, 1, 0), Vec3(1, 0, 0)},
                       Ray{Vec3(0, 1, 0), Vec3(0, 0, 1)}};
  const Footprint none = footprint(miss, p, up);
  EXPECT_EQ(none.center, p);
  EXPECT_EQ(none.half_width, Vec3(0.0f));
}

RenderSettings small(int samples, bool filter) {
  RenderSettings s;
  s.width = 160;
  s.height = 120;
  s.samples = samples;
  s.max_depth = 5;
  s.texture_filter = filter;
  return s;
}

// RMSE over the pixels [x0, x1) x [y0, y1).
double rmse_rect(const Framebuffer& a, const Framebuffer& b, int x0, int y0, int x1, int y1) {
  double e = 0;
  size_t n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const Color d = a.color[a.index(x, y)] - b.color[b.index(x, y)];
      e += double(glm::dot(d, d));
      n += 3;
    }
  return std::sqrt(e / double(n));
}

TEST(TextureFilter, FarCheckerboardIsCloserToTheConvergedImage) {
  // The default scene's far floor (columns 0..30, rows 29..50 of 160 x 120:
  // the checkerboard from just below the horizon, left of the objects)
  // aliases when point sampled. The reference is the unfiltered render at
  // 12 x 12 samples, the pixel integral the filter approximates.
  Scene scene = make_default_scene();
  scene.commit();
  const Framebuffer ref = render(scene, small(12, false));
  const Framebuffer point = render(scene, small(1, false));
  const Framebuffer filtered = render(scene, small(1, true));
  const double e_point = rmse_rect(point, ref, 0, 29, 30, 50);
  const double e_filtered = rmse_rect(filtered, ref, 0, 29, 30, 50);
  std::printf("far floor RMSE, 1 spp: point %.4f, filtered %.4f\n", e_point, e_filtered);
  EXPECT_LT(e_filtered, 0.6 * e_point);
  // Filtering changes only the checker's albedo: the sky rows are identical.
  EXPECT_EQ(rmse_rect(point, filtered, 0, 0, 160, 10), 0.0);
}

TEST(TextureFilter, SameImageForAnyThreadCountAndReplayedPixelsMatch) {
  Scene scene = make_default_scene();
  scene.commit();
  RenderSettings a = small(2, true);
  a.threads = 1;
  RenderSettings b = a;
  b.threads = 2;
  b.tile_size = 7;
  const Framebuffer fa = render(scene, a), fb = render(scene, b);
  ASSERT_EQ(fa.color.size(), fb.color.size());
  EXPECT_EQ(std::memcmp(fa.color.data(), fb.color.data(), fa.color.size() * sizeof(Color)), 0);
  for (auto [x, y] : {std::pair{10, 55}, {80, 100}, {150, 50}, {60, 70}}) {
    const PixelRecord r = record_pixel(scene, a, x, y);
    EXPECT_EQ(r.color, fa.color[fa.index(x, y)]) << x << "," << y;
  }
}

}  // namespace
