// Ray trees, statistics and "render only what the scene needs".
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "rayscope/raytree_format.h"
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
  EXPECT_FALSE(tiny.summary().walks_structure);
  Scene big = diffuse_scene(true);  // 2 spheres + 3 hidden = 5 > kBruteForceMax
  big.spheres.push_back(Sphere{"hidden1", Vec3(0, 0.5f, 100), 0.1f, 0});  // behind the camera
  big.spheres.push_back(Sphere{"hidden2", Vec3(3, 0.5f, 100), 0.1f, 0});
  big.spheres.push_back(Sphere{"hidden3", Vec3(-3, 0.5f, 100), 0.1f, 0});
  big.commit();
  EXPECT_TRUE(big.summary().walks_structure);
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
      EXPECT_EQ(records[k].rays[i].traversal.nodes(), replay.rays[i].traversal.nodes());
  }
  std::vector<PixelRecord> none;
  EXPECT_THROW(render_and_record(scene, rs, {{64, 0}}, none), std::out_of_range);
}

// --- What the viewer and `rayscope inspect` show of each hit and walk --------

namespace {

// A 9x9 image whose center pixel (4, 4), with one sample, looks straight down
// -z from (0, 0, 5).
RenderSettings center_render(int max_depth = 5, float min_contribution = 1e-3f) {
  RenderSettings rs = rstest::small_render(9, 9, 1);
  rs.max_depth = max_depth;
  rs.min_contribution = min_contribution;
  return rs;
}

// Two facing mirrors (reflectivity r) at z = -2 and z = 10, no lights: the
// center ray bounces between them until the depth limit or the cutoff stops it.
Scene facing_mirrors(float r) {
  Scene s;
  Material m;
  m.name = "mirror";
  m.reflectivity = r;
  s.materials = {m};
  s.planes.push_back(Plane{"front", Vec3(0, 0, -2), Vec3(0, 0, 1), 0});
  s.planes.push_back(Plane{"back", Vec3(0, 0, 10), Vec3(0, 0, -1), 0});
  return s;
}

// A skipped ray of this kind, parent, depth and reason, never walked.
void expect_skipped(const RayRecord& r, RayKind kind, int parent, int depth, SkipReason why) {
  EXPECT_EQ(r.kind, kind);
  EXPECT_EQ(r.parent, parent);
  EXPECT_EQ(r.depth, depth);
  EXPECT_TRUE(r.skipped);
  EXPECT_EQ(r.skip_reason, why);
  EXPECT_TRUE(r.traversal.steps.empty());
  EXPECT_TRUE(r.color == Color(0.0f));
}

std::vector<const RayRecord*> skipped_rays(const PixelRecord& rec) {
  std::vector<const RayRecord*> out;
  for (const RayRecord& r : rec.rays)
    if (r.skipped) out.push_back(&r);
  return out;
}

}  // namespace

// A sphere lit from behind: the shadow ray to the light is not traced (N.L <=
// 0) and appears in the tree as skipped, pointing at the light; the hit's
// local illumination is its ambient term alone.
TEST(RayTree, LightBehindTheSurfaceGivesASkippedShadowRay) {
  Scene s;
  Material m;
  m.name = "matte";
  m.ambient = 0.25f;
  s.materials = {m};
  s.spheres.push_back(Sphere{"ball", Vec3(0), 1.0f, 0});
  Light l;
  l.name = "back";
  l.position = Vec3(0, 0, -5);
  s.lights.push_back(l);
  s.commit();
  RenderSettings rs = center_render();
  prepare_frame(s, rs);
  PixelRecord rec = record_pixel(s, rs, 4, 4);
  ASSERT_EQ(rec.rays.size(), 2u);
  const RayRecord& primary = rec.rays[0];
  ASSERT_TRUE(primary.hit);
  EXPECT_NEAR(primary.point.z, 1.0f, 1e-5f);
  const RayRecord& shadow = rec.rays[1];
  expect_skipped(shadow, RayKind::Shadow, 0, 1, SkipReason::Backfacing);
  EXPECT_EQ(shadow.light, 0);
  EXPECT_NEAR(glm::normalize(shadow.dir).z, -1.0f, 1e-5f);  // toward the light at z = -5
  EXPECT_NEAR(shadow.origin.z, 1.0f, 1e-4f);                // from the hit
  EXPECT_TRUE(primary.lights.empty());
  // ambient 0.25 x material color 0.8 x ambient light 1, and nothing else
  for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(primary.ambient[k], 0.25f * 0.8f);
  EXPECT_TRUE(same_bits(primary.ambient, primary.color));
  // The renderer counts what the tree shows.
  RayCounters c;
  render(s, rs, &c);
  EXPECT_EQ(c.rays[int(RayKind::Shadow)], 0u);
  EXPECT_GT(c.shadow_skipped_backfacing, 0u);
}

