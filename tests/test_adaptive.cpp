// Adaptive sampling (RenderSettings::max_samples, target_error; render.h):
// the batches cover the sample grid once, flat pixels stop after the first
// batch while edges take more, the image and the sample counts are the same
// for any thread count and tile size, a target of 0 is the fixed M x M render
// bit for bit, replayed pixels match, and bad settings are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <tuple>
#include <vector>

#include "rayscope/raytree_format.h"
#include "rayscope/render.h"
#include "rayscope/replay.h"
#include "rayscope/shapes.h"

namespace {

using namespace rayscope;

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

RenderSettings adaptive(int samples, int max_samples, float target) {
  RenderSettings s;
  s.width = 120;
  s.height = 90;
  s.samples = samples;
  s.max_samples = max_samples;
  s.target_error = target;
  s.max_depth = 5;
  return s;
}

TEST(Adaptive, BatchesCoverTheGridOnceEachSpreadOverThePixel) {
  for (auto [b, m] : {std::pair{1, 1}, {1, 4}, {2, 8}, {3, 9}, {2, 6}, {4, 64}, {1, 5}}) {
    RenderSettings s;
    s.samples = b;
    s.max_samples = m;
    ASSERT_NO_THROW(s.validate());
    const int kb = m / b;
    std::vector<int> order(static_cast<size_t>(kb), 0), strata(static_cast<size_t>(b * b), 0);
    std::vector<int> seen(static_cast<size_t>(m * m), 0);
    spread_order(kb, order.data());
    std::vector<int> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (int i = 0; i < kb; ++i) EXPECT_EQ(sorted[size_t(i)], i) << "order is a permutation";
    for (int j = 0; j < kb * kb; ++j) {
      batch_strata(s, order.data(), j, strata.data());
      // One stratum in each K x K block of the grid: the batch is a B x B
      // stratified pattern over the whole pixel.
      std::vector<int> blocks(size_t(b * b), 0);
      for (int k : strata) {
        ASSERT_GE(k, 0);
        ASSERT_LT(k, m * m);
        ++seen[size_t(k)];
        ++blocks[size_t((k / m / kb) * b + (k % m) / kb)];
      }
      for (int c : blocks) EXPECT_EQ(c, 1) << "B=" << b << " M=" << m << " batch " << j;
      if (j == 0) {
        EXPECT_EQ(strata[0], 0) << "the first sample is stratum 0 (the AOVs' sample)";
      }
    }
    for (int c : seen) EXPECT_EQ(c, 1) << "B=" << b << " M=" << m;
  }
}

TEST(Adaptive, FlatPixelsStopEarlyEdgesTakeMore) {
  Scene scene = make_default_scene();
  scene.commit();
  const RenderSettings s = adaptive(2, 8, 0.01f);
  const Framebuffer fb = render(scene, s);
  ASSERT_EQ(fb.samples.size(), fb.color.size());
  // The sky (top rows: background only) is flat: two batches of 2 x 2 (the
  // fewest that estimate a variance).
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < s.width; ++x) EXPECT_EQ(fb.samples[fb.index(x, y)], 8.0f) << x << "," << y;
  // Silhouettes (object id differs from a neighbour's) take more on average
  // than pixels inside one object, and some take all 64.
  double edge = 0, inner = 0;
  int n_edge = 0, n_inner = 0;
  float most = 0;
  for (int y = 1; y + 1 < s.height; ++y)
    for (int x = 1; x + 1 < s.width; ++x) {
      const size_t i = fb.index(x, y);
      const float id = fb.object_id[i];
      const bool is_edge =
          fb.object_id[fb.index(x - 1, y)] != id || fb.object_id[fb.index(x + 1, y)] != id ||
          fb.object_id[fb.index(x, y - 1)] != id || fb.object_id[fb.index(x, y + 1)] != id;
      (is_edge ? edge : inner) += fb.samples[i];
      ++(is_edge ? n_edge : n_inner);
      most = std::max(most, fb.samples[i]);
    }
  ASSERT_GT(n_edge, 0);
  ASSERT_GT(n_inner, 0);
  std::printf("mean samples: edges %.1f, elsewhere %.1f\n", edge / n_edge, inner / n_inner);
  // (Pixels inside an object include the checkerboard's own edges, which
  // take many samples too.)
  EXPECT_GT(edge / n_edge, 1.5 * inner / n_inner);
  EXPECT_EQ(most, 64.0f);
  // Every count is a whole number of batches.
  for (float c : fb.samples) EXPECT_EQ(std::fmod(c, 4.0f), 0.0f);
  // A looser target spends fewer samples.
  const Framebuffer loose = render(scene, adaptive(2, 8, 0.05f));
  double a = 0, b = 0;
  for (size_t i = 0; i < fb.samples.size(); ++i) {
    a += fb.samples[i];
    b += loose.samples[i];
  }
  EXPECT_LT(b, a);
  // The box-filtered checkerboard varies less within a pixel than the point
  // sampled one: the same target costs fewer samples.
  RenderSettings f = s;
  f.texture_filter = true;
  const Framebuffer filtered = render(scene, f);
  double c = 0;
  for (float v : filtered.samples) c += v;
  std::printf("samples in all: %.0f point sampled, %.0f filtered\n", a, c);
  EXPECT_LT(c, 0.9 * a);
}

