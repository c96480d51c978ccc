// Packets (ray_packet.h, wide_bvh_packet.h, triangle_packet.h): rays traced
// together give the single-ray walk's answers bit for bit (t, barycentrics,
// record and primitive, plane; occluded or not), on every scene in
// data/scenes/ (primary rays in 4x4 blocks and in rows of 16, shadow rays from
// their hits toward each light) and on adversarial rays (through vertices and
// shared edges, where the tie rule decides; mixed direction signs and dominant
// axes; short tmax; packets of 1 to 16 rays; rays from inside a closed mesh).
//
// This file is compiled for the baseline (SSE2), and once more for each
// higher x86-64 level the build machine runs (tests/CMakeLists.txt: avx2.*,
// avx512.*), so that the packet walk of every instruction set is run here:
// the packet calls and the walk are inline (aggregate_packet.h), instantiated
// in this file with its instruction set. The baseline build also tests the
// hot loops of every level as RayScope ships them (kernels.h; Kernels.*).
#include <gtest/gtest.h>

#include <cctype>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "rayscope/accel/bvh_walk.h"
#include "rayscope/camera.h"
#include "rayscope/integrator.h"
#include "rayscope/kernels.h"
#include "rayscope/packet_replay.h"
#include "rayscope/render.h"
#include "rayscope/render_block.h"
#include "rayscope/scene.h"
#include "rayscope/scene_io.h"
#include "rayscope/shapes.h"
#include "rayscope_vtkio/mesh_files.h"
#include "test_util.h"

