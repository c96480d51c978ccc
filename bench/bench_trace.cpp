// bench_trace: RayScope's BVH against Embree 3 on identical rays.
//
// For the Stanford bunny (69,666 triangles) and, unless --no-big, a version of it
// subdivided twice (1,114,656 triangles) this measures
//  - build time: Scene::commit() (validation + bounds + binned SAH build + its
//    8-wide collapse + leaf blocks) and Bvh::build() alone, limited to N
//    threads by tbb::global_control, and rtcCommitScene() with Embree's builder
//    limited to N threads (device config "threads=N"), N from --threads;
//  - memory: every byte of our aggregate and what Embree's memory monitor
//    counts while it builds, per triangle;
//  - primary rays (closest hit): Scene::intersect vs rtcIntersect1, one ray per
//    pixel centre of a pinhole camera framing the mesh, traced in 16x16 tiles.
//    Ours uses the lean query Scene::intersect(ray, PrimHit&), which returns t,
//    barycentrics and primitive ids, i.e. the same work as rtcIntersect1 (t, u,
//    v, Ng, primID, geomID); the shading data of Scene::surface_hit (hit point
//    and error bound, interpolated normal, object, material) is not computed;
//  - shadow rays (any hit): Scene::occluded vs rtcOccluded1, spawned once with
//    spawn_ray_to from our primary hits toward a point light above the mesh (only
//    where the light is in front of the surface, as the Whitted integrator does),
//    and fed unchanged to both tracers.
// Both tracers run the same loop: tbb::parallel_for over blocks of 256 rays
// inside a tbb::task_arena(threads), one warm-up pass each, then --runs passes
// alternating ours / Embree (so background load hits both alike), median
// reported. Embree's "threads=N" only limits its builder; tracing with
// rtcIntersect1 / rtcOccluded1 runs on the calling (arena) thread. Embree is
// used with default scene flags (not RTC_SCENE_FLAG_ROBUST) unless
// --embree-robust, and BUILD_QUALITY_MEDIUM (binned SAH, like ours) unless
// --embree-quality says otherwise.
//  - Embree's packet calls on the same rays: rtcIntersect8/16 and
//    rtcOccluded8/16 with the coherent flag, 8 or 16 consecutive rays of a
//    block per call (half a row or a row of a 16x16 tile of primary rays), as
//    an Embree user traces coherent rays; reported against its single-ray
//    calls and ours, with the rays whose packet answer differs from its
//    single-ray one.
// Finally the two tracers' answers are compared ray by ray.
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "rayscope/camera.h"
#include "rayscope/kernels.h"
#include "rayscope/scene.h"
#include "rayscope/shapes.h"
#include "rayscope_vtkio/mesh_files.h"

namespace {

using namespace rayscope;
using Clock = std::chrono::steady_clock;

constexpr size_t kBlock = 256;  // rays per task; one 16x16 tile of primary rays
constexpr int kTile = 16;
constexpr const char* kDefaultMesh = "/usr/share/glmark2/models/bunny.obj";
constexpr double kRelTolerance = 1e-4;    // hit distances agree when closer than this
constexpr double kAgreeRequired = 0.999;  // fraction of rays that must agree

static_assert(sizeof(Vec3) == 3 * sizeof(float));
static_assert(sizeof(glm::uvec3) == 3 * sizeof(unsigned));

// ---------------------------------------------------------------------------
// Options

struct Options {
  int runs = 7;
  int res = 1024;
  std::string mesh = kDefaultMesh;
  bool big = true;
  std::string csv;
  std::vector<int> threads{1, 2};
  /// Our builder's settings (--leaf-cost sets its intersection_cost).
  AccelConfig accel;
  RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM;
  bool robust = false;  // RTC_SCENE_FLAG_ROBUST (watertight, like ours) instead of none
};

const char* quality_name(RTCBuildQuality q) {
  switch (q) {
    case RTC_BUILD_QUALITY_LOW:
      return "LOW";
    case RTC_BUILD_QUALITY_MEDIUM:
      return "MEDIUM";
    case RTC_BUILD_QUALITY_HIGH:
      return "HIGH";
    default:
      return "REFIT";
  }
}

[[noreturn]] void usage(int code) {
  std::fprintf(
      code ? stderr : stdout,
      "usage: bench_trace [options]\n"
      "  --runs N              timed passes per measurement, median reported (default 7)\n"
      "  --res N               N x N primary rays (default 1024)\n"
      "  --mesh PATH           mesh file read through VTK (default %s)\n"
      "  --no-big              skip the subdivided (> 1M triangle) mesh\n"
      "  --threads LIST        comma-separated thread counts (default 1,2)\n"
      "  --embree-quality Q    low | medium | high (default medium: binned SAH,\n"
      "                        like ours; high adds spatial splits)\n"
      "  --embree-robust       build Embree scenes with RTC_SCENE_FLAG_ROBUST (watertight\n"
      "                        like ours; default: no flags, Embree's fast path)\n"
      "  --leaf-cost X         our builder's cost of a primitive test relative to a node\n"
      "                        visit, BvhBuildConfig::intersection_cost (default %g)\n"
      "  --csv FILE            also write all results to FILE\n",
      kDefaultMesh, double(BvhBuildConfig{}.intersection_cost));
  std::exit(code);
}

int parse_int(const std::string& s, const char* what, int lo, int hi) {
  try {
    size_t pos = 0;
    int v = std::stoi(s, &pos);
    if (pos == s.size() && v >= lo && v <= hi) return v;
  } catch (const std::exception&) {
  }
  std::fprintf(stderr, "bench_trace: %s must be an integer in %d..%d, got '%s'\n", what, lo, hi,
               s.c_str());
  std::exit(2);
}

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_trace: %s needs a value\n", a.c_str());
        usage(2);
      }
      return argv[++i];
    };
    if (a == "-h" || a == "--help") {
      usage(0);
    } else if (a == "--runs") {
      o.runs = parse_int(value(), "--runs", 1, 1000);
    } else if (a == "--res") {
      o.res = parse_int(value(), "--res", 1, 16384);
    } else if (a == "--mesh") {
      o.mesh = value();
    } else if (a == "--no-big") {
      o.big = false;
    } else if (a == "--embree-robust") {
      o.robust = true;
    } else if (a == "--csv") {
      o.csv = value();
    } else if (a == "--leaf-cost") {
      const std::string v = value();
      char* end = nullptr;
      const float c = std::strtof(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(c >= 0.01f && c <= 100.0f)) {
        std::fprintf(stderr, "bench_trace: --leaf-cost must be a number in 0.01..100, got '%s'\n",
                     v.c_str());
        std::exit(2);
      }
      o.accel.bvh.intersection_cost = c;
    } else if (a == "--threads") {
      o.threads.clear();
      std::stringstream ss(value());
      for (std::string t; std::getline(ss, t, ',');)
        o.threads.push_back(parse_int(t, "--threads", 1, 1024));
      if (o.threads.empty()) usage(2);
    } else if (a == "--embree-quality") {
      const std::string q = value();
      if (q == "low")
        o.quality = RTC_BUILD_QUALITY_LOW;
      else if (q == "medium")
        o.quality = RTC_BUILD_QUALITY_MEDIUM;
      else if (q == "high")
        o.quality = RTC_BUILD_QUALITY_HIGH;
      else
        usage(2);
    } else {
      std::fprintf(stderr, "bench_trace: unknown option '%s'\n", a.c_str());
      usage(2);
    }
  }
  return o;
}