TEST(Adaptive, SameImageAndCountsForAnyThreadCountAndTileSize) {
  Scene scene = make_default_scene();
  scene.commit();
  for (bool filter : {false, true}) {
    RenderSettings a = adaptive(2, 6, 0.004f);
    a.texture_filter = filter;
    a.threads = 1;
    RenderSettings b = a;
    b.threads = 2;
    b.tile_size = 5;
    RenderSettings c = a;
    c.threads = 4;
    c.tile_size = 64;
    const Framebuffer fa = render(scene, a), fb = render(scene, b), fc = render(scene, c);
    EXPECT_TRUE(same_bytes(fa.color, fb.color));
    EXPECT_TRUE(same_bytes(fa.color, fc.color));
    EXPECT_TRUE(same_bytes(fa.samples, fb.samples));
    EXPECT_TRUE(same_bytes(fa.samples, fc.samples));
    EXPECT_TRUE(same_bytes(fa.depth, fc.depth));
  }
}

TEST(Adaptive, TargetZeroIsTheFixedRenderBitForBit) {
  Scene scene = make_default_scene();
  scene.commit();
  // (Without the texture filter: with it, the adaptive render filters over
  // the cells of its batches, B x B, not over the M x M strata.)
  for (auto [b, m, filter] : {std::tuple{2, 6, false}, {1, 4, false}, {3, 6, false}}) {
    RenderSettings fixed = adaptive(m, 0, 0.0f);
    fixed.texture_filter = filter;
    RenderSettings all = adaptive(b, m, 0.0f);
    all.texture_filter = filter;
    RayCounters cf, ca;
    const Framebuffer ff = render(scene, fixed, &cf), fa = render(scene, all, &ca);
    EXPECT_TRUE(same_bytes(ff.color, fa.color)) << b << " of " << m;
    EXPECT_TRUE(same_bytes(ff.depth, fa.depth));
    EXPECT_TRUE(same_bytes(ff.normal, fa.normal));
    EXPECT_TRUE(same_bytes(ff.object_id, fa.object_id));
    EXPECT_EQ(ca.total_rays(), cf.total_rays());
    for (float c : fa.samples) ASSERT_EQ(c, float(m * m));
  }
}

TEST(Adaptive, ReplayedAndRecordedPixelsMatchTheRender) {
  Scene scene = make_default_scene();
  scene.commit();
  RenderSettings s = adaptive(2, 8, 0.01f);
  s.texture_filter = true;
  const Framebuffer fb = render(scene, s);
  std::vector<glm::ivec2> pixels{{3, 3}, {60, 40}, {40, 50}, {100, 60}, {20, 45}};
  std::vector<PixelRecord> records;
  const Framebuffer rec = render_and_record(scene, s, pixels, records);
  EXPECT_TRUE(same_bytes(fb.color, rec.color));
  EXPECT_TRUE(same_bytes(fb.samples, rec.samples));
  for (size_t k = 0; k < pixels.size(); ++k) {
    const int x = pixels[k].x, y = pixels[k].y;
    const PixelRecord r = record_pixel(scene, s, x, y);
    EXPECT_EQ(r.color, fb.color[fb.index(x, y)]) << x << "," << y;
    EXPECT_EQ(records[k].color, fb.color[fb.index(x, y)]);
    // One primary ray per sample the pixel took.
    int primaries = 0;
    for (const RayRecord& ray : r.rays) primaries += ray.parent < 0;
    EXPECT_EQ(float(primaries), fb.samples[fb.index(x, y)]) << x << "," << y;
    // The record says how many it took, and so do the text and JSON views.
    const int taken = int(fb.samples[fb.index(x, y)]);
    EXPECT_EQ(r.samples_taken, taken);
    EXPECT_EQ(records[k].samples_taken, taken);
    const std::string text = format_text(r, scene);
    if (taken < 64)
      EXPECT_NE(text.find("8x8 samples (adaptive: took " + std::to_string(taken) + " of 64)"),
                std::string::npos)
          << text.substr(0, 80);
    else
      EXPECT_EQ(text.find("adaptive"), std::string::npos) << text.substr(0, 80);
    EXPECT_NE(format_json(r, scene, -1).find("\"samples_taken\":" + std::to_string(taken)),
              std::string::npos);
  }
  // Statistics are another compiled policy of the same pixel loop.
  RenderSettings st = s;
  st.statistics = true;
  const Framebuffer fs = render(scene, st);
  EXPECT_TRUE(same_bytes(fb.color, fs.color));
  EXPECT_TRUE(same_bytes(fb.samples, fs.samples));
}

TEST(Adaptive, BadSettingsAreRefused) {
  auto message = [](const RenderSettings& s) {
    try {
      s.validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  RenderSettings s = adaptive(2, 5, 0.01f);
  EXPECT_EQ(message(s),
            "max_samples must be 0 (no adaptive sampling) or a multiple of samples (2) in 2..64, "
            "got 5");
  s.max_samples = 1;
  EXPECT_NE(message(s).find("max_samples must be"), std::string::npos);
  s.max_samples = 66;
  EXPECT_NE(message(s).find("got 66"), std::string::npos);
  s.max_samples = 8;
  EXPECT_EQ(message(s), "no error");
  s.target_error = -0.5f;
  EXPECT_EQ(message(s), "target_error must be in 0..1, got -0.5");
  s.target_error = std::nanf("");
  EXPECT_NE(message(s).find("target_error must be in 0..1"), std::string::npos);
  s.target_error = 2.0f;
  EXPECT_NE(message(s).find("target_error must be in 0..1"), std::string::npos);
  s.target_error = 0.01f;
  s.max_samples = 0;
  EXPECT_EQ(message(s),
            "target_error 0.01 needs adaptive sampling: max_samples must be set (a multiple of "
            "samples)");
  // The frame refuses them too (prepare_frame runs validate()).
  Scene scene = make_default_scene();
  scene.commit();
  EXPECT_THROW(render(scene, s), std::invalid_argument);
}

}  // namespace