namespace {

using namespace rayscope;

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

/// Whether two closest hits are the same, bit for bit.
::testing::AssertionResult same_hit(const PrimHit& a, const PrimHit& b) {
  if (same_bits(a.t, b.t) && same_bits(a.b0, b.b0) && same_bits(a.b1, b.b1) &&
      same_bits(a.b2, b.b2) && a.record == b.record && a.prim == b.prim && a.plane == b.plane)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "t " << a.t << " vs " << b.t << ", prim " << a.prim << " vs " << b.prim << ", plane "
         << a.plane << " vs " << b.plane << ", b0 " << a.b0 << " vs " << b.b0;
}

/// The closest hits of up to kPacketRays rays through the packet walk
/// instantiated in this file (its instruction set), for scenes of triangles
/// only, with the aggregate's tie rule written out: at equal t the higher
/// triangle index wins. Returns the lanes hit; hits[k].t and .prim filled.
unsigned packet_walk_of_this_file(const Scene& scene, std::span<const Ray> rays, PrimHit* hits) {
  const Aggregate& a = scene.accel();
  RayPacket packet;
  if (!packet.load(rays)) return ~0u;
  TrianglePrecomp pre[kPacketRays];
  uint32_t best[kPacketRays];
  for (size_t k = 0; k < rays.size(); ++k) {
    pre[k] = TrianglePrecomp(rays[k]);
    best[k] = ~0u;
  }
  auto prim = [&](unsigned lane, uint32_t i, float& t, const TriangleHit* decided) {
    const PrimRecord& r = a.records()[i];
    TriangleHit th;
    if (!(decided ? (th = *decided, true) : intersect_triangle(pre[lane], t, r.a, r.b, r.c, th)))
      return false;
    if (!(th.t < t || best[lane] == ~0u || r.id > a.records()[best[lane]].id)) return false;
    t = th.t;
    best[lane] = i;
    hits[lane].b0 = th.b0;
    hits[lane].b1 = th.b1;
    hits[lane].b2 = th.b2;
    return true;
  };
  const unsigned found = a.structure_as<BvhWalk>().traverse_packet<false>(packet, pre, prim);
  for (size_t k = 0; k < rays.size(); ++k) {
    if (!((found >> k) & 1u)) continue;
    hits[k].t = packet.tmax[k];
    hits[k].record = best[k];
    hits[k].prim = a.records()[best[k]].id;
    hits[k].plane = -1;
  }
  return found;
}

/// Checks Scene::intersect_packet and occluded_packet against the single-ray
/// calls for `rays`, taken `n` at a time. Adds to `walked` the number of
/// packets the packet walk took (the others are traced ray by ray).
void check_packets(const Scene& scene, const std::vector<Ray>& rays, size_t n,
                   const std::string& what, size_t* walked = nullptr) {
  for (size_t first = 0; first < rays.size(); first += n) {
    const std::span<const Ray> part(rays.data() + first, std::min(n, rays.size() - first));
    if (RayPacket probe; walked && probe.load(part)) ++*walked;
    PrimHit hits[kPacketRays];
    const unsigned found = scene.intersect_packet(part, hits);
    const unsigned occluded = scene.occluded_packet(part);
    for (size_t k = 0; k < part.size(); ++k) {
      PrimHit single;
      const bool hit = scene.intersect(part[k], single);
      ASSERT_EQ(hit, bool((found >> k) & 1u)) << what << ", ray " << first + k;
      if (hit) {
        ASSERT_TRUE(same_hit(hits[k], single)) << what << ", ray " << first + k;
      }
      ASSERT_EQ(scene.occluded(part[k]), bool((occluded >> k) & 1u))
          << what << ", ray " << first + k;
    }
  }
}

/// The primary rays of `cam` at w x h, in blocks of bw x bh pixels (each
/// block's rays row by row), blocks row by row.
std::vector<Ray> primary_blocks(Camera cam, int w, int h, int bw, int bh) {
  cam.prepare(w, h);
  std::vector<Ray> rays;
  for (int by = 0; by < h; by += bh)
    for (int bx = 0; bx < w; bx += bw)
      for (int y = by; y < std::min(by + bh, h); ++y)
        for (int x = bx; x < std::min(bx + bw, w); ++x)
          rays.push_back(cam.generate_ray(float(x) + 0.5f, float(y) + 0.5f));
  return rays;
}

/// Shadow rays from the hits of `primary` toward each light, spawned as the
/// integrator spawns them, in the primary rays' order (so neighbouring hits'
/// rays share a packet).
std::vector<Ray> shadow_rays(const Scene& scene, const std::vector<Ray>& primary) {
  std::vector<Ray> rays;
  for (const Light& light : scene.lights)
    for (const Ray& r : primary) {
      SurfaceHit h;
      if (!scene.intersect(r, h)) continue;
      const ShadingNormals sn = shading_normals(r, h);
      const LightView lv = light_view(light, h, sn.ng, sn.ns);
      if (lv.status == LightView::Status::Facing) rays.push_back(shadow_ray(h, sn.ng, light, lv.l));
    }
  return rays;
}

/// Calls f(scene, file name) for every scene of data/scenes/, committed with
/// the default structure; checks there are at least 8.
template <class F>
void for_each_data_scene(F&& f) {
  const std::filesystem::path dir = std::filesystem::path(RAYSCOPE_SOURCE_DIR) / "data/scenes";
  size_t scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    LoadedScene ls = load_scene(entry.path(), rayscope_vtkio::load_meshes);
    ls.scene.commit();
    ++scenes;
    f(ls.scene, name);
  }
  EXPECT_GE(scenes, 8u);
}

TEST(Packets, EveryDataSceneGivesTheSingleRayHits) {
  for_each_data_scene([](const Scene& scene, const std::string& name) {
    const std::vector<Ray> blocks = primary_blocks(scene.camera, 96, 72, 4, 4);
    const std::vector<Ray> rows = primary_blocks(scene.camera, 96, 72, 16, 1);
    size_t walked = 0;
    check_packets(scene, blocks, kPacketRays, name + " 4x4", &walked);
    check_packets(scene, rows, kPacketRays, name + " rows");
    check_packets(scene, shadow_rays(scene, blocks), kPacketRays, name + " shadow");
    // Coherent primary rays take the packet walk (unless the structure is too
    // small to walk): most blocks agree on their directions' signs.
    if (scene.accel().walks_structure()) {
      EXPECT_GT(walked, blocks.size() / kPacketRays / 2) << name;
    }
  });
}