// ---------------------------------------------------------------------------
// Timing and system information

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// One untimed warm-up call, then the median of `runs` calls; `once` returns seconds.
template <class F>
double median_seconds(int runs, F&& once) {
  once();
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) t.push_back(once());
  return median(t);
}

/// The same for two contenders, timed alternately (a, b, a, b, ...) so that load
/// from other processes hits both alike; returns the two medians in seconds.
template <class A, class B>
std::pair<double, double> median_seconds_interleaved(int runs, A&& a, B&& b) {
  a();
  b();
  std::vector<double> ta, tb;
  for (int i = 0; i < runs; ++i) {
    ta.push_back(a());
    tb.push_back(b());
  }
  return {median(ta), median(tb)};
}

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  for (std::string line; std::getline(f, line);) {
    if (line.rfind("model name", 0) != 0) continue;
    size_t colon = line.find(':');
    if (colon == std::string::npos) break;
    size_t start = line.find_first_not_of(" \t", colon + 1);
    return start == std::string::npos ? "unknown" : line.substr(start);
  }
  return "unknown";
}

std::string load_average() {
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  if (!(f >> a >> b >> c)) return "unknown";
  return a + " " + b + " " + c;
}

std::string compiler() {
#if defined(__clang__)
  return "clang " __clang_version__;
#elif defined(__GNUC__)
  return "g++ " __VERSION__;
#else
  return "unknown compiler";
#endif
}

// ---------------------------------------------------------------------------
// Embree

const char* tasking_name(ssize_t v) {
  switch (v) {
    case 0:
      return "internal";
    case 1:
      return "TBB";
    case 2:
      return "PPL";
    default:
      return "unknown";
  }
}

void embree_error(void* /*user*/, RTCError code, const char* message) {
  std::fprintf(stderr, "Embree error %d: %s\n", int(code), message ? message : "");
}

RTCDevice new_device(const std::string& config) {
  RTCDevice dev = rtcNewDevice(config.c_str());
  if (!dev) {
    std::fprintf(stderr, "bench_trace: rtcNewDevice(\"%s\") failed (error %d)\n", config.c_str(),
                 int(rtcGetDeviceError(nullptr)));
    std::exit(2);
  }
  rtcSetDeviceErrorFunction(dev, embree_error, nullptr);
  return dev;
}

/// Net bytes Embree's devices hold (its memory monitor callback: every
/// allocation and release of scene and geometry memory).
std::atomic<int64_t> g_embree_bytes{0};

bool embree_memory(void*, ssize_t bytes, bool) {
  g_embree_bytes += int64_t(bytes);
  return true;
}

/// Builds an Embree scene holding one triangle mesh. The vertex and index data
/// are copied into Embree-owned buffers (rtcSetNewGeometryBuffer): a shared
/// std::vector<Vec3> does not guarantee the 4 bytes of readable padding after
/// the last vertex that Embree's 16-byte loads need. The copy is part of the
/// measured build, as our commit() also copies the vertices into its leaves.
RTCScene embree_scene(RTCDevice dev, const TriangleMesh& m, RTCBuildQuality quality, bool robust) {
  RTCScene scene = rtcNewScene(dev);
  rtcSetSceneFlags(scene, robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
  rtcSetSceneBuildQuality(scene, quality);
  RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(geom, quality);
  void* v = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                    sizeof(Vec3), m.positions.size());
  void* i = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    sizeof(glm::uvec3), m.triangles.size());
  if (!v || !i) {
    std::fprintf(stderr, "bench_trace: Embree could not allocate the geometry buffers\n");
    std::exit(2);
  }
  std::memcpy(v, m.positions.data(), m.positions.size() * sizeof(Vec3));
  std::memcpy(i, m.triangles.data(), m.triangles.size() * sizeof(glm::uvec3));
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);
  return scene;
}

// ---------------------------------------------------------------------------
// Rays

/// Pinhole camera looking at the centre of the mesh bounds from the front, a
/// little from above and to the side, close enough that the mesh fills most of
/// the frame (for the bunny about 40% of the primary rays hit).
Camera framing_camera(const Bounds3& b, int res) {
  Camera cam;
  const Vec3 c = b.center();
  const float r = 0.5f * glm::length(b.extent());
  cam.vfov_degrees = 40.0f;
  const float dist = 0.75f * r / std::tan(0.5f * glm::radians(cam.vfov_degrees));
  cam.eye = c + dist * glm::normalize(Vec3(0.35f, 0.3f, 1.0f));
  cam.look_at = c;
  cam.up = Vec3(0.0f, 1.0f, 0.0f);
  cam.prepare(res, res);
  return cam;
}

/// A point light above the mesh, in front and to the left: about one shadow ray
/// in ten is blocked on the bunny (ears and head on the back).
Vec3 light_position(const Bounds3& b) {
  const Vec3 c = b.center();
  const float r = 0.5f * glm::length(b.extent());
  return c + r * Vec3(-1.0f, 2.0f, 1.5f);
}

/// One ray through every pixel centre, in 16x16 tiles (rows within a tile), so
/// that each 256-ray block is one compact tile as in the renderer.
std::vector<Ray> primary_rays(const Camera& cam, int res) {
  std::vector<Ray> rays;
  rays.reserve(size_t(res) * size_t(res));
  for (int ty = 0; ty < res; ty += kTile)
    for (int tx = 0; tx < res; tx += kTile)
      for (int y = ty; y < std::min(ty + kTile, res); ++y)
        for (int x = tx; x < std::min(tx + kTile, res); ++x)
          rays.push_back(cam.generate_ray(float(x) + 0.5f, float(y) + 0.5f));
  return rays;
}

