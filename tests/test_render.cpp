// Rendering (render.h) of the built-in default scene: bit-identical results for
// any thread count and tile size, a reference-image regression test, and
// semantic facts about the render that only a correct tracer produces.
//
// Reference image: tests/data/default_160x120.png, the default scene at
// 160x120, 2x2 samples, max_depth 5, written by this test itself with
//   RAYSCOPE_UPDATE_REFERENCE=1 build/tests/test_render --gtest_filter='*ReferenceImage*'
// (through write_image: 8-bit sRGB). Regenerate it only after an intended
// change of the rendering, and look at the picture before committing it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "rayscope/image.h"
#include "rayscope/ray_estimate.h"
#include "rayscope/render.h"
#include "rayscope/shapes.h"
#include "test_util.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::to_d;

constexpr int kWidth = 160, kHeight = 120, kSamples = 2;

RenderSettings settings(int threads, int tile_size = 16, bool statistics = false) {
  RenderSettings s;
  s.width = kWidth;
  s.height = kHeight;
  s.samples = kSamples;
  s.max_depth = 5;
  s.threads = threads;
  s.tile_size = tile_size;
  s.statistics = statistics;
  return s;
}

struct Result {
  Framebuffer fb;
  RayCounters counters;
  Scene scene;
};

Result render_default(const RenderSettings& s) {
  Result r;
  r.scene = make_default_scene();
  r.scene.commit();
  r.fb = render(r.scene, s, &r.counters);
  return r;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  // Empty vectors may have a null data(), which memcmp must not be given (UBSan).
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void expect_identical(const Result& a, const Result& b, const std::string& what) {
  EXPECT_EQ(a.fb.width, b.fb.width);
  EXPECT_EQ(a.fb.height, b.fb.height);
  EXPECT_TRUE(same_bytes(a.fb.color, b.fb.color)) << what << ": color differs";
  EXPECT_TRUE(same_bytes(a.fb.depth, b.fb.depth)) << what << ": depth differs";
  EXPECT_TRUE(same_bytes(a.fb.normal, b.fb.normal)) << what << ": normal differs";
  EXPECT_TRUE(same_bytes(a.fb.object_id, b.fb.object_id)) << what << ": object id differs";
  EXPECT_EQ(a.fb.cost.size(), b.fb.cost.size());
  EXPECT_TRUE(same_bytes(a.fb.cost, b.fb.cost)) << what << ": cost AOV differs";
  // RayCounters is all uint64_t, no padding: compare the bytes, and the
  // fields for a readable message.
  static_assert(sizeof(RayCounters) % sizeof(uint64_t) == 0);
  EXPECT_EQ(std::memcmp(&a.counters, &b.counters, sizeof(RayCounters)), 0) << what;
  EXPECT_EQ(a.counters.rays, b.counters.rays) << what;
  EXPECT_EQ(a.counters.shadow_occluded, b.counters.shadow_occluded) << what;
  EXPECT_EQ(a.counters.total_internal_reflections, b.counters.total_internal_reflections) << what;
}

TEST(Render, BitIdenticalForAnyThreadCountAndTileSize) {
  Result one = render_default(settings(1));
  for (int threads : {2, 3}) {
    Result r = render_default(settings(threads));
    expect_identical(one, r, std::to_string(threads) + " threads vs 1");
  }
  // Tiles only schedule work; every pixel depends on its coordinates alone.
  Result tiles = render_default(settings(3, 7));
  expect_identical(one, tiles, "tile size 7 vs 16");
  // The statistics path computes the same image (and deterministic costs).
  Result s1 = render_default(settings(1, 16, true)), s2 = render_default(settings(2, 16, true));
  expect_identical(s1, s2, "statistics, 2 threads vs 1");
  EXPECT_TRUE(same_bytes(one.fb.color, s1.fb.color)) << "statistics changed the image";
  EXPECT_EQ(one.counters.rays, s1.counters.rays);
  EXPECT_GT(s1.counters.nodes_visited, 0u);
  // A different seed moves the jittered samples: the image must change.
  RenderSettings other = settings(2);
  other.seed = 7;
  Result seeded = render_default(other);
  EXPECT_FALSE(same_bytes(one.fb.color, seeded.fb.color));
}

// 8-bit sRGB code of a linear value, exactly as write_image() encodes it.
int encode(float v) {
  return int(std::lround(255.0f * linear_to_srgb(v)));
}

TEST(Render, MatchesReferenceImage) {
  const std::filesystem::path ref =
      std::filesystem::path(RAYSCOPE_TEST_DATA_DIR) / "default_160x120.png";
  Result r = render_default(settings(0));
  const char* update = std::getenv("RAYSCOPE_UPDATE_REFERENCE");
  if (update && std::string(update) == "1") {
    std::filesystem::create_directories(ref.parent_path());
    write_image(ref, r.fb);
    GTEST_SKIP() << "wrote " << ref;
  }
  ASSERT_TRUE(std::filesystem::exists(ref))
      << ref << " is missing; create it with RAYSCOPE_UPDATE_REFERENCE=1 (see the top of "
      << __FILE__ << ")";
  int w = 0, h = 0;
  std::vector<float> rgb = read_image_rgb(ref, w, h);
  ASSERT_EQ(w, kWidth);
  ASSERT_EQ(h, kHeight);
  // Tolerance: the reference is quantised to 8 bits (+-0.5 level), and a
  // different compiler, optimisation or libm may move a few values across a
  // rounding boundary or, at silhouettes and shadow edges, flip a sample. So:
  // mean absolute difference below 0.5 level over all channels, and at most
  // 0.5% of the pixels off by more than 2 levels in some channel. A real change
  // of the shading (a wrong Fresnel weight, a light term, an offset that lets
  // shadow acne through) moves whole regions by many levels and fails both.
  // Pixels more than kFarOff levels off: at most kMaxFarOff of them, none
  // more than kMaxLevels off (see the end of the test).
  constexpr int kFarOff = 8, kMaxFarOff = 6, kMaxLevels = 64;
  double sum = 0;
  int big = 0, far_off = 0, max_diff = 0;
  for (int i = 0; i < w * h; ++i) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      int want = int(std::lround(rgb[size_t(i) * 3 + size_t(c)] * 255.0f));
      int got = encode(r.fb.color[size_t(i)][c]);
      int d = std::abs(got - want);
      sum += d;
      worst = std::max(worst, d);
    }
    if (worst > 2) ++big;
    if (worst > kFarOff) ++far_off;
    max_diff = std::max(max_diff, worst);
  }
  double mean = sum / (3.0 * w * h);
  std::printf(
      "reference: mean abs diff %.4f levels, %d pixels > 2 levels, %d > %d levels, max %d\n", mean,
      big, far_off, kFarOff, max_diff);
  EXPECT_LT(mean, 0.5);
  EXPECT_LE(big, w * h / 200);
  // The largest differences. One flipped sample of the 2x2 moves a pixel by at
  // most a quarter of the range between the two colors it falls between (the
  // default scene's strongest edge, sky against the dark checker, is ~200
  // levels: <= 50 levels); a handful of such flips is what another compiler
  // or libm can cause. Measured with this build: max 0 levels. Replacing the
  // error-bound ray offset with a fixed 1e-4 epsilon moved 32 pixels by more
  // than 2 levels, 22 by more than 8, up to 37 (the issue measured up to 50):
  // the mean and the 0.5% above let that through; these fail it (and so does
  // AnalyticMirrorImage below).
  EXPECT_LE(far_off, kMaxFarOff);
  EXPECT_LE(max_diff, kMaxLevels);
}