/// Whether two framebuffers hold the same colors and AOVs, bit for bit.
::testing::AssertionResult same_image(const Framebuffer& a, const Framebuffer& b) {
  auto same = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof x[0]) == 0;
  };
  if (!same(a.color, b.color)) return ::testing::AssertionFailure() << "colors differ";
  if (!same(a.depth, b.depth)) return ::testing::AssertionFailure() << "depths differ";
  if (!same(a.normal, b.normal)) return ::testing::AssertionFailure() << "normals differ";
  if (!same(a.object_id, b.object_id)) return ::testing::AssertionFailure() << "object ids differ";
  return ::testing::AssertionSuccess();
}

// The frame loop renders plain images in blocks of pixels whose primary and
// shadow rays are packets (render_block.h): every data scene's image, AOVs
// and ray counters are those of the single-ray frame loop, bit for bit, with
// 2x2 samples, the texture filter, a progressive pass, and a size and tile
// size that leave partial blocks.
TEST(Packets, FrameLoopInBlocksGivesTheSingleRayImage) {
  for_each_data_scene([](Scene& scene, const std::string&) {
    RenderSettings rs;
    rs.width = 67;
    rs.height = 45;
    rs.tile_size = 14;  // blocks of 4x4, 4x2, 2x4 and 2x2 at the tiles' edges
    rs.samples = 2;
    rs.threads = 2;
    for (int variant = 0; variant < 3; ++variant) {
      SCOPED_TRACE("variant " + std::to_string(variant));
      rs.texture_filter = variant == 1;
      rs.only_sample = variant == 2 ? 3 : -1;
      RayCounters in_blocks, single;
      rs.packets = true;
      ASSERT_TRUE(renders_in_blocks(scene, rs));
      const Framebuffer a = render(scene, rs, &in_blocks);
      rs.packets = false;
      const Framebuffer b = render(scene, rs, &single);
      EXPECT_TRUE(same_image(a, b));
      EXPECT_EQ(in_blocks.rays, single.rays);
      EXPECT_EQ(in_blocks.hits, single.hits);
      EXPECT_EQ(in_blocks.primary_hits, single.primary_hits);
      EXPECT_EQ(in_blocks.shadow_occluded, single.shadow_occluded);
      EXPECT_EQ(in_blocks.shadow_skipped_backfacing, single.shadow_skipped_backfacing);
      EXPECT_GT(single.primary_hits, 0u);
    }
  });
}

