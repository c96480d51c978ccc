// Ray trees, statistics and "render only what the scene needs".
#include <gtest/gtest.h>

#include <cstring>

#include "rayscope/render.h"
#include "rayscope/replay.h"
#include "rayscope/shapes.h"
#include "test_util.h"

using namespace rayscope;

namespace {

bool same_bits(const Color& a, const Color& b) {
  return std::memcmp(&a, &b, sizeof(Color)) == 0;
}

// A diffuse scene: a plane and two spheres, no reflective or refractive material.
Scene diffuse_scene(bool with_light) {
  Scene s;
  s.camera.eye = Vec3(0, 1.5f, 6);
  s.camera.look_at = Vec3(0, 0.7f, 0);
  Material m;
  m.name = "matte";
  s.materials = {m};
  s.planes.push_back(Plane{"floor", Vec3(0), Vec3(0, 1, 0), 0});
  s.spheres.push_back(Sphere{"a", Vec3(-1, 1, 0), 1.0f, 0});
  s.spheres.push_back(Sphere{"b", Vec3(1.2f, 0.6f, 0.8f), 0.6f, 0});
  if (with_light) {
    Light l;
    l.name = "key";
    l.position = Vec3(-3, 5, 4);
    s.lights.push_back(l);
  }
  return s;
}

}  // namespace

// Replaying a pixel gives exactly the color it has in the full render, for every
// pixel of a small default-scene render (glass, mirror, shadow edges included)
// and for single samples summed by hand.
TEST(RayTree, ReplayEqualsRender) {
  Scene scene = make_default_scene();
  scene.commit();
  RenderSettings rs = rstest::small_render(96, 72, 2);
  Framebuffer fb = render(scene, rs);
  int compared = 0, with_refraction = 0, with_occlusion = 0;
  for (int y = 0; y < rs.height; y += 3)
    for (int x = 0; x < rs.width; x += 2) {
      PixelRecord rec = record_pixel(scene, rs, x, y);
      ASSERT_TRUE(same_bits(rec.color, fb.color[fb.index(x, y)])) << "pixel " << x << "," << y;
      ++compared;
      for (const RayRecord& r : rec.rays) {
        with_refraction += r.kind == RayKind::Refraction;
        with_occlusion += r.kind == RayKind::Shadow && r.occluded;
      }
    }
  EXPECT_GT(compared, 1000);
  EXPECT_GT(with_refraction, 100);  // glass pixels were among them
  EXPECT_GT(with_occlusion, 100);   // and shadowed ones
}

// The tree is well formed: parents precede children, depths increase by one,
// every ray's weight is its parent's weight times a factor <= 1, and the
// primary rays' returned colors average to the pixel color.
TEST(RayTree, TreeStructure) {
  Scene scene = make_default_scene();
  scene.commit();
  RenderSettings rs = rstest::small_render(64, 48, 2);
  prepare_frame(scene, rs);
  for (auto [x, y] : {std::pair{20, 25}, {40, 30}, {32, 20}, {10, 40}}) {
    PixelRecord rec = record_pixel(scene, rs, x, y);
    Color sum(0.0f);
    int primaries = 0;
    for (const RayRecord& r : rec.rays) {
      if (r.parent < 0) {
        EXPECT_EQ(r.kind, RayKind::Primary);
        EXPECT_EQ(r.depth, 0);
        sum += r.color;
        ++primaries;
        continue;
      }
      ASSERT_LT(r.parent, r.id);
      const RayRecord& p = rec.rays[size_t(r.parent)];
      EXPECT_EQ(r.depth, p.depth + 1);
      EXPECT_TRUE(p.hit);
      EXPECT_NE(std::find(p.children.begin(), p.children.end(), r.id), p.children.end());
      EXPECT_LE(max_component(r.weight), max_component(p.weight) * (1.0f + 1e-6f));
      EXPECT_EQ(r.sample, p.sample);
    }
    EXPECT_EQ(primaries, 4);
    Color avg = sum * 0.25f;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(avg[c], rec.color[c], 1e-6f);
  }
  // One sample only.
  PixelRecord one = record_pixel(scene, rs, 20, 25, 3);
  for (const RayRecord& r : one.rays) EXPECT_EQ(r.sample, 3);
  EXPECT_THROW(record_pixel(scene, rs, 64, 0), std::out_of_range);
  EXPECT_THROW(record_pixel(scene, rs, 0, -1), std::out_of_range);
  EXPECT_THROW(record_pixel(scene, rs, 0, 0, 4), std::out_of_range);
}

// A diffuse scene without lights traces exactly width x height x spp rays.
TEST(RenderOnlyWhatIsNeeded, NoLightsNoShadowRays) {
  Scene scene = diffuse_scene(false);
  scene.commit();
  for (int spp : {1, 2, 3}) {
    RenderSettings rs = rstest::small_render(40, 30, spp);
    RayCounters c;
    render(scene, rs, &c);
    EXPECT_EQ(c.total_rays(), uint64_t(40 * 30 * spp * spp));
    EXPECT_EQ(c.rays[int(RayKind::Primary)], uint64_t(40 * 30 * spp * spp));
    EXPECT_EQ(c.rays[int(RayKind::Shadow)], 0u);
    EXPECT_EQ(c.shadow_skipped_backfacing, 0u);
  }
}