// Pixel coordinates (continuous) where the point p appears, for the prepared
// camera of a render of kWidth x kHeight.
glm::dvec2 project(const Camera& cam, const Vec3& p) {
  DVec3 d = to_d(p) - to_d(cam.eye);
  double f = glm::dot(d, to_d(cam.forward()));
  double x = glm::dot(d, to_d(cam.right())) / f, y = glm::dot(d, to_d(cam.up_vector())) / f;
  double hh = std::tan(0.5 * glm::radians(double(cam.vfov_degrees)));
  double hw = hh * double(kWidth) / kHeight;
  return {(x / hw + 1) * 0.5 * kWidth, (1 - y / hh) * 0.5 * kHeight};
}

TEST(Render, SemanticFacts) {
  Result r = render_default(settings(2));
  const Scene& s = r.scene;
  const Framebuffer& fb = r.fb;
  const RayCounters& c = r.counters;
  // Objects: torus (mesh) 0, mirror sphere 1, glass sphere 2, floor plane 3.
  ASSERT_EQ(s.object_count(), 4u);
  ASSERT_EQ(s.object_type(3), ObjectType::Plane);

  // Ray counts: every sample is a primary ray; there is sky in the picture;
  // the mirror and the glass spawn reflection and refraction rays; every hit
  // handles both lights with a shadow ray or finds the light behind it.
  const uint64_t primaries = uint64_t(kWidth) * kHeight * kSamples * kSamples;
  EXPECT_EQ(c.rays[int(RayKind::Primary)], primaries);
  EXPECT_GT(c.primary_hits, primaries / 2);
  EXPECT_LT(c.primary_hits, primaries);
  EXPECT_GT(c.rays[int(RayKind::Reflection)], 0u);
  EXPECT_GT(c.rays[int(RayKind::Refraction)], 0u);
  EXPECT_GT(c.rays[int(RayKind::Shadow)], 0u);
  EXPECT_GT(c.shadow_occluded, 0u);
  EXPECT_LT(c.shadow_occluded, c.rays[int(RayKind::Shadow)]);
  EXPECT_EQ(c.rays[int(RayKind::Shadow)] + c.shadow_skipped_backfacing, 2 * c.hits);
  EXPECT_LE(c.hits,
            c.rays[0] + c.rays[int(RayKind::Reflection)] + c.rays[int(RayKind::Refraction)]);

  // Sky: the top rows look above the horizon and see the background.
  for (int x = 0; x < kWidth; x += 9) {
    size_t i = fb.index(x, 0);
    EXPECT_EQ(fb.object_id[i], -1.0f) << "x=" << x;
    EXPECT_EQ(fb.depth[i], kInfinity);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(fb.color[i][k], s.background[k], 1e-6);
  }

  // Every pixel's AOVs agree with an analytic intersection of its first
  // sample's primary ray: floor pixels lie at the ray-plane distance, sphere
  // pixels at the ray-sphere distance, with the right normals.
  int floor_px = 0, sphere_px[2] = {0, 0};
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      size_t i = fb.index(x, y);
      Vec2 sp = sample_position(x, y, 0, kSamples, 0);
      Ray ray = s.camera.generate_ray(sp.x, sp.y);
      DVec3 o = to_d(ray.origin), d = glm::normalize(to_d(ray.dir));
      int id = int(fb.object_id[i]);
      if (id == 3) {
        ++floor_px;
        double t = -o.y / d.y;  // floor: y = 0
        EXPECT_NEAR(fb.depth[i], t, 1e-5 * t) << x << "," << y;
        EXPECT_EQ(fb.normal[i], Vec3(0, 1, 0));
        // Lit floor is never the sky color.
        EXPECT_GT(glm::length(fb.color[i] - s.background), 0.05f) << x << "," << y;
      } else if (id == 1 || id == 2) {
        ++sphere_px[id - 1];
        const rayscope::Sphere& sph = s.spheres[size_t(id - 1)];
        double t0, t1, impact;
        ASSERT_TRUE(rstest::ref_ray_sphere(o, d, to_d(sph.center), sph.radius, t0, t1, impact))
            << x << "," << y;
        // Near the silhouette t is ill-conditioned; 1e-4 relative is ~1000 eps.
        if (impact < 0.99 * sph.radius) {
          EXPECT_NEAR(fb.depth[i], t0, 1e-4 * t0) << x << "," << y;
          DVec3 n = glm::normalize(o + t0 * d - to_d(sph.center));
          EXPECT_GT(glm::dot(to_d(fb.normal[i]), n), 0.9999) << x << "," << y;
        }
      }
    }
  EXPECT_GT(floor_px, kWidth * kHeight / 5);
  EXPECT_GT(sphere_px[0], 200);
  EXPECT_GT(sphere_px[1], 200);

  // The centers of the spheres show the spheres (object ids by projection).
  for (int k = 0; k < 2; ++k) {
    glm::dvec2 p = project(s.camera, s.spheres[size_t(k)].center);
    int x = int(p.x), y = int(p.y);
    ASSERT_TRUE(x >= 0 && x < kWidth && y >= 0 && y < kHeight);
    EXPECT_EQ(fb.object_id[fb.index(x, y)], float(k + 1)) << "sphere " << k;
  }

  // The checkerboard: light and dark squares of the floor differ clearly.
  double light = 0, dark = 0;
  int nl = 0, nd = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      size_t i = fb.index(x, y);
      if (fb.object_id[i] != 3.0f) continue;
      Vec2 sp = sample_position(x, y, 0, kSamples, 0);
      Ray ray = s.camera.generate_ray(sp.x, sp.y);
      Vec3 p = ray.origin + (-ray.origin.y / ray.dir.y) * ray.dir;
      bool is_dark = (long long)(std::floor(p.x) + std::floor(p.z)) & 1;
      (is_dark ? dark : light) += luminance(fb.color[i]);
      (is_dark ? nd : nl)++;
    }
  ASSERT_GT(nl, 100);
  ASSERT_GT(nd, 100);
  EXPECT_GT(light / nl, 2 * dark / nd);
}