// Depth limit 1 between two mirrors: primary (depth 0) -> reflection (depth 1)
// -> a reflection at depth 2 that is not traced, reason "depth limit".
TEST(RayTree, DepthLimitGivesASkippedReflectionRay) {
  Scene s = facing_mirrors(0.8f);
  s.commit();
  RenderSettings rs = center_render(1);
  prepare_frame(s, rs);
  PixelRecord rec = record_pixel(s, rs, 4, 4);
  ASSERT_EQ(rec.rays.size(), 3u);
  EXPECT_FALSE(rec.rays[1].skipped);
  EXPECT_EQ(rec.rays[1].kind, RayKind::Reflection);
  const RayRecord& cut = rec.rays[2];
  expect_skipped(cut, RayKind::Reflection, 1, 2, SkipReason::Depth);
  EXPECT_NEAR(cut.weight.x, 0.8f * 0.8f, 1e-6f);
  EXPECT_NEAR(glm::normalize(cut.dir).z, -1.0f, 1e-5f);  // back toward the front mirror
  EXPECT_NEAR(cut.origin.z, 10.0f, 1e-4f);               // from the back mirror
}

// The contribution cutoff: weights 1, 0.5, 0.25, then 0.125 < 0.2 is not traced.
TEST(RayTree, ContributionCutoffGivesASkippedReflectionRay) {
  Scene s = facing_mirrors(0.5f);
  s.commit();
  RenderSettings rs = center_render(20, 0.2f);
  prepare_frame(s, rs);
  PixelRecord rec = record_pixel(s, rs, 4, 4);
  ASSERT_EQ(rec.rays.size(), 4u);
  std::vector<const RayRecord*> cut = skipped_rays(rec);
  ASSERT_EQ(cut.size(), 1u);
  EXPECT_EQ(cut[0]->id, 3);
  expect_skipped(*cut[0], RayKind::Reflection, 2, 3, SkipReason::Contribution);
  EXPECT_NEAR(cut[0]->weight.x, 0.125f, 1e-7f);
  // The counters of a render agree with the tree: one cutoff per pixel.
  RayCounters c;
  render(s, rs, &c);
  EXPECT_EQ(c.weight_cutoffs, uint64_t(rs.width * rs.height));
  EXPECT_EQ(c.depth_cutoffs, 0u);
}