struct ShadowSet {
  std::vector<Ray> rays;
  size_t primary_hits = 0;
  size_t facing_away = 0;  // hits where the light is behind the surface: no shadow ray
};

/// Shadow rays from our closest hits toward the light, spawned exactly as the
/// integrator does (normal facing the incoming ray, spawn_ray_to, t in (0, 1)).
ShadowSet shadow_rays(const Scene& scene, const std::vector<Ray>& primary, const Vec3& light) {
  const size_t n = primary.size();
  std::vector<Ray> slot(n);
  std::vector<uint8_t> state(n, 0);  // 0 miss, 1 facing away, 2 shadow ray
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kBlock),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i) {
                        SurfaceHit h;
                        if (!scene.intersect(primary[i], h)) continue;
                        const Vec3 ng = glm::dot(primary[i].dir, h.ng) < 0.0f ? h.ng : -h.ng;
                        if (glm::dot(ng, light - h.p) <= 0.0f) {
                          state[i] = 1;
                          continue;
                        }
                        slot[i] = spawn_ray_to(h.p, h.p_error, ng, light);
                        state[i] = 2;
                      }
                    });
  ShadowSet s;
  for (size_t i = 0; i < n; ++i) {
    if (state[i] == 0) continue;
    s.primary_hits++;
    if (state[i] == 1)
      s.facing_away++;
    else
      s.rays.push_back(slot[i]);
  }
  return s;
}

// ---------------------------------------------------------------------------
// Tracing loops (identical scheduling for both tracers)

/// Runs body(begin, end) over blocks of kBlock rays in the arena; returns seconds.
template <class Body>
double run_blocks(tbb::task_arena& arena, size_t n, const Body& body) {
  const size_t nblocks = (n + kBlock - 1) / kBlock;
  const auto t0 = Clock::now();
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, nblocks, 1),
        [&](const tbb::blocked_range<size_t>& r) {
          for (size_t b = r.begin(); b != r.end(); ++b)
            body(b * kBlock, std::min(n, (b + 1) * kBlock));
        },
        tbb::simple_partitioner());
  });
  return seconds_since(t0);
}

struct PrimaryResult {
  std::vector<float> t;  // +inf for a miss
  std::vector<uint32_t> prim;
  explicit PrimaryResult(size_t n) : t(n, kInfinity), prim(n, ~0u) {}
};

/// Copies a block's hits into `out` (t = +inf, prim = ~0u for a miss).
void store_hits(size_t begin, size_t end, const PrimHit* hits, const uint8_t* found,
                PrimaryResult& out) {
  for (size_t i = begin; i < end; ++i) {
    out.t[i] = found[i - begin] ? hits[i - begin].t : kInfinity;
    out.prim[i] = found[i - begin] ? hits[i - begin].prim : ~0u;
  }
}

// Our loops are the hot loops of kernels.h, as RayScope ships them: compiled
// for every x86-64 level, run with the CPU's best (or $RAYSCOPE_ISA's).
// Single rays: the lean query (t, barycentrics, ids; no shading data, as
// rtcIntersect1), one ray at a time.
double trace_ours_primary(tbb::task_arena& arena, const Scene& scene, const std::vector<Ray>& rays,
                          PrimaryResult& out) {
  const Kernels& k = kernels();
  return run_blocks(arena, rays.size(), [&](size_t begin, size_t end) {
    PrimHit hits[kBlock];
    uint8_t found[kBlock];
    k.intersect(scene, std::span(rays).subspan(begin, end - begin), hits, found);
    store_hits(begin, end, hits, found, out);
  });
}

double trace_embree_primary(tbb::task_arena& arena, RTCScene scene, const std::vector<Ray>& rays,
                            PrimaryResult& out) {
  return run_blocks(arena, rays.size(), [&](size_t begin, size_t end) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (size_t i = begin; i < end; ++i) {
      const Ray& r = rays[i];
      RTCRayHit rh;
      rh.ray.org_x = r.origin.x;
      rh.ray.org_y = r.origin.y;
      rh.ray.org_z = r.origin.z;
      rh.ray.tnear = 0.0f;
      rh.ray.dir_x = r.dir.x;
      rh.ray.dir_y = r.dir.y;
      rh.ray.dir_z = r.dir.z;
      rh.ray.time = 0.0f;
      rh.ray.tfar = r.tmax;
      rh.ray.mask = ~0u;
      rh.ray.id = 0;
      rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &ctx, &rh);
      if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
        out.t[i] = rh.ray.tfar;
        out.prim[i] = rh.hit.primID;
      } else {
        out.t[i] = kInfinity;
        out.prim[i] = ~0u;
      }
    }
  });
}

double trace_ours_shadow(tbb::task_arena& arena, const Scene& scene, const std::vector<Ray>& rays,
                         std::vector<uint8_t>& occluded) {
  const Kernels& k = kernels();
  return run_blocks(arena, rays.size(), [&](size_t begin, size_t end) {
    k.occluded(scene, std::span(rays).subspan(begin, end - begin), occluded.data() + begin);
  });
}

double trace_embree_shadow(tbb::task_arena& arena, RTCScene scene, const std::vector<Ray>& rays,
                           std::vector<uint8_t>& occluded) {
  return run_blocks(arena, rays.size(), [&](size_t begin, size_t end) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (size_t i = begin; i < end; ++i) {
      const Ray& r = rays[i];
      RTCRay ray;
      ray.org_x = r.origin.x;
      ray.org_y = r.origin.y;
      ray.org_z = r.origin.z;
      ray.tnear = 0.0f;
      ray.dir_x = r.dir.x;
      ray.dir_y = r.dir.y;
      ray.dir_z = r.dir.z;
      ray.time = 0.0f;
      ray.tfar = r.tmax;
      ray.mask = ~0u;
      ray.id = 0;
      ray.flags = 0;
      rtcOccluded1(scene, &ctx, &ray);
      occluded[i] = ray.tfar < 0.0f ? 1 : 0;  // tfar = -inf when occluded
    }
  });
}

