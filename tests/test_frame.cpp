// The frame loop (frame.h) and its policies: a plain render, a render with
// statistics (per-pixel cost AOVs) and a render that records ray trees are one
// walk. The images are bit-identical, the cost AOV of every pixel equals the
// walk its recorded ray tree logs, and that walk is the one renders do (the
// 8-wide BVH by default; the binary teaching walk or the kD-tree only when
// chosen).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "rayscope/frame.h"
#include "rayscope/replay.h"
#include "rayscope/shapes.h"
#include "rayscope/tiles.h"
#include "test_util.h"

using namespace rayscope;

namespace {

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  // memcmp must not see the null data of an empty vector.
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void expect_same_image(const Framebuffer& a, const Framebuffer& b, const char* what) {
  EXPECT_TRUE(same_bytes(a.color, b.color)) << what;
  EXPECT_TRUE(same_bytes(a.depth, b.depth)) << what;
  EXPECT_TRUE(same_bytes(a.normal, b.normal)) << what;
  EXPECT_TRUE(same_bytes(a.object_id, b.object_id)) << what;
}

// Every third pixel of every other row: about 1/6 of the image, in most tiles.
std::vector<glm::ivec2> some_pixels(const RenderSettings& rs) {
  std::vector<glm::ivec2> p;
  for (int y = 0; y < rs.height; y += 2)
    for (int x = (y / 2) % 3; x < rs.width; x += 3) p.emplace_back(x, y);
  return p;
}

PixelCost walk_of(const PixelRecord& rec) {
  PixelCost c;
  for (const RayRecord& r : rec.rays) {
    c.rays += !r.skipped;  // skipped rays are recorded, not traced
    c.nodes += uint32_t(r.traversal.nodes().size());
    c.boxes += r.traversal.boxes_tested();
    c.prims += r.traversal.prims_tested;
    c.culled += r.traversal.culled();
  }
  return c;
}

class FrameWalk : public ::testing::TestWithParam<AccelKind> {};
INSTANTIATE_TEST_SUITE_P(Accel, FrameWalk,
                         ::testing::Values(AccelKind::Bvh, AccelKind::BinaryBvh, AccelKind::KdTree,
                                           AccelKind::Grid, AccelKind::Octree, AccelKind::Bsp,
                                           AccelKind::Spheres),
                         [](const auto& info) { return std::string(to_string(info.param)); });

TEST_P(FrameWalk, StatisticsAndRecordingObserveThePlainWalk) {
  // The default scene (glass, mirror, shadows, a mesh, spheres, a plane) with
  // 2x2 samples: plain, statistics and recording renders, and the recorded
  // pixels' walks against the cost AOV, field by field.
  Scene scene = make_default_scene();
  AccelConfig cfg;
  cfg.kind = GetParam();
  scene.commit(cfg);
  ASSERT_TRUE(scene.summary().walks_structure);
  RenderSettings rs = rstest::small_render(96, 72, 2);
  RayCounters plain_counters, stats_counters, record_counters;
  const Framebuffer plain = render(scene, rs, &plain_counters);
  RenderSettings with_stats = rs;
  with_stats.statistics = true;
  const Framebuffer stats = render(scene, with_stats, &stats_counters);
  const std::vector<glm::ivec2> pixels = some_pixels(rs);
  std::vector<PixelRecord> records;
  const Framebuffer recorded = render_and_record(scene, rs, pixels, records, &record_counters);

  expect_same_image(plain, stats, "plain vs statistics");
  expect_same_image(plain, recorded, "plain vs recording");
  EXPECT_EQ(plain_counters.rays, stats_counters.rays);
  EXPECT_EQ(plain_counters.rays, record_counters.rays);
  EXPECT_EQ(plain_counters.shadow_occluded, stats_counters.shadow_occluded);

  ASSERT_EQ(stats.cost.size(), stats.color.size());
  ASSERT_EQ(records.size(), pixels.size());
  for (size_t k = 0; k < pixels.size(); ++k) {
    const PixelCost aov = stats.cost[stats.index(pixels[k].x, pixels[k].y)];
    const PixelCost walk = walk_of(records[k]);
    const std::string at =
        "pixel (" + std::to_string(pixels[k].x) + ", " + std::to_string(pixels[k].y) + ")";
    ASSERT_EQ(aov.rays, walk.rays) << at;
    ASSERT_EQ(aov.nodes, walk.nodes) << at;
    ASSERT_EQ(aov.boxes, walk.boxes) << at;
    ASSERT_EQ(aov.prims, walk.prims) << at;
    ASSERT_EQ(aov.culled, walk.culled) << at;
  }
  // The counters are the sums of the AOV.
  PixelCost sum;
  for (const PixelCost& c : stats.cost) {
    sum.nodes += c.nodes;
    sum.boxes += c.boxes;
    sum.prims += c.prims;
    sum.culled += c.culled;
  }
  EXPECT_EQ(stats_counters.nodes_visited, sum.nodes);
  EXPECT_EQ(stats_counters.boxes_tested, sum.boxes);
  EXPECT_EQ(stats_counters.prims_tested, sum.prims);
  EXPECT_EQ(stats_counters.nodes_culled, sum.culled);
  EXPECT_GT(sum.culled, 0u);

  // A pixel replayed alone logs the walk its frame recorded.
  for (size_t k = 0; k < pixels.size(); k += 97) {
    const PixelRecord alone = record_pixel(scene, rs, pixels[k].x, pixels[k].y);
    ASSERT_EQ(alone.rays.size(), records[k].rays.size());
    for (size_t r = 0; r < alone.rays.size(); ++r)
      EXPECT_EQ(alone.rays[r].traversal.nodes(), records[k].rays[r].traversal.nodes());
  }
}

TEST(FrameWalk, DefaultWalkIsTheWideOneAndBinaryIsAChoice) {
  // The walk that statistics report is the 8-wide one unless the binary walk
  // is chosen: every recorded inner node is the top of a wide node, and the
  // binary walk enters more nodes and tests fewer boxes per node for the same
  // image.
  RenderSettings rs = rstest::small_render(64, 48, 1);
  rs.statistics = true;
  Scene wide = make_default_scene(), binary = make_default_scene();
  wide.commit();
  AccelConfig cfg;
  cfg.kind = AccelKind::BinaryBvh;
  binary.commit(cfg);
  RayCounters cw, cb;
  const Framebuffer fw = render(wide, rs, &cw), fb = render(binary, rs, &cb);
  expect_same_image(fw, fb, "8-wide vs binary walk");
  std::printf(
      "default scene 64x48: 8-wide walk %llu nodes, %llu boxes; binary walk %llu nodes, "
      "%llu boxes\n",
      (unsigned long long)cw.nodes_visited, (unsigned long long)cw.boxes_tested,
      (unsigned long long)cb.nodes_visited, (unsigned long long)cb.boxes_tested);
  EXPECT_GT(cb.nodes_visited, cw.nodes_visited);
  EXPECT_LT(double(cb.boxes_tested) / double(cb.nodes_visited),
            double(cw.boxes_tested) / double(cw.nodes_visited));

  const Bvh& bvh = wide.bvh();
  const WideBvh& walk = wide.accel().structure_as<BvhWalk>().walk();
  ASSERT_EQ(walk.arity(), WideBvh::kRenderArity);
  std::vector<char> is_top(bvh.nodes.size(), 0);
  is_top[0] = 1;
  for (uint32_t src : walk.slot_source)
    if (src != ~0u) is_top[src] = 1;
  std::vector<glm::ivec2> pixels = some_pixels(rs);
  std::vector<PixelRecord> records;
  RenderSettings plain = rs;
  plain.statistics = false;
  render_and_record(wide, plain, pixels, records);
  size_t nodes = 0;
  for (const PixelRecord& rec : records)
    for (const RayRecord& r : rec.rays)
      for (uint32_t n : r.traversal.nodes()) {
        ASSERT_TRUE(is_top[n]) << "node " << n << " is inside a 8-wide node";
        ++nodes;
      }
  EXPECT_GT(nodes, 0u);
}

TEST(Frame, PolicyFinishSeesEveryPixelOnce) {
  // A custom policy (as the VTK BVH source uses): finish() runs once per
  // pixel, concurrently, with the pixel's own recorder.
  struct CountPixels : FramePolicy {
    std::vector<std::atomic<int>>* seen;
    void finish(size_t i, NullRecorder&, RayCounters&, Framebuffer&) { (*seen)[i]++; }
  };
  Scene scene = make_default_scene();
  scene.commit();
  const RenderSettings rs = rstest::small_render(37, 29, 1);  // tiles cut at the borders
  prepare_frame(scene, rs);
  std::vector<std::atomic<int>> seen(size_t(rs.width * rs.height));
  CountPixels policy;
  policy.seen = &seen;
  size_t progress_calls = 0, last_done = 0, total_tiles = 0;
  render_frame(scene, rs, policy, nullptr, [&](size_t done, size_t total) {
    ++progress_calls;
    last_done = std::max(last_done, done);
    total_tiles = total;
  });
  for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << "pixel " << i;
  EXPECT_EQ(total_tiles, size_t(3 * 2));  // 16-pixel tiles
  EXPECT_EQ(progress_calls, total_tiles);
  EXPECT_EQ(last_done, total_tiles);
}

TEST(Frame, TileDoneShowsFinishedPixelsOnce) {
  // tile_done() (what a progressive display reads) covers every pixel exactly
  // once, and the colors it sees are the final ones.
  struct CopyTiles : FramePolicy {
    std::vector<std::atomic<int>>* seen;
    std::vector<Color>* copy;
    void tile_done(int x0, int y0, int x1, int y1, const Framebuffer& fb) {
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          (*seen)[fb.index(x, y)]++;
          (*copy)[fb.index(x, y)] = fb.color[fb.index(x, y)];
        }
    }
  };
  Scene scene = make_default_scene();
  scene.commit();
  const RenderSettings rs = rstest::small_render(37, 29, 1);
  prepare_frame(scene, rs);
  std::vector<std::atomic<int>> seen(size_t(rs.width * rs.height));
  std::vector<Color> copy(seen.size(), Color(-1.0f));
  CopyTiles policy;
  policy.seen = &seen;
  policy.copy = &copy;
  Framebuffer fb = render_frame(scene, rs, policy);
  for (size_t i = 0; i < seen.size(); ++i) {
    ASSERT_EQ(seen[i].load(), 1) << "pixel " << i;
    ASSERT_EQ(0, std::memcmp(&copy[i], &fb.color[i], sizeof(Color))) << "pixel " << i;
  }
}