TEST(Render, DepthLimitStopsSecondaryRays) {
  // max_depth 0: no reflection or refraction rays at all, cut-offs counted
  // instead; deeper limits trace more secondary rays.
  uint64_t prev = 0;
  for (int depth : {0, 1, 5}) {
    RenderSettings s = settings(2);
    s.width = 80;
    s.height = 60;
    s.max_depth = depth;
    Result r = render_default(s);
    uint64_t secondary =
        r.counters.rays[int(RayKind::Reflection)] + r.counters.rays[int(RayKind::Refraction)];
    if (depth == 0) {
      EXPECT_EQ(secondary, 0u);
      EXPECT_GT(r.counters.depth_cutoffs, 0u);
    } else {
      EXPECT_GT(secondary, prev) << "max_depth " << depth;
    }
    prev = secondary;
  }
}

TEST(RayEstimate, BoundsEveryRenderAndIsReachedInsideAMirror) {
  // The worst case (ray_estimate.h) is an upper bound: renders of the default
  // scene at several depths, cutoffs and sample counts never trace more.
  for (int depth : {0, 1, 3, 8})
    for (float cutoff : {0.0f, 1e-3f, 0.2f})
      for (int spp : {1, 2}) {
        Scene scene = make_default_scene();
        RenderSettings s = settings(2);
        s.samples = spp;
        s.width = 40;
        s.height = 30;
        s.max_depth = depth;
        s.min_contribution = cutoff;
        RayCounters c;
        render(scene, s, &c);
        const RayEstimate e = estimate_rays(scene, s);
        EXPECT_LE(double(c.total_rays()), e.rays)
            << "depth " << depth << ", cutoff " << cutoff << ", spp " << spp;
        EXPECT_EQ(e.samples, 40.0 * 30.0 * spp * spp);
        EXPECT_EQ(e.branching, 2);  // the glass sphere
        EXPECT_EQ(e.lights, 2);
      }
  // Inside a perfect mirror every ray hits and reflects: the bound is reached
  // exactly (no lights: no shadow rays; no cutoff: every level full).
  Scene mirror;
  mirror.materials[0].reflectivity = 1.0f;
  mirror.lights.clear();
  mirror.spheres.push_back(Sphere{"mirror", Vec3(0.0f), 10.0f, 0});
  mirror.camera.eye = Vec3(0.0f, 0.0f, 2.0f);
  mirror.camera.look_at = Vec3(0.0f);
  RenderSettings s = settings(2);
  s.samples = 2;
  s.width = 16;
  s.height = 12;
  s.max_depth = 6;
  s.min_contribution = 0.0f;
  mirror.commit();
  RayCounters c;
  render(mirror, s, &c);
  const RayEstimate e = estimate_rays(mirror, s);
  EXPECT_EQ(e.branching, 1);
  EXPECT_EQ(e.levels, 6);
  EXPECT_EQ(e.rays, 16.0 * 12.0 * 4.0 * 7.0);
  EXPECT_EQ(double(c.total_rays()), e.rays);
  // The cutoff bounds the depth: weights 0.5^k fall below 0.1 after level 3.
  mirror.materials[0].reflectivity = 0.5f;
  mirror.commit();
  s.min_contribution = 0.1f;
  const RayEstimate cut = estimate_rays(mirror, s);
  EXPECT_EQ(cut.levels, 3);
  EXPECT_EQ(cut.rays_per_sample, 4.0);
  RayCounters cc;
  render(mirror, s, &cc);
  EXPECT_EQ(double(cc.total_rays()), cut.rays);
  // The case: depth 64 without a cutoff on a refractive scene is
  // over the budget, the default render is not.
  Scene glass = make_default_scene();
  RenderSettings deep;
  deep.max_depth = 64;
  deep.min_contribution = 0.0f;
  EXPECT_GT(estimate_rays(glass, deep).rays, kRayBudget);
  EXPECT_LT(estimate_rays(glass, RenderSettings{}).rays, kRayBudget);
}

}  // namespace