// Our packets: kPacketRays consecutive rays of a block per call (a row of a
// 16x16 tile of primary rays; the shadow rays of neighbouring hits), the same
// rays per call as Embree's 16-wide packets.
double trace_ours_primary_packets(tbb::task_arena& arena, const Scene& scene,
                                  const std::vector<Ray>& rays, PrimaryResult& out) {
  const Kernels& k = kernels();
  return run_blocks(arena, rays.size(), [&](size_t begin, size_t end) {
    PrimHit hits[kBlock];
    uint8_t found[kBlock];
    k.intersect_packets(scene, std::span(rays).subspan(begin, end - begin), hits, found);
    store_hits(begin, end, hits, found, out);
  });
}

double trace_ours_shadow_packets(tbb::task_arena& arena, const Scene& scene,
                                 const std::vector<Ray>& rays, std::vector<uint8_t>& occluded) {
  const Kernels& k = kernels();
  return run_blocks(arena, rays.size(), [&](size_t begin, size_t end) {
    k.occluded_packets(scene, std::span(rays).subspan(begin, end - begin), occluded.data() + begin);
  });
}

// Embree's packet calls: N consecutive rays of a block per call (N = 8: half a
// row of a 16x16 tile of primary rays, 16: a row; the shadow rays of
// neighbouring hits), lanes past the block's end invalid, with the coherent
// flag, as an Embree user traces primary rays and shadow rays of a tile.
template <class RayHitN, class RayN_, auto kIntersect, auto kOccluded>
struct EmbreePacketCalls {
  using RayHit = RayHitN;
  using RayN = RayN_;
  static constexpr auto intersect = kIntersect;
  static constexpr auto occluded = kOccluded;
};
template <int N>
struct EmbreePacket;
template <>
struct EmbreePacket<8> : EmbreePacketCalls<RTCRayHit8, RTCRay8, &rtcIntersect8, &rtcOccluded8> {};
template <>
struct EmbreePacket<16>
    : EmbreePacketCalls<RTCRayHit16, RTCRay16, &rtcIntersect16, &rtcOccluded16> {};

template <int N, class RayN>
void fill_packet(RayN& p, const std::vector<Ray>& rays, size_t first, size_t end, int* valid) {
  for (int k = 0; k < N; ++k) {
    const size_t i = first + size_t(k);
    const Ray& r = rays[std::min(i, end - 1)];
    valid[k] = i < end ? -1 : 0;
    p.org_x[k] = r.origin.x;
    p.org_y[k] = r.origin.y;
    p.org_z[k] = r.origin.z;
    p.tnear[k] = 0.0f;
    p.dir_x[k] = r.dir.x;
    p.dir_y[k] = r.dir.y;
    p.dir_z[k] = r.dir.z;
    p.time[k] = 0.0f;
    p.tfar[k] = r.tmax;
    p.mask[k] = ~0u;
    p.id[k] = 0;
    p.flags[k] = 0;
  }
}

RTCIntersectContext coherent_context() {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  return ctx;
}