// A pixel's packet replayed (record_packet) is the packet the frame loop
// traced: with primary rays only (no shadows, depth 0), each pixel's cost AOV
// is its lane's work in the replayed packet, for every pixel of an image whose
// tiles leave partial blocks. The log of its walk agrees with its counts, and
// its hits are the single-ray hits.
TEST(Packets, ReplayIsTheFrameLoopsPacket) {
  for_each_data_scene([](Scene& scene, const std::string&) {
    for (Light& l : scene.lights) l.casts_shadows = false;
    RenderSettings rs;
    rs.width = 67;
    rs.height = 45;
    rs.tile_size = 14;
    rs.max_depth = 0;
    rs.statistics = true;
    const Framebuffer fb = render(scene, rs);
    ASSERT_EQ(fb.cost.size(), size_t(rs.width) * size_t(rs.height));
    size_t walked = 0, partial = 0;
    for (int y = 0; y < rs.height; ++y)
      for (int x = 0; x < rs.width; ++x) {
        const PacketReplay r = record_packet(scene, rs, x, y);
        ASSERT_EQ(r.every_ray_alone, "");
        const int w = r.width();
        ASSERT_EQ(r.block.x0 + r.lane % w, x);
        ASSERT_EQ(r.block.y0 + r.lane / w, y);
        partial += r.rays() < kPacketRays;
        const PixelCost& aov = fb.cost[fb.index(x, y)];
        ASSERT_EQ(aov.nodes, r.cost.nodes[r.lane]) << x << "," << y;
        ASSERT_EQ(aov.boxes, r.cost.boxes[r.lane]) << x << "," << y;
        ASSERT_EQ(aov.prims, r.cost.prims[r.lane]) << x << "," << y;
        if (r.lane != 0) continue;  // the rest once per block
        if (r.cost.fell_back) {
          EXPECT_TRUE(r.steps.empty());
          continue;
        }
        ++walked;
        ASSERT_EQ(r.steps.size(), r.cost.node_visits);
        // The steps' boxes: the root's first, each one found, and each ray's
        // hit on a primitive inside a leaf it was active in.
        ASSERT_EQ(r.boxes.size(), r.steps.size());
        const Bounds3 root = scene.accel().structure_as<BvhWalk>().walk().root_bounds();
        if (!r.steps.empty()) {  // (none when every ray misses the root's box)
          EXPECT_TRUE(r.boxes[0].lo == root.lo && r.boxes[0].hi == root.hi);
        }
        for (const Bounds3& b : r.boxes) {
          EXPECT_TRUE(glm::all(glm::lessThanEqual(b.lo, b.hi)));  // found, not empty
          EXPECT_TRUE(glm::all(glm::lessThanEqual(root.lo, b.lo)) &&
                      glm::all(glm::lessThanEqual(b.hi, root.hi)));
        }
        for (int k = 0; k < r.rays(); ++k) {
          if (!(r.hits >> k & 1u) || r.hit[k].plane >= 0) continue;
          RayDifferential diff;
          const Ray ray = primary_ray(scene, rs, r.block.x0 + k % w, r.block.y0 + k / w, 0, &diff);
          const Vec3 p = ray.origin + r.hit[k].t * ray.dir;
          const float slack = 1e-4f * glm::length(root.hi - root.lo);
          bool inside = false;
          for (size_t i = 0; i < r.steps.size(); ++i)
            if ((r.steps[i].child & WideBvhNode::kLeaf) && (r.steps[i].lanes >> k & 1u))
              inside |= glm::all(glm::lessThanEqual(r.boxes[i].lo - slack, p)) &&
                        glm::all(glm::lessThanEqual(p, r.boxes[i].hi + slack));
          EXPECT_TRUE(inside) << "lane " << k;
        }
        uint32_t active = 0, per_lane[kPacketRays] = {};
        for (const PacketStep& st : r.steps) {
          active += uint32_t(__builtin_popcount(st.lanes));
          for (int k = 0; k < kPacketRays; ++k) per_lane[k] += st.lanes >> k & 1u;
          EXPECT_EQ(st.lanes >> r.rays(), 0u);
        }
        EXPECT_EQ(active, r.cost.active_lanes);
        for (int k = 0; k < r.rays(); ++k) {
          EXPECT_EQ(per_lane[k], r.cost.nodes[k]);
          RayDifferential diff;
          const Ray ray = primary_ray(scene, rs, r.block.x0 + k % w, r.block.y0 + k / w, 0, &diff);
          PrimHit single;
          const bool hit = scene.intersect(ray, single);
          ASSERT_EQ(hit, bool(r.hits >> k & 1u));
          if (hit) {
            EXPECT_TRUE(same_bits(single.t, r.hit[k].t));
            EXPECT_EQ(single.prim, r.hit[k].prim);
            EXPECT_EQ(single.plane, r.hit[k].plane);
          }
        }
      }
    EXPECT_GT(partial, 0u);
    if (scene.accel().walks_structure()) {
      EXPECT_GT(walked, 0u);
    }
  });
}