// ---------------------------------------------------------------------------
// Pixels whose value is known from the scene alone: shading, shadow and
// mirror image computed here in double precision from the lecture's model
// (ambient + diffuse per visible light, plus reflectivity times the reflected
// ray's color), not from the renderer. One sample per pixel, whose primary
// ray is the camera's (camera mapping is tested in test_frame and
// SemanticFacts); everything after the primary ray is independent.
// ---------------------------------------------------------------------------

constexpr int kAW = 96, kAH = 72;
const Color kClay(0.8f, 0.5f, 0.3f), kSky(0.2f, 0.3f, 0.4f);
constexpr float kClayAmbient = 0.1f, kClayDiffuse = 0.9f;
const DVec3 kBallCenter(0.0, 1.0, 0.0);
constexpr double kBallRadius = 0.5;

// A clay ball above a floor, lit straight from above by one directional light
// (so the ball's shadow is the disc of its radius under it); the floor is
// white and matte, or a perfect mirror.
Scene ball_scene(bool mirror_floor) {
  Scene s;
  s.camera.eye = Vec3(0.3f, 2.2f, 3.5f);
  s.camera.look_at = Vec3(0.0f, 0.5f, 0.0f);
  s.background = kSky;
  Material clay;
  clay.name = "clay";
  clay.color = kClay;
  clay.ambient = kClayAmbient;
  clay.diffuse = kClayDiffuse;
  clay.specular = 0.0f;
  Material floor;
  floor.name = "floor";
  floor.color = Color(1.0f);
  floor.ambient = mirror_floor ? 0.0f : 0.2f;
  floor.diffuse = mirror_floor ? 0.0f : 0.8f;
  floor.specular = 0.0f;
  floor.reflectivity = mirror_floor ? 1.0f : 0.0f;
  s.materials = {clay, floor};
  s.spheres.push_back(Sphere{"ball", Vec3(kBallCenter), float(kBallRadius), 0});
  s.planes.push_back(Plane{"floor", Vec3(0.0f), Vec3(0.0f, 1.0f, 0.0f), 1});
  Light sun;
  sun.type = Light::Type::Directional;
  sun.direction = Vec3(0.0f, -1.0f, 0.0f);
  s.lights = {sun};
  s.commit();
  return s;
}