TEST(FrameShares, SharesRenderedApartAssembleToTheWholeImage) {
  // What the processes of a parallel render do: each renders its share of the
  // tiles and packs it; the assembler unpacks every share into one
  // framebuffer. Bit-identical to the whole render for 1, 2, 3 and 7 shares
  // (more than there are rows of tiles in one test), with statistics and
  // adaptive sampling (the packed optional channels), with tile sizes that
  // do not divide the image.
  Scene scene = make_default_scene();
  scene.commit();
  for (const bool stats : {false, true})
    for (const int tile : {16, 7}) {
      RenderSettings rs = rstest::small_render(53, 41, 2);
      rs.tile_size = tile;
      rs.statistics = stats;
      rs.max_samples = stats ? 0 : 4;
      RayCounters whole_counters;
      const Framebuffer whole = render(scene, rs, &whole_counters);
      for (const int count : {1, 2, 3, 7}) {
        const std::string what = "stats " + std::to_string(stats) + ", tile " +
                                 std::to_string(tile) + ", " + std::to_string(count) + " shares";
        Framebuffer assembled;
        assembled.resize(rs.width, rs.height);
        if (stats) assembled.cost.assign(assembled.color.size(), PixelCost{});
        if (rs.max_samples > 0) assembled.samples.assign(assembled.color.size(), 0.0f);
        RayCounters sum;
        size_t tiles = 0;
        for (int index = 0; index < count; ++index) {
          RenderSettings part = rs;
          part.share = {index, count};
          RayCounters counters;
          const Framebuffer fb = render(scene, part, &counters);
          sum += counters;
          tiles += TileGrid(part).share_count(part.share);
          const std::vector<float> packed = pack_share(fb, part);
          unpack_share(assembled, part, packed);
          // A buffer of another share's length is refused.
          if (count > 1) {
            RenderSettings other = part;
            other.share.index = (index + 1) % count;
            if (TileGrid(other).share_count(other.share) !=
                TileGrid(part).share_count(part.share)) {
              EXPECT_THROW(unpack_share(assembled, other, packed), std::invalid_argument) << what;
            }
          }
        }
        EXPECT_EQ(tiles, TileGrid(rs).count()) << what;
        expect_same_image(whole, assembled, what.c_str());
        EXPECT_TRUE(same_bytes(whole.samples, assembled.samples)) << what;
        if (stats) {
          ASSERT_EQ(whole.cost.size(), assembled.cost.size());
          EXPECT_EQ(0, std::memcmp(whole.cost.data(), assembled.cost.data(),
                                   whole.cost.size() * sizeof(PixelCost)))
              << what;
          EXPECT_EQ(whole_counters.nodes_visited, sum.nodes_visited) << what;
        }
        EXPECT_EQ(whole_counters.rays, sum.rays) << what;
      }
    }
  // Bad shares are refused by the one settings check.
  RenderSettings bad = rstest::small_render(8, 8, 1);
  bad.share = {2, 2};
  EXPECT_THROW(bad.validate(), std::invalid_argument);
  bad.share = {0, 0};
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

}  // namespace