// The replay's text names the block, the pixel's lane and each step's active
// rays as the block's rows; a pixel outside the image is refused.
TEST(Packets, ReplayTextDrawsTheBlocksRows) {
  LoadedScene ls = load_scene(std::filesystem::path(RAYSCOPE_SOURCE_DIR) / "data/scenes/bunny.json",
                              rayscope_vtkio::load_meshes);
  ls.scene.commit();
  RenderSettings rs = ls.settings;
  rs.width = 320;
  rs.height = 240;
  prepare_frame(ls.scene, rs);
  // A block on the bunny's silhouette: its rays part ways.
  const PacketReplay r = record_packet(ls.scene, rs, 86, 122);
  ASSERT_FALSE(r.cost.fell_back);
  EXPECT_EQ(r.block.x0, 84);
  EXPECT_EQ(r.block.y0, 120);
  EXPECT_EQ(r.lane, 10);
  const std::string text = format_packet_text(r, ls.scene);
  EXPECT_NE(text.find("from (84, 120) to (87, 123)"), std::string::npos) << text;
  EXPECT_NE(text.find("lane 10 is this pixel"), std::string::npos) << text;
  EXPECT_NE(text.find("   1  node 0                  16  #### #### #### ####"), std::string::npos)
      << text;
  // One line per step; a step where only lane 10 is active draws one '#',
  // in row 2, column 2.
  size_t steps = 0, only_this = 0;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.size() > 4 && std::isdigit(static_cast<unsigned char>(line[3]))) ++steps;
    if (line.find(".... .... ..#. ....") != std::string::npos) {
      ++only_this;
      EXPECT_EQ(line.substr(line.size() - 2), "in") << line;
    }
  }
  EXPECT_EQ(steps, r.steps.size());
  EXPECT_GT(r.cost.node_visits, 16u);
  EXPECT_LT(double(r.cost.active_lanes) / r.cost.node_visits, 8.0);
  EXPECT_GT(only_this, 0u);
  EXPECT_THROW(record_packet(ls.scene, rs, 320, 0), std::out_of_range);
  EXPECT_THROW(record_packet(ls.scene, rs, 0, 0, rs.sample_grid() * rs.sample_grid()),
               std::out_of_range);
}

/// A closed icosphere and a flat grid of triangles with shared edges and
/// vertices, over a floor plane.
Scene adversarial_scene() {
  Scene s;
  Material m;
  m.name = "m";
  s.materials = {m};
  TriangleMesh ball = make_icosphere(Vec3(0.0f), 1.0f, 3);
  ball.material = 0;
  TriangleMesh grid;
  const int n = 8;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      grid.positions.push_back(Vec3(float(x) - 4.0f, float(y) - 4.0f, -2.0f));
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const unsigned i = unsigned(y * (n + 1) + x);
      grid.triangles.push_back({i, i + 1, i + unsigned(n) + 2});
      grid.triangles.push_back({i, i + unsigned(n) + 2, i + unsigned(n) + 1});
    }
  grid.material = 0;
  s.meshes = {ball, grid};
  s.planes = {Plane{"floor", Vec3(0.0f, -3.0f, 0.0f), Vec3(0.0f, 1.0f, 0.0f), 0}};
  Light l;
  l.position = Vec3(0.0f, 5.0f, 5.0f);
  s.lights = {l};
  return s;
}

/// Rays at the adversarial scene: exact ties at shared vertices and edges,
/// mixed direction signs, zero direction components, short tmax, several
/// dominant axes.
std::vector<Ray> adversarial_rays() {
  rstest::Rng rng(7);
  std::vector<Ray> rays;
  // Through the grid's vertices and edge midpoints from one eye: exact ties.
  const Vec3 eye(0.0f, 0.0f, 6.0f);
  for (int y = -4; y <= 4; ++y)
    for (int x = -4; x <= 4; ++x)
      for (const Vec3 off : {Vec3(0.0f), Vec3(0.5f, 0.0f, 0.0f), Vec3(0.5f, 0.5f, 0.0f)})
        rays.push_back(Ray{eye, Vec3(float(x), float(y), -2.0f) + off - eye, kInfinity});
  // From inside the ball, every direction (mixed signs).
  for (int i = 0; i < 160; ++i)
    rays.push_back(Ray{Vec3(0.1f, -0.2f, 0.05f), Vec3(rng.unit_vector()), kInfinity});
  // Coherent rays with short and shrinking tmax, and axis-aligned directions
  // (zero components: infinite reciprocals of both signs).
  for (int i = 0; i < 160; ++i) {
    const float x = -1.5f + 3.0f * float(i % 16) / 15.0f;
    rays.push_back(Ray{Vec3(x, 0.3f, 5.0f), Vec3(0.0f, 0.0f, -1.0f), 3.0f + 0.05f * float(i)});
  }
  for (int i = 0; i < 48; ++i)
    rays.push_back(Ray{Vec3(-5.0f, 0.25f * float(i % 8) - 1.0f, 0.0f),
                       Vec3(i % 2 ? 1.0f : -1.0f, 0.0f, i % 3 ? 0.0f : -0.0f), kInfinity});
  // Axis-aligned rays from the grid's vertex coordinates: their origins lie
  // on box planes of the structure, where 0 * inf makes a slab NaN (which
  // the rays' tests and the packet's frustum test both ignore).
  for (int i = 0; i < 81; ++i)
    rays.push_back(Ray{Vec3(float(i % 9) - 4.0f, float(i / 9) - 4.0f, 5.0f),
                       Vec3(i < 40 ? 0.0f : -0.0f, 0.0f, -1.0f), kInfinity});
  // Rays whose dominant axis differs within a packet.
  for (int i = 0; i < 64; ++i)
    rays.push_back(
        Ray{Vec3(0.0f, 0.0f, 4.0f), Vec3(0.02f * float(i), -0.01f * float(i), -1.0f), kInfinity});
  return rays;
}