// The recorded local terms add up to what the integrator adds: on a diffuse
// and specular scene (no secondary rays) every hit's color is its ambient term
// plus the diffuse and specular terms of the lights reaching it; and each
// light is accounted for once per hit: reaching it, occluded, or skipped.
TEST(RayTree, LocalTermsAddUpToTheHitColor) {
  Scene s = diffuse_scene(true);
  s.materials[0].specular = 0.6f;
  s.materials[0].shininess = 20.0f;
  Light fill;
  fill.name = "fill";
  fill.type = Light::Type::Directional;
  fill.direction = Vec3(1, -1, -1);
  fill.intensity = 0.5f;
  s.lights.push_back(fill);
  s.commit();
  RenderSettings rs = rstest::small_render(40, 30, 2);
  prepare_frame(s, rs);
  int hits = 0, lit = 0, skipped = 0, occluded = 0;
  float max_specular = 0.0f;
  for (int y = 0; y < rs.height; y += 2)
    for (int x = 0; x < rs.width; x += 2) {
      PixelRecord rec = record_pixel(s, rs, x, y);
      for (const RayRecord& r : rec.rays) {
        if (r.kind != RayKind::Primary || !r.hit) continue;
        ++hits;
        Color sum = r.ambient;
        for (const LightTerms& t : r.lights) {
          sum += t.diffuse + t.specular;
          max_specular = std::max(max_specular, max_component(t.specular));
        }
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(sum[k], r.color[k], 1e-6f) << x << "," << y;
        // Every light once: a term, an occluded shadow ray, or a skipped one.
        std::vector<int> seen(s.lights.size(), 0);
        for (const LightTerms& t : r.lights) seen[size_t(t.light)]++;
        for (int c : r.children) {
          const RayRecord& sh = rec.rays[size_t(c)];
          ASSERT_EQ(sh.kind, RayKind::Shadow);
          if (sh.skipped || sh.occluded) seen[size_t(sh.light)]++;
          skipped += sh.skipped;
          occluded += sh.occluded;
        }
        for (int n : seen) EXPECT_EQ(n, 1) << x << "," << y;
        lit += !r.lights.empty();
      }
    }
  EXPECT_GT(hits, 200);
  EXPECT_GT(lit, 100);
  EXPECT_GT(skipped, 10);
  EXPECT_GT(occluded, 10);
  EXPECT_GT(max_specular, 0.05f);  // highlights were among them
}

// The walk in order: the root's box test first; every node entered after the
// root was tested and hit before; missed boxes are never entered; culled nodes
// were hit and never entered after; the hit's leaf is an entered leaf that
// holds a primitive of the hit object (shadow rays: of the occluder).
TEST(RayTree, WalkStepsAndHitLeaf) {
  for (AccelKind accel : {AccelKind::Bvh, AccelKind::BinaryBvh}) {
    Scene s = make_default_scene();
    AccelConfig config;
    config.kind = accel;
    s.commit(config);
    ASSERT_TRUE(s.summary().walks_structure);
    const Bvh& bvh = s.bvh();
    RenderSettings rs = rstest::small_render(48, 36, 1);
    prepare_frame(s, rs);
    int leaves = 0, culls = 0, misses = 0;
    for (int y = 0; y < rs.height; y += 3)
      for (int x = 0; x < rs.width; x += 3) {
        PixelRecord rec = record_pixel(s, rs, x, y);
        for (const RayRecord& r : rec.rays) {
          if (r.skipped) continue;
          const std::vector<TraversalStep>& st = r.traversal.steps;
          ASSERT_FALSE(st.empty());
          EXPECT_EQ(st[0].node, 0u);
          EXPECT_NE(st[0].kind, TraversalStep::Kind::Enter);
          std::vector<int> state(bvh.nodes.size(), 0);  // 1 hit, 2 missed, 3 entered, 4 culled
          for (size_t i = 0; i < st.size(); ++i) {
            int& n = state.at(st[i].node);
            switch (st[i].kind) {
              case TraversalStep::Kind::BoxHit:
                EXPECT_EQ(n, 0);
                n = 1;
                break;
              case TraversalStep::Kind::BoxMiss:
                EXPECT_EQ(n, 0);
                n = 2;
                ++misses;
                break;
              case TraversalStep::Kind::Enter:
                EXPECT_EQ(n, 1) << "node " << st[i].node << " entered without a box hit";
                n = 3;
                break;
              case TraversalStep::Kind::Cull:
                EXPECT_EQ(n, 1) << "node " << st[i].node << " culled without a box hit";
                n = 4;
                ++culls;
                break;
            }
          }
          const bool hit = r.kind == RayKind::Shadow ? r.occluded : r.hit;
          const uint32_t object = r.kind == RayKind::Shadow ? r.occluder : r.object;
          if (!hit || s.object_type(object) == ObjectType::Plane) {
            EXPECT_EQ(r.traversal.hit_leaf, kNoNode);
            continue;
          }
          const uint32_t leaf = r.traversal.hit_leaf;
          ASSERT_NE(leaf, kNoNode);
          EXPECT_EQ(state.at(leaf), 3);
          ASSERT_TRUE(bvh.nodes[leaf].is_leaf());
          bool holds = false;
          for (uint32_t i = 0; i < bvh.nodes[leaf].count; ++i)
            holds |= s.prim_object(bvh.prim_indices[bvh.nodes[leaf].index + i]) == object;
          EXPECT_TRUE(holds) << "leaf " << leaf << " holds no primitive of object " << object;
          ++leaves;
        }
      }
    EXPECT_GT(leaves, 100);
    EXPECT_GT(misses, 100);
    if (accel == AccelKind::Bvh) {
      EXPECT_GT(culls, 0);
    }
  }
}