// The clay's color at a point of the ball with outward normal n: ambient, and
// diffuse where the light (from +y) reaches it; the upper half is unshadowed.
DVec3 clay_color(const DVec3& n) {
  return (double(kClayAmbient) + double(kClayDiffuse) * std::max(0.0, n.y)) * DVec3(kClay);
}

struct AnalyticCounts {
  int ball = 0, shadow = 0, lit = 0, mirrored_ball = 0, mirrored_sky = 0;
};

// Compares every pixel whose analytic value is well defined (not within
// 1e-3 of a silhouette or of the shadow's edge, where the pixel's one sample
// may fall either side) with the render; returns how many of each kind.
AnalyticCounts check_analytic(bool mirror_floor) {
  Scene s = ball_scene(mirror_floor);
  RenderSettings rs;
  rs.width = kAW;
  rs.height = kAH;
  rs.samples = 1;
  const Framebuffer fb = render(s, rs);
  AnalyticCounts n;
  // Float shading of unit-size quantities: errors ~1e-6; 1e-4 of the range
  // is far below any real difference (a missing term is >= 0.02).
  constexpr double kTol = 1e-4;
  auto expect_color = [&](int x, int y, const DVec3& want, const char* what) {
    const Color got = fb.color[fb.index(x, y)];
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(got[k], want[k], kTol) << what << " at pixel " << x << "," << y;
  };
  for (int y = 0; y < kAH; ++y)
    for (int x = 0; x < kAW; ++x) {
      const Vec2 sp = sample_position(x, y, 0, 1, rs.seed);
      const Ray ray = s.camera.generate_ray(sp.x, sp.y);
      const DVec3 o = to_d(ray.origin), d = glm::normalize(to_d(ray.dir));
      double t0, t1, impact;
      const bool ball = rstest::ref_ray_sphere(o, d, kBallCenter, kBallRadius, t0, t1, impact);
      if (std::abs(impact - kBallRadius) < 1e-3) continue;  // silhouette
      if (ball && t0 > 0.0) {
        ++n.ball;
        expect_color(x, y, clay_color((o + t0 * d - kBallCenter) / kBallRadius), "ball");
        continue;
      }
      if (d.y >= 0.0) continue;              // sky: SemanticFacts checks it
      const DVec3 p = o + (-o.y / d.y) * d;  // on the floor
      if (!mirror_floor) {
        const double rho = std::hypot(p.x - kBallCenter.x, p.z - kBallCenter.z);
        if (std::abs(rho - kBallRadius) < 1e-3) continue;  // the shadow's edge
        const bool shadowed = rho < kBallRadius;
        ++(shadowed ? n.shadow : n.lit);
        expect_color(x, y, DVec3(shadowed ? 0.2 : 1.0), shadowed ? "shadow" : "lit floor");
      } else {
        const DVec3 r(d.x, -d.y, d.z);  // the mirror image of the ray
        double u0, u1, rimpact;
        const bool sees = rstest::ref_ray_sphere(p, r, kBallCenter, kBallRadius, u0, u1, rimpact);
        if (std::abs(rimpact - kBallRadius) < 1e-3) continue;
        if (sees && u0 > 0.0) {
          ++n.mirrored_ball;
          expect_color(x, y, clay_color((p + u0 * r - kBallCenter) / kBallRadius), "mirrored ball");
        } else {
          ++n.mirrored_sky;
          expect_color(x, y, DVec3(kSky), "mirrored sky");
        }
      }
    }
  return n;
}