TEST(Packets, AdversarialRaysGiveTheSingleRayHits) {
  Scene scene = adversarial_scene();
  scene.commit();
  const std::vector<Ray> rays = adversarial_rays();
  for (size_t n = 1; n <= size_t(kPacketRays); ++n)
    check_packets(scene, rays, n, "adversarial, " + std::to_string(n) + " per packet");
  check_packets(scene, shadow_rays(scene, rays), kPacketRays, "adversarial shadow");
}

TEST(Packets, PacketWalkOfThisFileGivesTheSingleRayHits) {
  // Triangles only (the walk's own tie rule above), a mesh the size of a
  // small model, viewed from several sides.
  Scene scene;
  Material m;
  m.name = "m";
  scene.materials = {m};
  TriangleMesh ball = subdivide(make_icosphere(Vec3(0.0f), 1.0f, 3));
  for (Vec3& p : ball.positions) p *= Vec3(1.0f + 0.3f * std::sin(7.0f * p.y), 1.0f, 1.0f);
  ball.material = 0;
  scene.meshes = {ball};
  scene.commit();
  ASSERT_TRUE(scene.accel().walks_structure());
  size_t walked = 0;
  for (const Vec3 eye :
       {Vec3(0.2f, 0.3f, 3.0f), Vec3(-3.0f, 1.0f, -0.5f), Vec3(0.1f, -2.5f, 0.4f)}) {
    Camera cam;
    cam.eye = eye;
    const std::vector<Ray> rays = primary_blocks(cam, 64, 64, 4, 4);
    for (size_t first = 0; first < rays.size(); first += kPacketRays) {
      const std::span<const Ray> part(rays.data() + first, kPacketRays);
      PrimHit hits[kPacketRays];
      const unsigned found = packet_walk_of_this_file(scene, part, hits);
      if (found == ~0u) continue;  // signs differ: not a packet
      ++walked;
      for (size_t k = 0; k < part.size(); ++k) {
        PrimHit single;
        const bool hit = scene.intersect(part[k], single);
        ASSERT_EQ(hit, bool((found >> k) & 1u)) << "ray " << first + k;
        if (hit) {
          ASSERT_TRUE(same_hit(hits[k], single)) << "ray " << first + k;
        }
      }
    }
  }
  EXPECT_GT(walked, 3 * 64 * 64 / kPacketRays / 2);
}

/// A single-ray walk's counts, as the statistics observer counts them.
struct WalkCount : TraversalHooks {
  static constexpr bool kActive = true;
  uint32_t nodes = 0, boxes = 0, prims = 0, culled = 0;
  void on_node(uint32_t) { ++nodes; }
  void on_box_test(uint32_t, bool) { ++boxes; }
  void on_cull(uint32_t) { ++culled; }
  void on_prim_test(uint32_t) { ++prims; }
};

