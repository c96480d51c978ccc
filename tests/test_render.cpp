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
  double sum = 0;
  int big = 0, max_diff = 0;
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
    max_diff = std::max(max_diff, worst);
  }
  double mean = sum / (3.0 * w * h);
  std::printf("reference: mean abs diff %.4f levels, %d pixels > 2 levels, max %d\n", mean, big,
              max_diff);
  EXPECT_LT(mean, 0.5);
  EXPECT_LE(big, w * h / 200);
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

}  // namespace