template <int N>
double trace_embree_primary_packets(tbb::task_arena& arena, RTCScene scene,
                                    const std::vector<Ray>& rays, PrimaryResult& out) {
  return run_blocks(arena, rays.size(), [&](size_t begin, size_t end) {
    RTCIntersectContext ctx = coherent_context();
    alignas(64) typename EmbreePacket<N>::RayHit rh;
    alignas(64) int valid[N];
    for (size_t first = begin; first < end; first += N) {
      fill_packet<N>(rh.ray, rays, first, end, valid);
      for (int k = 0; k < N; ++k) {
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
      EmbreePacket<N>::intersect(valid, scene, &ctx, &rh);
      for (int k = 0; k < N && first + size_t(k) < end; ++k) {
        const bool hit = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
        out.t[first + size_t(k)] = hit ? rh.ray.tfar[k] : kInfinity;
        out.prim[first + size_t(k)] = hit ? rh.hit.primID[k] : ~0u;
      }
    }
  });
}

template <int N>
double trace_embree_shadow_packets(tbb::task_arena& arena, RTCScene scene,
                                   const std::vector<Ray>& rays, std::vector<uint8_t>& occluded) {
  return run_blocks(arena, rays.size(), [&](size_t begin, size_t end) {
    RTCIntersectContext ctx = coherent_context();
    alignas(64) typename EmbreePacket<N>::RayN ray;
    alignas(64) int valid[N];
    for (size_t first = begin; first < end; first += N) {
      fill_packet<N>(ray, rays, first, end, valid);
      EmbreePacket<N>::occluded(valid, scene, &ctx, &ray);
      for (int k = 0; k < N && first + size_t(k) < end; ++k)
        occluded[first + size_t(k)] = ray.tfar[k] < 0.0f ? 1 : 0;
    }
  });
}

// ---------------------------------------------------------------------------
// Validation

struct Check {
  std::string mesh, kind;
  int threads = 0;
  size_t rays = 0;
  size_t ours = 0, embree = 0;  // hits (primary) or occluded rays (shadow)
  size_t hit_mismatch = 0;      // one tracer hits / is occluded, the other not
  size_t t_mismatch = 0;        // both hit, relative t difference >= kRelTolerance
  size_t prim_differs = 0;      // both hit, different triangle (ties, edges): information only
  double max_rel = 0.0;         // largest relative t difference among matching hits
  double agree() const {
    return rays ? double(rays - hit_mismatch - t_mismatch) / double(rays) : 1.0;
  }
  bool pass() const { return agree() > kAgreeRequired; }
};

Check compare_primary(const PrimaryResult& a, const PrimaryResult& b) {
  Check c;
  c.kind = "primary";
  c.rays = a.t.size();
  for (size_t i = 0; i < c.rays; ++i) {
    const bool ha = a.t[i] != kInfinity, hb = b.t[i] != kInfinity;
    c.ours += ha;
    c.embree += hb;
    if (ha != hb) {
      c.hit_mismatch++;
      continue;
    }
    if (!ha) continue;
    const double rel = std::abs(double(a.t[i]) - double(b.t[i])) / std::max(double(b.t[i]), 1e-30);
    if (rel >= kRelTolerance)
      c.t_mismatch++;
    else
      c.max_rel = std::max(c.max_rel, rel);
    if (a.prim[i] != b.prim[i]) c.prim_differs++;
  }
  return c;
}

Check compare_shadow(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  Check c;
  c.kind = "shadow";
  c.rays = a.size();
  for (size_t i = 0; i < c.rays; ++i) {
    c.ours += a[i];
    c.embree += b[i];
    c.hit_mismatch += a[i] != b[i];
  }
  return c;
}

// ---------------------------------------------------------------------------
// One mesh

// Every byte Aggregate::memory_bytes() counts after a commit, by what holds
// it (the same terms; test_aggregate's
// APlainRenderHoldsWhatItWalksAndTheToolsBuildTheRestWhenAsked checks the
// sum, part by part), for the 8-wide walk renders use: what a plain render
// walks. Then, as "+ ..." parts, what the tools' first question builds: the
// records with their vertices, made again from the blocks (leaf_records.h),
// the binary tree and its leaf order (bvh_on_demand.h), which the teaching
// views and range queries walk, and the binary node ids of the wide slots,
// which statistics and recording report. Call it before anything asks for
// those.
std::vector<std::pair<std::string, size_t>> memory_parts(const Aggregate& a) {
  const size_t held = a.memory_bytes();
  std::vector<std::pair<std::string, size_t>> parts;
  const BvhWalk* w = a.kind() == AccelKind::Bvh ? &a.structure_as<BvhWalk>() : nullptr;
  if (w) {
    parts.push_back({"wide nodes", w->walk().nodes.size() * sizeof(WideBvhNode)});
    parts.push_back({"triangle blocks", w->triangle_blocks().size() * sizeof(TriangleBlock)});
  }
  parts.push_back({"record ids", a.record_ids().size() * sizeof(uint32_t)});
  if (!a.other_records().empty())
    parts.push_back({"other records", a.other_records().size() * sizeof(PrimRecord)});
  if (!w) parts.push_back({"leaf records", a.records().size() * sizeof(PrimRecord)});
  if (!a.plane_records().empty())
    parts.push_back({"planes", a.plane_records().size() * sizeof(PlaneRecord)});
  size_t counted = 0;
  for (const auto& [name, bytes] : parts) counted += bytes;
  if (counted != held)
    parts.push_back({"other", held - counted});  // a term added to memory_bytes()
  if (w) parts.push_back({"+ leaf records", a.records().size() * sizeof(PrimRecord)});
  parts.push_back({"+ binary nodes", a.bvh().nodes.size() * sizeof(BvhNode)});
  parts.push_back({"+ leaf order", a.bvh().prim_indices.size() * sizeof(uint32_t)});
  if (w) parts.push_back({"+ slot sources", w->slot_sources().size() * sizeof(uint32_t)});
  return parts;
}

struct BuildRow {
  std::string mesh;
  size_t tris = 0;
  // (builder threads, ms): ours limited by tbb::global_control, Embree by its
  // device's "threads=N".
  std::vector<std::pair<int, double>> commit_ms, bvh_ms, embree_ms;
  BvhQuality quality;
  size_t ours_bytes = 0;  ///< Scene::accel().memory_bytes(): nodes, leaf order, records.
  /// Where ours_bytes go, part by part (memory_parts()); they sum to it.
  std::vector<std::pair<std::string, size_t>> ours_parts;
  /// The 8-wide BVH's nodes and triangle blocks (0 for another structure).
  size_t wide_nodes = 0, blocks = 0;
  int64_t embree_bytes = 0;  ///< What Embree's memory monitor counted for the scene.
};

struct TraceRow {
  std::string mesh, kind;
  size_t tris = 0, rays = 0;
  int threads = 0;
  double ours = 0.0, embree = 0.0;  // Mrays/s
  /// Embree's packet calls with the coherent flag on the same rays
  /// (rtcIntersect8/16 or rtcOccluded8/16), Mrays/s; and the rays whose
  /// answer differs from its single-ray call's.
  double embree8 = 0.0, embree16 = 0.0;
  size_t packet_differs = 0;
  /// Our packets (Scene::intersect_packet, occluded_packet) on the same rays,
  /// Mrays/s; and the rays whose answer differs from our single-ray answer
  /// (hit or miss, t, triangle), which must be none.
  double ours_packet = 0.0;
  size_t ours_packet_differs = 0;
};

struct Results {
  std::vector<BuildRow> builds;
  std::vector<TraceRow> traces;
  std::vector<Check> checks;
  std::vector<std::string> notes;
};

void bench_mesh(const std::string& name, const TriangleMesh& mesh, const Options& opt,
                Results& res) {
  const size_t tris = mesh.triangles.size();
  std::fprintf(stderr, "[%s] %zu triangles\n", name.c_str(), tris);

  // --- Our build: the whole commit(), and the BVH builder alone, with the
  // builder limited to N threads.
  BuildRow build;
  build.mesh = name;
  build.tris = tris;
  for (int n : opt.threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n));
    build.commit_ms.emplace_back(n, 1e3 * median_seconds(opt.runs, [&] {
                                      Scene s;
                                      s.meshes.push_back(mesh);
                                      const auto t0 = Clock::now();
                                      s.commit(opt.accel);
                                      return seconds_since(t0);
                                    }));
  }
  {
    std::vector<Bounds3> bounds(tris);
    std::vector<Vec3> centroids(tris);
    for (size_t i = 0; i < tris; ++i) {
      const glm::uvec3& t = mesh.triangles[i];
      Bounds3 b(mesh.positions[t.x]);
      b.extend(mesh.positions[t.y]);
      b.extend(mesh.positions[t.z]);
      bounds[i] = b;
      centroids[i] = b.center();
    }
    for (int n : opt.threads) {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n));
      build.bvh_ms.emplace_back(n, 1e3 * median_seconds(opt.runs, [&] {
                                     Bvh bvh;
                                     const auto t0 = Clock::now();
                                     bvh.build(bounds, centroids, opt.accel.bvh);
                                     return seconds_since(t0);
                                   }));
    }
  }
  for (size_t k = 0; k < opt.threads.size(); ++k)
    std::fprintf(stderr, "[%s] ours, %d thread%s: commit %.1f ms, Bvh::build %.1f ms\n",
                 name.c_str(), opt.threads[k], opt.threads[k] == 1 ? "" : "s",
                 build.commit_ms[k].second, build.bvh_ms[k].second);

  // --- Embree build with its builder limited to N threads. With the TBB tasking
  // system "threads=N" installs a process-wide tbb::global_control while the
  // device lives, so the device is released before any tracing (it would
  // otherwise cap our task_arena too).
  for (int n : opt.threads) {
    RTCDevice dev = new_device("threads=" + std::to_string(n) + ",start_threads=1");
    const double ms = 1e3 * median_seconds(opt.runs, [&] {
                        const auto t0 = Clock::now();
                        RTCScene s = embree_scene(dev, mesh, opt.quality, opt.robust);
                        const double sec = seconds_since(t0);
                        rtcReleaseScene(s);
                        return sec;
                      });
    rtcReleaseDevice(dev);
    build.embree_ms.emplace_back(n, ms);
    std::fprintf(stderr, "[%s] Embree (%s, %d thread%s): %.1f ms\n", name.c_str(),
                 quality_name(opt.quality), n, n == 1 ? "" : "s", ms);
  }

  // --- Scenes used for tracing.
  Scene scene;
  scene.meshes.push_back(mesh);
  scene.commit(opt.accel);
  build.ours_bytes = scene.accel().memory_bytes();
  build.ours_parts = memory_parts(scene.accel());
  if (scene.accel().kind() == AccelKind::Bvh) {
    const BvhWalk& w = scene.accel().structure_as<BvhWalk>();
    build.wide_nodes = w.walk().nodes.size();
    build.blocks = w.triangle_blocks().size();
  }
  build.quality = scene.bvh().quality();

  RTCDevice dev = new_device("");  // default: no thread cap
  rtcSetDeviceMemoryMonitorFunction(dev, embree_memory, nullptr);
  const int64_t embree_before = g_embree_bytes;
  RTCScene escene = embree_scene(dev, mesh, opt.quality, opt.robust);
  build.embree_bytes = g_embree_bytes - embree_before;
  res.builds.push_back(build);

  // --- Rays.
  const Bounds3 box = scene.bounds();
  const Camera cam = framing_camera(box, opt.res);
  const std::vector<Ray> primary = primary_rays(cam, opt.res);
  const ShadowSet shadow = shadow_rays(scene, primary, light_position(box));
  {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "%s: %zu primary rays, %zu hit (%.1f%%); %zu shadow rays (%zu hits face away "
                  "from the light)",
                  name.c_str(), primary.size(), shadow.primary_hits,
                  100.0 * double(shadow.primary_hits) / double(primary.size()), shadow.rays.size(),
                  shadow.facing_away);
    res.notes.push_back(buf);
    std::fprintf(stderr, "[%s] %s\n", name.c_str(), buf + name.size() + 2);
  }

  PrimaryResult ours_p(primary.size()), embree_p(primary.size());
  std::vector<uint8_t> ours_s(shadow.rays.size()), embree_s(shadow.rays.size());
  for (int n : opt.threads) {
    tbb::task_arena arena(n);
    auto mrays = [&](size_t rays, double sec) { return double(rays) / sec * 1e-6; };

    TraceRow p{name, "primary", tris, primary.size(), n, 0.0, 0.0};
    const auto [po, pe] = median_seconds_interleaved(
        opt.runs, [&] { return trace_ours_primary(arena, scene, primary, ours_p); },
        [&] { return trace_embree_primary(arena, escene, primary, embree_p); });
    p.ours = mrays(primary.size(), po);
    p.embree = mrays(primary.size(), pe);
    {
      PrimaryResult packet_p(primary.size());
      p.embree8 = mrays(primary.size(), median_seconds(opt.runs, [&] {
                          return trace_embree_primary_packets<8>(arena, escene, primary, packet_p);
                        }));
      p.embree16 =
          mrays(primary.size(), median_seconds(opt.runs, [&] {
                  return trace_embree_primary_packets<16>(arena, escene, primary, packet_p);
                }));
      for (size_t i = 0; i < primary.size(); ++i)
        p.packet_differs += packet_p.prim[i] != embree_p.prim[i] || packet_p.t[i] != embree_p.t[i];
      p.ours_packet = mrays(primary.size(), median_seconds(opt.runs, [&] {
                              return trace_ours_primary_packets(arena, scene, primary, packet_p);
                            }));
      for (size_t i = 0; i < primary.size(); ++i)
        p.ours_packet_differs += packet_p.prim[i] != ours_p.prim[i] || packet_p.t[i] != ours_p.t[i];
    }
    res.traces.push_back(p);
    std::fprintf(stderr, "[%s] %dT primary: ours %.2f, Embree %.2f Mrays/s\n", name.c_str(), n,
                 p.ours, p.embree);

    TraceRow s{name, "shadow", tris, shadow.rays.size(), n, 0.0, 0.0};
    const auto [so, se] = median_seconds_interleaved(
        opt.runs, [&] { return trace_ours_shadow(arena, scene, shadow.rays, ours_s); },
        [&] { return trace_embree_shadow(arena, escene, shadow.rays, embree_s); });
    s.ours = mrays(shadow.rays.size(), so);
    s.embree = mrays(shadow.rays.size(), se);
    {
      std::vector<uint8_t> packet_s(shadow.rays.size());
      s.embree8 =
          mrays(shadow.rays.size(), median_seconds(opt.runs, [&] {
                  return trace_embree_shadow_packets<8>(arena, escene, shadow.rays, packet_s);
                }));
      s.embree16 =
          mrays(shadow.rays.size(), median_seconds(opt.runs, [&] {
                  return trace_embree_shadow_packets<16>(arena, escene, shadow.rays, packet_s);
                }));
      for (size_t i = 0; i < shadow.rays.size(); ++i)
        s.packet_differs += packet_s[i] != embree_s[i];
      s.ours_packet = mrays(shadow.rays.size(), median_seconds(opt.runs, [&] {
                              return trace_ours_shadow_packets(arena, scene, shadow.rays, packet_s);
                            }));
      for (size_t i = 0; i < shadow.rays.size(); ++i)
        s.ours_packet_differs += packet_s[i] != ours_s[i];
    }
    res.traces.push_back(s);
    std::fprintf(stderr, "[%s] %dT shadow:  ours %.2f, Embree %.2f Mrays/s\n", name.c_str(), n,
                 s.ours, s.embree);

    // The arrays hold the answers of the last timed pass with n threads.
    Check cp = compare_primary(ours_p, embree_p);
    Check cs = compare_shadow(ours_s, embree_s);
    for (Check* c : {&cp, &cs}) {
      c->mesh = name;
      c->threads = n;
      res.checks.push_back(*c);
    }
  }

  rtcReleaseScene(escene);
  rtcReleaseDevice(dev);
}