// The walk of a packet of one ray, counted (PacketWalkCost), is the
// single-ray walk the statistics observer counts, for closest hits: the same
// nodes, boxes, primitives and culls.
TEST(Packets, OneRayPacketCountsTheSingleRayWalk) {
  Scene scene = adversarial_scene();
  scene.commit();
  Camera cam;
  cam.eye = Vec3(0.5f, 1.0f, 6.0f);
  cam.look_at = Vec3(0.0f);
  size_t tested = 0, culls = 0;
  for (const Ray& r : primary_blocks(cam, 40, 30, 1, 1)) {
    PacketWalkCost cost;
    PrimHit hit;
    ASSERT_LE(scene.intersect_packet(std::span<const Ray>(&r, 1), &hit, &cost), 1u);
    ASSERT_FALSE(cost.fell_back);
    WalkCount single;
    PrimHit alone;
    scene.intersect(r, alone, single);
    ASSERT_EQ(cost.nodes[0], single.nodes);
    ASSERT_EQ(cost.boxes[0], single.boxes);
    ASSERT_EQ(cost.prims[0], single.prims);
    ASSERT_EQ(cost.culled[0], single.culled);
    ASSERT_EQ(cost.node_visits, single.nodes);
    ASSERT_EQ(cost.active_lanes, single.nodes);
    ++tested;
    culls += single.culled;
  }
  EXPECT_EQ(tested, 1200u);
  EXPECT_GT(culls, 0u);
}

TEST(Packets, TooManyRaysAreRefused) {
  Scene scene = adversarial_scene();
  scene.commit();
  std::vector<Ray> rays(kPacketRays + 1);
  PrimHit hits[kPacketRays + 1];
  EXPECT_THROW(scene.intersect_packet(rays, hits), std::invalid_argument);
  EXPECT_THROW(scene.occluded_packet(rays), std::invalid_argument);
  EXPECT_EQ(scene.intersect_packet({}, hits), 0u);
}

#if !defined(RAYSCOPE_TEST_FOR_LEVEL)
// The hot loops of every level as RayScope ships them (kernels.h): compiled
// once per level and chosen at run time. Tested from the baseline build
// only (the level builds of this file would repeat them).

/// The levels whose hot loops this build has and this CPU runs, lowest first.
std::vector<Isa> runnable_levels() {
  std::vector<Isa> levels;
  for (Isa isa : kAllIsas)
    if (has_kernels(isa) && cpu_runs(isa)) levels.push_back(isa);
  return levels;
}

/// Each level's batch loops, one ray at a time and in packets, against this
/// file's single-ray calls, bit for bit.
void check_kernels(const Scene& scene, const std::vector<Ray>& rays, const std::string& what) {
  const size_t n = rays.size();
  std::vector<PrimHit> single(n);
  std::vector<uint8_t> hit(n), occluded(n);
  for (size_t i = 0; i < n; ++i) {
    hit[i] = scene.intersect(rays[i], single[i]);
    occluded[i] = scene.occluded(rays[i]);
  }
  for (Isa isa : runnable_levels()) {
    const Kernels& k = kernels(isa);
    ASSERT_EQ(k.isa, isa);
    for (auto intersect : {k.intersect, k.intersect_packets}) {
      std::vector<PrimHit> hits(n);
      std::vector<uint8_t> found(n, 2);
      intersect(scene, rays, hits.data(), found.data());
      for (size_t i = 0; i < n; ++i) {
        ASSERT_EQ(found[i], hit[i]) << isa_name(isa) << ", " << what << ", ray " << i;
        if (hit[i]) {
          ASSERT_TRUE(same_hit(hits[i], single[i]))
              << isa_name(isa) << ", " << what << ", ray " << i;
        }
      }
    }
    for (auto occluded_fn : {k.occluded, k.occluded_packets}) {
      std::vector<uint8_t> out(n, 2);
      occluded_fn(scene, rays, out.data());
      for (size_t i = 0; i < n; ++i)
        ASSERT_EQ(out[i], occluded[i]) << isa_name(isa) << ", " << what << ", ray " << i;
    }
  }
}

TEST(Kernels, ThisBuildHasEveryLevelAndThisCpuRunsItsBest) {
  if (kCompiledIsa == Isa::Sse2) {  // the portable build (not RAYSCOPE_NATIVE)
    for (Isa isa : kAllIsas) EXPECT_TRUE(has_kernels(isa)) << isa_name(isa);
  }
  EXPECT_TRUE(cpu_runs(Isa::Sse2));
  const std::vector<Isa> levels = runnable_levels();
  ASSERT_FALSE(levels.empty());
  EXPECT_EQ(levels.back(), best_cpu_isa());
  // Levels the CPU lacks are refused by name.
  for (Isa isa : kAllIsas)
    if (has_kernels(isa) && !cpu_runs(isa)) {
      EXPECT_THROW(kernels(isa), std::runtime_error) << isa_name(isa);
    }
}