// With one light and no secondary materials, every hit either casts one shadow
// ray or is skipped because the light is behind it; nothing else is traced.
TEST(RenderOnlyWhatIsNeeded, OneShadowRayPerLitHit) {
  Scene scene = diffuse_scene(true);
  scene.commit();
  RenderSettings rs = rstest::small_render(40, 30, 1);
  RayCounters c;
  render(scene, rs, &c);
  EXPECT_EQ(c.rays[int(RayKind::Primary)], 1200u);
  EXPECT_EQ(c.rays[int(RayKind::Reflection)] + c.rays[int(RayKind::Refraction)], 0u);
  EXPECT_EQ(c.rays[int(RayKind::Shadow)] + c.shadow_skipped_backfacing, c.primary_hits);
  EXPECT_GT(c.shadow_skipped_backfacing, 0u);  // the spheres' far sides face away
}

// Making one sphere a mirror adds exactly one reflection ray per pixel that sees it.
TEST(RenderOnlyWhatIsNeeded, MirrorAddsExactlyItsReflectionRays) {
  Scene base = diffuse_scene(false);
  base.commit();
  RenderSettings rs = rstest::small_render(40, 30, 1);
  RayCounters c0;
  Framebuffer fb = render(base, rs, &c0);
  const uint32_t mirror_object = 0;  // sphere "a": objects are meshes, spheres, planes
  uint64_t mirror_pixels = 0;
  for (float id : fb.object_id) mirror_pixels += id == float(mirror_object);
  ASSERT_GT(mirror_pixels, 50u);

  Scene mirrored = diffuse_scene(false);
  Material mirror;
  mirror.name = "mirror";
  mirror.reflectivity = 0.8f;
  mirrored.materials.push_back(mirror);
  mirrored.spheres[0].material = 1;
  mirrored.commit();
  RayCounters c1;
  render(mirrored, rs, &c1);
  // A convex sphere never sees itself, and the rest is diffuse: one bounce each.
  EXPECT_EQ(c1.rays[int(RayKind::Reflection)], mirror_pixels);
  EXPECT_EQ(c1.total_rays(), c0.total_rays() + mirror_pixels);
}

// A scene with few primitives skips the BVH and renders the same image as the
// same scene with a BVH (made necessary by two extra spheres nobody sees).
TEST(RenderOnlyWhatIsNeeded, TinySceneSkipsBvh) {
  Scene tiny = diffuse_scene(true);
  tiny.commit();
  EXPECT_FALSE(tiny.summary().bvh_used);
  Scene big = diffuse_scene(true);  // 2 spheres + 3 hidden = 5 > kBruteForceMax
  big.spheres.push_back(Sphere{"hidden1", Vec3(0, 0.5f, 100), 0.1f, 0});  // behind the camera
  big.spheres.push_back(Sphere{"hidden2", Vec3(3, 0.5f, 100), 0.1f, 0});
  big.spheres.push_back(Sphere{"hidden3", Vec3(-3, 0.5f, 100), 0.1f, 0});
  big.commit();
  EXPECT_TRUE(big.summary().bvh_used);
  RenderSettings rs = rstest::small_render(48, 36, 1);
  Framebuffer a = render(tiny, rs), b = render(big, rs);
  ASSERT_EQ(0, std::memcmp(a.color.data(), b.color.data(), a.color.size() * sizeof(Color)));
}

// A depth limit of 0 traces no secondary rays and counts the ones it cut.
TEST(RenderOnlyWhatIsNeeded, DepthZeroCutsAllSecondaryRays) {
  Scene scene = make_default_scene();
  scene.commit();
  RenderSettings rs = rstest::small_render(32, 24, 1);
  rs.max_depth = 0;
  RayCounters c;
  render(scene, rs, &c);
  EXPECT_EQ(c.rays[int(RayKind::Reflection)] + c.rays[int(RayKind::Refraction)], 0u);
  EXPECT_GT(c.depth_cutoffs, 0u);
}

// Recording pixels during a full render changes nothing in the image, and the
// records equal those of a separate replay.
TEST(RayTree, RenderAndRecordMatchesReplay) {
  Scene scene = make_default_scene();
  scene.commit();
  RenderSettings rs = rstest::small_render(64, 48, 2);
  Framebuffer plain = render(scene, rs);
  std::vector<glm::ivec2> pixels = {{10, 10}, {32, 24}, {50, 30}, {32, 24}};
  std::vector<PixelRecord> records;
  RayCounters c;
  Framebuffer fb = render_and_record(scene, rs, pixels, records, &c);
  ASSERT_EQ(0, std::memcmp(plain.color.data(), fb.color.data(), fb.color.size() * sizeof(Color)));
  ASSERT_EQ(records.size(), pixels.size());
  for (size_t k = 0; k < pixels.size(); ++k) {
    PixelRecord replay = record_pixel(scene, rs, pixels[k].x, pixels[k].y);
    EXPECT_TRUE(same_bits(records[k].color, replay.color)) << "record " << k;
    ASSERT_EQ(records[k].rays.size(), replay.rays.size());
    for (size_t i = 0; i < replay.rays.size(); ++i)
      EXPECT_EQ(records[k].rays[i].traversal.nodes, replay.rays[i].traversal.nodes);
  }
  std::vector<PixelRecord> none;
  EXPECT_THROW(render_and_record(scene, rs, {{64, 0}}, none), std::out_of_range);
}