// ---------------------------------------------------------------------------
// Output

void print_tables(const Results& r, const Options& opt) {
  std::printf(
      "\nBuild (median of %d; Embree quality %s; ours: binned SAH, %d bins, leaves <= %u, "
      "leaf cost %g)\n",
      opt.runs, quality_name(opt.quality), opt.accel.bvh.bins, opt.accel.bvh.max_leaf_size,
      double(opt.accel.bvh.intersection_cost));
  std::printf("%-11s %9s %7s %10s %10s %10s %12s\n", "mesh", "tris", "threads", "commit ms",
              "bvh ms", "Embree ms", "commit/Embree");
  for (const BuildRow& b : r.builds)
    for (size_t k = 0; k < b.commit_ms.size(); ++k) {
      const double embree = k < b.embree_ms.size() ? b.embree_ms[k].second : 0.0;
      std::printf("%-11s %9zu %7d %10.1f %10.1f %10.1f %12.2f\n", b.mesh.c_str(), b.tris,
                  b.commit_ms[k].first, b.commit_ms[k].second, b.bvh_ms[k].second, embree,
                  b.commit_ms[k].second / embree);
    }
  std::printf("%-11s %9s %6s %9s %8s %8s %8s %11s %11s\n", "mesh", "nodes", "depth", "leaf avg",
              "max leaf", "SAH", "SAH 1:1", "ours B/tri", "Embree B/tri");
  for (const BuildRow& b : r.builds)
    std::printf("%-11s %9u %6u %9.2f %8u %8.2f %8.2f %11.1f %11.1f\n", b.mesh.c_str(),
                b.quality.nodes, b.quality.depth, b.quality.mean_leaf_prims,
                b.quality.max_leaf_prims, b.quality.sah_cost, b.quality.sah_cost_1to1,
                double(b.ours_bytes) / double(b.tris), double(b.embree_bytes) / double(b.tris));
  std::printf("Where our bytes go (bytes per triangle)\n%-11s", "mesh");
  if (!r.builds.empty())
    for (const auto& [name, bytes] : r.builds.front().ours_parts)
      std::printf(" %18s", name.c_str());
  std::printf("\n");
  for (const BuildRow& b : r.builds) {
    std::printf("%-11s", b.mesh.c_str());
    for (const auto& [name, bytes] : b.ours_parts)
      std::printf(" %18.1f", double(bytes) / double(b.tris));
    std::printf("\n");
  }
  for (const BuildRow& b : r.builds)
    if (b.wide_nodes > 0)
      std::printf("%-11s %zu wide nodes (%.1f triangles each), %zu triangle blocks (%.2f each)\n",
                  b.mesh.c_str(), b.wide_nodes, double(b.tris) / double(b.wide_nodes), b.blocks,
                  double(b.tris) / double(b.blocks));
  std::printf(
      "(commit = Scene::commit(): validation, bounds, Bvh::build, WideBvh collapse, leaf "
      "blocks;\n bvh = Bvh::build() alone; ours limited to N threads by tbb::global_control;\n "
      "Embree N = rtcNewScene .. rtcCommitScene incl. buffer copy with device \"threads=N\";\n "
      "SAH = the tree's expected cost of a random ray with the build's costs (a primitive test\n "
      "%g of a node visit); SAH 1:1 = the same with equal costs, comparable across cost "
      "settings;\n "
      "B/tri = bytes per triangle: ours every byte the aggregate holds after the commit (wide\n "
      "nodes, the leaves' triangle blocks, each record's id; \"+\" parts below are built when\n "
      "a tool first asks), Embree the net bytes its memory monitor reported while\n "
      "the scene was built)\n",
      double(opt.accel.bvh.intersection_cost / opt.accel.bvh.traversal_cost));

  std::printf(
      "\nTrace throughput (Mrays/s, median of %d after 1 warm-up, ours and Embree passes "
      "alternating; blocks of %zu rays)\n",
      opt.runs, kBlock);
  std::printf("%-11s %7s %-8s %9s %10s %10s %12s\n", "mesh", "threads", "kind", "rays", "ours",
              "Embree", "ours/Embree");
  for (const TraceRow& t : r.traces)
    std::printf("%-11s %7d %-8s %9zu %10.2f %10.2f %12.3f\n", t.mesh.c_str(), t.threads,
                t.kind.c_str(), t.rays, t.ours, t.embree, t.ours / t.embree);
  for (const std::string& n : r.notes) std::printf("  %s\n", n.c_str());

  std::printf(
      "\nPacket calls on the same rays (Mrays/s, median of %d): Embree's with the coherent flag,\n"
      "8 or 16 consecutive rays of a block per call, and ours, %d per call, against the\n"
      "single-ray calls\n",
      opt.runs, kPacketRays);
  std::printf("%-11s %7s %-8s %10s %10s %10s %10s %10s %12s %9s %9s\n", "mesh", "threads", "kind",
              "ours 1", "ours 16", "Embree 1", "Embree 8", "Embree 16", "ours/best", "differ",
              "E differ");
  for (const TraceRow& t : r.traces)
    std::printf("%-11s %7d %-8s %10.2f %10.2f %10.2f %10.2f %10.2f %12.3f %9zu %9zu\n",
                t.mesh.c_str(), t.threads, t.kind.c_str(), t.ours, t.ours_packet, t.embree,
                t.embree8, t.embree16,
                std::max(t.ours, t.ours_packet) / std::max({t.embree, t.embree8, t.embree16}),
                t.ours_packet_differs, t.packet_differs);
  std::printf(
      "(ours/best = our faster call against Embree's fastest; differ = rays whose answer from\n"
      " our packets is not our single-ray answer (must be 0); E differ = the same for Embree's\n"
      " packets against its single-ray call: hit or miss, t and triangle for primary rays)\n");

  std::printf("\nValidation (ours vs Embree; agree = same hit/miss and |dt|/t < %g)\n",
              kRelTolerance);
  std::printf("%-11s %7s %-8s %9s %9s %9s %9s %9s %9s %10s %9s %5s\n", "mesh", "threads", "kind",
              "rays", "ours", "Embree", "hit/miss", "t diff", "prim diff", "agree", "max rel", "");
  for (const Check& c : r.checks)
    std::printf("%-11s %7d %-8s %9zu %9zu %9zu %9zu %9zu %9zu %9.5f%% %9.2e %5s\n", c.mesh.c_str(),
                c.threads, c.kind.c_str(), c.rays, c.ours, c.embree, c.hit_mismatch, c.t_mismatch,
                c.prim_differs, 100.0 * c.agree(), c.max_rel, c.pass() ? "ok" : "FAIL");
  std::printf(
      "(ours/Embree = hits for primary rays, occluded rays for shadow rays; prim diff is "
      "informational)\n");
}