TEST(Kernels, TheVariableChoosesALowerLevelAndBadValuesAreRefused) {
  Scene scene = adversarial_scene();
  scene.commit();
  RenderSettings rs;
  rs.width = 8;
  rs.height = 8;
  unsetenv(kIsaVariable);
  EXPECT_EQ(kernels().isa, best_cpu_isa());
  for (Isa isa : runnable_levels()) {
    setenv(kIsaVariable, std::string(isa_name(isa)).c_str(), 1);
    EXPECT_EQ(chosen_isa(), isa);
    EXPECT_EQ(kernels().isa, isa);
  }
  // A misspelt level stops renders and commits (the BVH builder is one of
  // the hot loops) with the one message.
  setenv(kIsaVariable, "avx1024", 1);
  try {
    kernels();
    ADD_FAILURE() << "RAYSCOPE_ISA=avx1024 was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(
        e.what(),
        "RAYSCOPE_ISA=avx1024: not an instruction set (one of sse2, sse4.2, avx2, avx512)");
  }
  EXPECT_THROW(render(scene, rs), std::runtime_error);
  Scene other = adversarial_scene();
  EXPECT_THROW(other.commit(), std::runtime_error);
  unsetenv(kIsaVariable);
}

TEST(Kernels, EveryLevelGivesTheSingleRayHits) {
  for_each_data_scene([](const Scene& scene, const std::string& name) {
    const std::vector<Ray> blocks = primary_blocks(scene.camera, 64, 48, 4, 4);
    check_kernels(scene, blocks, name);
    check_kernels(scene, shadow_rays(scene, blocks), name + " shadow");
  });
  Scene scene = adversarial_scene();
  scene.commit();
  const std::vector<Ray> rays = adversarial_rays();
  check_kernels(scene, rays, "adversarial");
  check_kernels(scene, shadow_rays(scene, rays), "adversarial shadow");
}

// Every level renders every data scene's image, AOVs, ray counters and, with
// statistics, traversal counters and per-pixel costs, bit for bit as the
// lowest level does.
TEST(Kernels, EveryLevelRendersTheSameFrame) {
  const std::vector<Isa> levels = runnable_levels();
  for_each_data_scene([&](Scene& scene, const std::string&) {
    RenderSettings rs;
    rs.width = 53;
    rs.height = 37;
    rs.samples = 2;
    rs.threads = 2;
    prepare_frame(scene, rs);
    // One framebuffer for every render, as a caller rendering frame after
    // frame keeps it: a plain frame after one with statistics has no costs.
    Framebuffer fb;
    for (bool statistics : {true, false}) {
      rs.statistics = statistics;
      RayCounters reference;
      Framebuffer ref;
      kernels(levels.front()).render(ref, scene, rs, &reference, {});
      for (Isa isa : levels) {
        SCOPED_TRACE(std::string(isa_name(isa)) + (statistics ? ", statistics" : ""));
        RayCounters c;
        kernels(isa).render(fb, scene, rs, &c, {});
        EXPECT_TRUE(same_image(fb, ref));
        ASSERT_EQ(fb.cost.size(), ref.cost.size());
        EXPECT_EQ(fb.cost.empty(), !statistics);
        if (!fb.cost.empty()) {
          EXPECT_EQ(
              std::memcmp(fb.cost.data(), ref.cost.data(), fb.cost.size() * sizeof(PixelCost)), 0);
        }
        EXPECT_EQ(c.rays, reference.rays);
        EXPECT_EQ(c.hits, reference.hits);
        EXPECT_EQ(c.shadow_occluded, reference.shadow_occluded);
        EXPECT_EQ(c.nodes_visited, reference.nodes_visited);
        EXPECT_EQ(c.boxes_tested, reference.boxes_tested);
        EXPECT_EQ(c.prims_tested, reference.prims_tested);
        EXPECT_EQ(c.packets, reference.packets);
        EXPECT_EQ(c.packet_active_lanes, reference.packet_active_lanes);
      }
    }
  });
}
#endif

}  // namespace