TEST(Render, AnalyticShadingAndShadowBoundary) {
  const AnalyticCounts n = check_analytic(false);
  std::printf("checked %d ball, %d shadow, %d lit floor pixels\n", n.ball, n.shadow, n.lit);
  EXPECT_GT(n.ball, 300);
  EXPECT_GT(n.shadow, 100);
  EXPECT_GT(n.lit, 1000);
}

TEST(Render, AnalyticMirrorImage) {
  const AnalyticCounts n = check_analytic(true);
  std::printf("checked %d ball, %d mirrored ball, %d mirrored sky pixels\n", n.ball,
              n.mirrored_ball, n.mirrored_sky);
  EXPECT_GT(n.ball, 300);
  EXPECT_GT(n.mirrored_ball, 100);
  EXPECT_GT(n.mirrored_sky, 1000);
}

// Camera::project() inverts generate_ray(): a point along the ray through an
// image-plane position projects back to that position (central and parallel
// projections), and a point behind the eye does not project.
TEST(Camera, ProjectInvertsGenerateRay) {
  for (bool parallel : {false, true}) {
    Camera c;
    c.eye = Vec3(1.0f, 2.0f, 6.0f);
    c.look_at = Vec3(-0.5f, 0.3f, 0.0f);
    c.up = Vec3(0.1f, 1.0f, 0.0f);
    c.parallel = parallel;
    c.parallel_scale = 2.5f;
    c.prepare(64, 48);
    for (auto [px, py] : {std::pair{0.5f, 0.5f}, {31.25f, 20.0f}, {63.5f, 47.5f}, {10.0f, 40.0f}})
      for (float t : {0.5f, 3.0f, 40.0f}) {
        const Ray r = c.generate_ray(px, py);
        float qx = -1.0f, qy = -1.0f;
        ASSERT_TRUE(c.project(r.origin + t * r.dir, qx, qy));
        EXPECT_NEAR(qx, px, 2e-3f) << parallel << " t=" << t;
        EXPECT_NEAR(qy, py, 2e-3f) << parallel << " t=" << t;
      }
    float qx, qy;
    if (!parallel) {
      EXPECT_FALSE(c.project(c.eye - 2.0f * c.forward(), qx, qy));
    }
  }
}