void write_csv(const Results& r, const std::string& path) {
  std::ofstream f(path);
  if (!f) {
    std::fprintf(stderr, "bench_trace: cannot write %s\n", path.c_str());
    return;
  }
  f << "mesh,triangles,metric,threads,rays,ours,embree,ours_over_embree,unit\n";
  for (const BuildRow& b : r.builds) {
    for (size_t k = 0; k < b.commit_ms.size(); ++k) {
      const auto [n, commit] = b.commit_ms[k];
      f << b.mesh << ',' << b.tris << ",build_commit," << n << ",0," << commit << ",,,ms\n";
      f << b.mesh << ',' << b.tris << ",build_bvh," << n << ",0," << b.bvh_ms[k].second
        << ",,,ms\n";
      if (k < b.embree_ms.size()) {
        const double ms = b.embree_ms[k].second;
        // ratio as speed (Embree time / our commit time): > 1 means ours is faster.
        f << b.mesh << ',' << b.tris << ",build," << n << ",0," << commit << ',' << ms << ','
          << ms / commit << ",ms\n";
      }
    }
    f << b.mesh << ',' << b.tris << ",bytes_per_triangle,0,0,"
      << double(b.ours_bytes) / double(b.tris) << ',' << double(b.embree_bytes) / double(b.tris)
      << ',' << double(b.ours_bytes) / double(b.embree_bytes) << ",B\n";
    f << b.mesh << ',' << b.tris << ",bvh_nodes,1,0," << b.quality.nodes << ",,,count\n";
    f << b.mesh << ',' << b.tris << ",bvh_leaves,1,0," << b.quality.leaves << ",,,count\n";
    f << b.mesh << ',' << b.tris << ",bvh_depth,1,0," << b.quality.depth << ",,,count\n";
    f << b.mesh << ',' << b.tris << ",bvh_sah_cost,1,0," << b.quality.sah_cost << ",,,cost\n";
    f << b.mesh << ',' << b.tris << ",bvh_sah_cost_1to1,1,0," << b.quality.sah_cost_1to1
      << ",,,cost\n";
  }
  for (const TraceRow& t : r.traces)
    f << t.mesh << ',' << t.tris << ',' << t.kind << ',' << t.threads << ',' << t.rays << ','
      << t.ours << ',' << t.embree << ',' << t.ours / t.embree << ",Mrays/s\n";
  for (const TraceRow& t : r.traces)
    for (const auto& [calls, rate] : {std::pair{"8", t.embree8}, std::pair{"16", t.embree16}})
      f << t.mesh << ',' << t.tris << ',' << t.kind << "_embree_packet" << calls << ',' << t.threads
        << ',' << t.rays << ',' << t.ours << ',' << rate << ',' << t.ours / rate << ",Mrays/s\n";
  for (const TraceRow& t : r.traces)
    f << t.mesh << ',' << t.tris << ',' << t.kind << "_packet16," << t.threads << ',' << t.rays
      << ',' << t.ours_packet << ',' << t.embree16 << ',' << t.ours_packet / t.embree16
      << ",Mrays/s\n";
  for (const Check& c : r.checks)
    f << c.mesh << ",," << c.kind << "_agree," << c.threads << ',' << c.rays << ',' << c.ours << ','
      << c.embree << ',' << c.agree() << ",fraction\n";
  std::fprintf(stderr, "wrote %s\n", path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse_options(argc, argv);

  if (!std::filesystem::exists(opt.mesh)) {
    std::printf(
        "bench_trace: mesh '%s' not found; skipping (install glmark2-data or pass "
        "--mesh PATH)\n",
        opt.mesh.c_str());
    return 0;
  }

  TriangleMesh base;
  try {
    base = rayscope_vtkio::read_mesh_file(opt.mesh);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_trace: %s\n", e.what());
    return 2;
  }
  const std::string base_name = std::filesystem::path(opt.mesh).stem().string();
  std::vector<std::pair<std::string, TriangleMesh>> meshes;
  meshes.emplace_back(base_name, base);
  if (opt.big) meshes.emplace_back(base_name + "/sub2", subdivide(subdivide(base)));

  {
    RTCDevice dev = new_device("");
    std::printf("RayScope bench_trace\n");
    std::printf("  CPU       %s (%u hardware threads)\n", cpu_model().c_str(),
                std::thread::hardware_concurrency());
    std::printf("  compiler  %s, %s%s\n", compiler().c_str(), RAYSCOPE_BENCH_BUILD_TYPE,
                RAYSCOPE_BENCH_NATIVE ? ", -march=native" : ", portable (every x86-64)");
    std::printf("  kernels   %s (this CPU runs up to %s)\n",
                std::string(isa_name(kernels().isa)).c_str(),
                std::string(isa_name(best_cpu_isa())).c_str());
    std::printf(
        "  Embree    %s (tasking: %s), build quality %s, scene flags %s, rtcIntersect1 / "
        "rtcOccluded1\n",
        RTC_VERSION_STRING,
        tasking_name(rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_TASKING_SYSTEM)),
        quality_name(opt.quality), opt.robust ? "ROBUST" : "NONE");
    rtcReleaseDevice(dev);
    std::printf("  load avg  %s (at start; other processes skew the timings)\n",
                load_average().c_str());
    std::printf("  mesh      %s\n", opt.mesh.c_str());
    for (const auto& [name, m] : meshes)
      std::printf("  %-9s %zu triangles, %zu vertices\n", name.c_str(), m.triangles.size(),
                  m.positions.size());
    std::printf(
        "  rays      %dx%d primary (pixel centres, 16x16 tiles), shadow rays from our "
        "hits; runs %d\n",
        opt.res, opt.res, opt.runs);
    std::printf(
        "  queries   ours: Scene::intersect(ray, PrimHit&) (t, barycentrics, prim id; no\n"
        "            shading data, like rtcIntersect1's t, u, v, Ng, ids) / Scene::occluded\n");
    std::fflush(stdout);
  }

  Results results;
  for (const auto& [name, m] : meshes) bench_mesh(name, m, opt, results);

  print_tables(results, opt);
  std::printf("\nload average at the end: %s\n", load_average().c_str());
  if (!opt.csv.empty()) write_csv(results, opt.csv);

  bool ok = true;
  for (const Check& c : results.checks) ok = ok && c.pass();
  if (!ok) {
    std::printf("\nVALIDATION FAILED: ours and Embree disagree on more than %.1f%% of rays\n",
                100.0 * (1.0 - kAgreeRequired));
    return 1;
  }
  return 0;
}