// What inspect and the viewer show as "lecture's test" (textbook_intersect.h,
// format_json's "lecture_test") agrees with the robust test that found each
// hit: lambda is the ray's t within 1e-5 relative (t is the float the
// watertight test returns, within a few ulps; lambda the formula in double
// on the same float inputs), and a triangle's lambda1, lambda2 put the point
// inside it up to 1e-5 (a watertight hit on a shared edge may lie a
// rounding outside one of its two triangles). On the default scene: triangles
// (the torus), spheres and the plane.
TEST(RayTree, TheLecturesTestOfEveryHitAgreesWithTheRobustOne) {
  using nlohmann::json;
  Scene scene = make_default_scene();
  scene.commit();
  RenderSettings rs;
  rs.width = 64;
  rs.height = 48;
  rs.samples = 1;
  prepare_frame(scene, rs);
  std::map<std::string, int> tests;
  for (int y = 1; y < rs.height; y += 2)
    for (int x = 1; x < rs.width; x += 2) {
      const json j = json::parse(format_json(record_pixel(scene, rs, x, y), scene));
      for (const json& r : j["rays"]) {
        if (!r.value("hit", false)) continue;
        const json& t = r["lecture_test"];
        ASSERT_TRUE(t.is_object()) << r.dump();
        const std::string kind = t["test"];
        tests[kind]++;
        const double robust = r["t"], tol = 1e-5 * std::max(1.0, robust);
        if (kind == "ray-triangle") {
          EXPECT_NEAR(t["plane"]["lambda"].get<double>(), robust, tol) << r.dump();
          const double l1 = t["lambda1"], l2 = t["lambda2"];
          EXPECT_GE(l1, -1e-5) << r.dump();
          EXPECT_GE(l2, -1e-5) << r.dump();
          EXPECT_LE(l1 + l2, 1.0 + 1e-5) << r.dump();
        } else if (kind == "ray-sphere") {
          EXPECT_GE(t["discriminant"].get<double>(), 0.0) << r.dump();
          EXPECT_NEAR(t["lambda"].get<double>(), robust, tol) << r.dump();
        } else {
          ASSERT_EQ(kind, "ray-plane");
          EXPECT_NE(t["tr_dot_n"].get<double>(), 0.0) << r.dump();
          EXPECT_NEAR(t["lambda"].get<double>(), robust, tol) << r.dump();
        }
      }
    }
  EXPECT_GT(tests["ray-triangle"], 20);
  EXPECT_GT(tests["ray-sphere"], 20);
  EXPECT_GT(tests["ray-plane"], 20);
  // The text shows the same quantities, in the lecture's names.
  const PixelRecord rec = record_pixel(scene, rs, 20, 24);
  const std::string text = format_text(rec, scene);
  EXPECT_NE(text.find("lecture's test: "), std::string::npos) << text;
}
