// Numerical stress tests: the tracer under conditions that break
// naive float code.
//
//  1. Watertightness at scale: a closed icosphere of 1,310,720 triangles
//     centred at (1e6, 1e6, 1e6); 1e6 random rays from interior points and rays
//     aimed exactly at every vertex and every edge midpoint, through Scene +
//     BVH, never escape.
//  2. Invalid and degenerate input: non-finite vertex coordinates, normals and
//     colors, zero-area triangles, duplicate (unwelded) vertices, rays with
//     NaN / infinite / zero components, grazing and tangent rays, the default
//     scene scaled by 1e-5 and 1e5: no crash, no NaN pixel, and what commit()
//     had to work around is reported in SceneSummary::warnings.
//  3. Translation invariance: the default scene moved far from the origin
//     renders the image it renders at the origin, within a stated PSNR.
//  4. Total internal reflection and nested dielectrics at and around the
//     critical angle: no NaN, and no energy is created (returned radiance and
//     ray-tree weights stay within what the scene can give).
//
// Run time: ~18 s in Release on 2 cores when ctest runs each case in its own
// process (the 1.3M-triangle mesh and its BVH take ~2 s to build, per case).
// The suite also runs in sanitizer and unoptimised builds, where tracing is
// 10-50x slower: there the ray counts (and, below a quarter, the big mesh's
// subdivision level: 7, 327,680 triangles) are scaled by stress_scale():
// RAYSCOPE_STRESS_SCALE from the environment if set (in (0, 1], e.g. 0.1),
// else 0.1 under AddressSanitizer/ThreadSanitizer or without optimisation, 1
// otherwise (measured with ASan+UBSan at -O1: ~17 s for the whole suite).
// Every check stays the same; only how many cases are tried changes.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "image_compare.h"
#include "rayscope/image.h"
#include "rayscope/render.h"
#include "rayscope/replay.h"
#include "rayscope/scene.h"
#include "rayscope/shapes.h"
#include "test_util.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::pixels_differing;
using rstest::psnr;
using rstest::Rng;
using rstest::stress_scale;
using rstest::to_d;
using rstest::to_f;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

size_t scaled(size_t n) {
  return rstest::stress_scaled(n);
}

bool finite_color(const Color& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
}

size_t count_nonfinite(const Framebuffer& fb) {
  return size_t(std::count_if(fb.color.begin(), fb.color.end(),
                              [](const Color& c) { return !finite_color(c); }));
}

bool any_warning_contains(const SceneSummary& s, const std::string& what) {
  for (const std::string& w : s.warnings)
    if (w.find(what) != std::string::npos) return true;
  return false;
}

// ===========================================================================
// 1. Watertightness of a 1.3M-triangle mesh far from the origin
// ===========================================================================
//
// Icosphere level 8 (20 * 4^8 = 1,310,720 triangles, 655,362 vertices,
// 1,966,080 edges), radius 1e4, centred at (1e6, 1e6, 1e6). Coordinates lie in
// [0.99e6, 1.01e6] where the float spacing is 0.0625; edges are ~41 long, ~650
// ulps: every triangle is resolved, and the vertex rounding (<= 0.031 per
// axis) leaves the mesh closed (vertices are shared by index) and convex to
// within rounding.
//
// Rays aimed "exactly" at a vertex v from an interior point o: o and v are
// floats within a factor 2 of each other in every component, so d = v - o is
// exact (Sterbenz) and o + 1 * d = v in real arithmetic: the ray passes through
// the vertex shared by 5 or 6 triangles. Edge midpoints are 0.5f * (a + b) in
// float, on the shared edge to within 0.0625 per axis (the rounding of a + b,
// near 2e6), 1/650 of an edge.
class WatertightMillion : public ::testing::Test {
 protected:
  static constexpr double kCenter = 1e6;
  static constexpr float kRadius = 1e4f;

  static void SetUpTestSuite() {
    // Below a quarter of the full counts (sanitizer builds) level 7 (327,680
    // triangles) keeps the mesh build and BVH within the time budget.
    level_ = stress_scale() >= 0.25 ? 8 : 7;
    mesh_ = new TriangleMesh(make_icosphere(Vec3(float(kCenter)), kRadius, level_));
    scene_ = new Scene;
    scene_->meshes = {*mesh_};
    scene_->commit();
  }
  static void TearDownTestSuite() {
    delete scene_;
    delete mesh_;
    scene_ = nullptr;
    mesh_ = nullptr;
  }

  // Traces o + t d through the scene; returns an error message or "". The hit
  // must exist for intersect() and occluded(), and lie on the mesh: beyond
  // the sphere by at most the vertices' distance from it (their rounding,
  // <= sqrt(3) * 0.032; twice that is allowed) plus the hit point's own error
  // bound, and inside it by at most the sagitta of the flat triangles (below
  // 3e-6 r at level 8: circumradius ~0.0024 r, sagitta R^2 / 2r; 2e-5 r is
  // allowed) plus the same slack.
  static std::string trace(const Vec3& o, const Vec3& d) {
    Ray ray{o, d, kInfinity};
    SurfaceHit hit;
    bool found = scene_->intersect(ray, hit);
    bool blocked = scene_->occluded(ray);
    char buf[256];
    if (!found || !blocked) {
      std::snprintf(buf, sizeof buf, "escaped (intersect %d occluded %d) o=(%a,%a,%a) d=(%a,%a,%a)",
                    int(found), int(blocked), double(o.x), double(o.y), double(o.z), double(d.x),
                    double(d.y), double(d.z));
      return buf;
    }
    const double r = kRadius;
    double dist = glm::length(to_d(hit.p) - DVec3(float(kCenter)));
    double slack = std::sqrt(3.0) * 0.0625 + glm::length(to_d(hit.p_error));
    if (!(hit.t > 0.0f && dist <= r + slack && dist >= r * (1.0 - 2e-5) - slack)) {
      std::snprintf(buf, sizeof buf, "hit off the mesh: distance %.9g from the center, t=%g", dist,
                    double(hit.t));
      return buf;
    }
    return "";
  }

  // Runs n cases in parallel; case i is made by make(i, rng) with a generator
  // seeded per chunk of 4096 cases, so the cases do not depend on the thread
  // schedule. Returns the failure count and keeps the first messages.
  template <class Make>
  static size_t run_parallel(size_t n, uint32_t seed, Make&& make,
                             std::vector<std::string>& messages) {
    constexpr size_t kChunk = 4096;
    std::atomic<size_t> failures{0};
    std::mutex mu;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, (n + kChunk - 1) / kChunk, 1),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t c = r.begin(); c != r.end(); ++c) {
                          Rng rng(seed + uint32_t(c) * 7919u);
                          for (size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) {
                            Vec3 o, d;
                            make(i, rng, o, d);
                            std::string e = trace(o, d);
                            if (!e.empty()) {
                              ++failures;
                              std::lock_guard<std::mutex> lock(mu);
                              if (messages.size() < 5) messages.push_back(e);
                            }
                          }
                        }
                      });
    return failures;
  }

  static Vec3 interior_point(Rng& rng) {
    // Within 0.98 r of the center: well inside the inscribed radius.
    return to_f(DVec3(kCenter) + 0.98 * double(kRadius) * rng.in_unit_ball());
  }

  static int level_;
  static TriangleMesh* mesh_;
  static Scene* scene_;
};
int WatertightMillion::level_ = 8;
TriangleMesh* WatertightMillion::mesh_ = nullptr;
Scene* WatertightMillion::scene_ = nullptr;

TEST_F(WatertightMillion, MillionRandomRaysFromInsideNeverEscape) {
  // The mesh is what it should be: big, far from the origin, all used.
  ASSERT_EQ(mesh_->triangles.size(), size_t(20) << (2 * level_));
  if (stress_scale() >= 0.25) {
    ASSERT_GT(mesh_->triangles.size(), 1000000u);
  }
  ASSERT_EQ(scene_->summary().triangles, mesh_->triangles.size());
  ASSERT_TRUE(scene_->summary().walks_structure);
  ASSERT_TRUE(scene_->summary().warnings.empty());
  for (const Vec3& p : mesh_->positions) {
    ASSERT_GE(std::min({p.x, p.y, p.z}), 0.98e6f);
    ASSERT_LE(std::max({p.x, p.y, p.z}), 1.02e6f);
  }

  const size_t n = scaled(1000000);
  std::vector<std::string> msg;
  size_t fails = run_parallel(
      n, 4242u,
      [](size_t, Rng& rng, Vec3& o, Vec3& d) {
        o = interior_point(rng);
        d = to_f(rng.unit_vector() * rng.log_uniform(1e-3, 1e3));
      },
      msg);
  std::printf("%zu random interior rays, %zu failed\n", n, fails);
  EXPECT_EQ(fails, 0u);
  for (const std::string& m : msg) ADD_FAILURE() << m;
}

TEST_F(WatertightMillion, RaysAtEveryVertexAndEdgeMidpointNeverMiss) {
  // Targets: every vertex, then every edge's midpoint (each edge once). With a
  // stress scale below 1, an evenly spaced subset.
  std::vector<Vec3> targets = mesh_->positions;
  for (const glm::uvec3& t : mesh_->triangles)
    for (int e = 0; e < 3; ++e) {
      uint32_t a = t[e], b = t[(e + 1) % 3];
      if (a < b) targets.push_back(0.5f * (mesh_->positions[a] + mesh_->positions[b]));
    }
  ASSERT_EQ(targets.size(), mesh_->positions.size() + mesh_->triangles.size() * 3 / 2);
  const size_t stride = rstest::stress_stride();
  const size_t n = (targets.size() + stride - 1) / stride;
  std::vector<std::string> msg;
  size_t fails = run_parallel(
      n, 777u,
      [&](size_t i, Rng& rng, Vec3& o, Vec3& d) {
        const Vec3& v = targets[i * stride];
        o = interior_point(rng);
        d = v - o;
      },
      msg);
  // The same from the center: there v - center is exact as well.
  size_t fails_c = run_parallel(
      n, 778u,
      [&](size_t i, Rng&, Vec3& o, Vec3& d) {
        o = Vec3(float(kCenter));
        d = targets[i * stride] - o;
      },
      msg);
  std::printf("%zu vertex/edge-midpoint targets, %zu + %zu rays failed\n", n, fails, fails_c);
  EXPECT_EQ(fails, 0u);
  EXPECT_EQ(fails_c, 0u);
  for (const std::string& m : msg) ADD_FAILURE() << m;
}

// ===========================================================================
// Helpers for rendered scenes
// ===========================================================================

// The scene moved by p -> scale * p + offset (positions rounded once from
// double), with everything that has a length scaled along: sphere radii,
// checker size, parallel scale, point-light attenuation (linear / scale,
// quadratic / scale^2, so that the light reaching a point is unchanged).
// With `local_origin`, as the scene parser does it: the scene's origin is the
// moved camera's look_at and positions are rounded relative to it
// (Scene::origin); otherwise the origin is the world's.
Scene transformed(const Scene& base, double scale, const DVec3& offset, bool local_origin = false) {
  Scene s = base;
  s.origin = local_origin ? to_d(base.camera.look_at) * scale + offset : DVec3(0.0);
  auto P = [&](const Vec3& p) { return to_f(to_d(p) * scale + offset - s.origin); };
  s.camera.eye = P(s.camera.eye);
  s.camera.look_at = P(s.camera.look_at);
  s.camera.parallel_scale = rstest::round_f(double(s.camera.parallel_scale) * scale);
  for (Light& l : s.lights) {
    l.position = P(l.position);
    l.attenuation.y = rstest::round_f(double(l.attenuation.y) / scale);
    l.attenuation.z = rstest::round_f(double(l.attenuation.z) / (scale * scale));
  }
  for (Sphere& sp : s.spheres) {
    sp.center = P(sp.center);
    sp.radius = rstest::round_f(double(sp.radius) * scale);
  }
  for (Plane& pl : s.planes) pl.point = P(pl.point);
  for (TriangleMesh& m : s.meshes)
    for (Vec3& p : m.positions) p = P(p);
  for (Material& m : s.materials) m.checker_size = rstest::round_f(double(m.checker_size) * scale);
  return s;
}

Framebuffer render_scene(Scene scene, int width, int height, int spp, int max_depth = 5,
                         float min_contribution = 1e-3f, RayCounters* counters = nullptr) {
  scene.commit();
  RenderSettings rs;
  rs.width = width;
  rs.height = height;
  rs.samples = spp;
  rs.max_depth = max_depth;
  rs.min_contribution = min_contribution;
  return render(scene, rs, counters);
}

bool same_colors(const Framebuffer& a, const Framebuffer& b) {
  if (a.color.size() != b.color.size()) return false;
  for (size_t i = 0; i < a.color.size(); ++i)
    if (a.color[i] != b.color[i]) return false;
  return true;
}

// A mesh in front of a camera on +z, lit by a point and a directional light,
// over a floor plane.
Scene mesh_scene(TriangleMesh mesh) {
  Scene s;
  s.camera.eye = Vec3(0.3f, 1.2f, 4.0f);
  s.camera.look_at = Vec3(0.0f);
  s.background = Color(0.2f, 0.3f, 0.5f);
  Material m;
  m.name = "plastic";
  m.specular = 0.5f;
  Material floor;
  floor.name = "floor";
  floor.checker = true;
  floor.reflectivity = 0.2f;
  s.materials = {m, floor};
  mesh.material = 0;
  s.meshes = {std::move(mesh)};
  s.planes = {Plane{"floor", Vec3(0.0f, -1.5f, 0.0f), Vec3(0.0f, 1.0f, 0.0f), 1}};
  Light key;
  key.position = Vec3(-3.0f, 5.0f, 4.0f);
  Light fill;
  fill.type = Light::Type::Directional;
  fill.direction = Vec3(0.5f, -1.0f, -0.4f);
  fill.intensity = 0.4f;
  s.lights = {key, fill};
  return s;
}

// ===========================================================================
// 2. Invalid and degenerate input
// ===========================================================================

TEST(InvalidInput, NonFiniteVerticesAreSkippedAndReported) {
  TriangleMesh m = make_icosphere(Vec3(0.0f), 1.0f, 3);
  m.name = "broken";
  const std::vector<uint32_t> bad = {5, 17, 33, 200};
  m.positions[bad[0]].x = kNaN;
  m.positions[bad[1]].y = kInfinity;
  m.positions[bad[2]].z = -kInfinity;
  m.positions[bad[3]] = Vec3(kNaN);
  std::vector<bool> skipped(m.triangles.size(), false);
  size_t n_skipped = 0;
  for (size_t i = 0; i < m.triangles.size(); ++i)
    for (uint32_t v : bad)
      if (m.triangles[i].x == v || m.triangles[i].y == v || m.triangles[i].z == v) {
        if (!skipped[i]) ++n_skipped;
        skipped[i] = true;
      }
  ASSERT_GT(n_skipped, 12u);

  Scene s = mesh_scene(m);
  s.commit();
  EXPECT_EQ(s.summary().skipped_triangles, n_skipped);
  EXPECT_EQ(s.summary().triangles, m.triangles.size() - n_skipped);
  ASSERT_EQ(s.summary().warnings.size(), 1u);
  EXPECT_EQ(s.summary().warnings[0], "mesh 'broken': " + std::to_string(n_skipped) +
                                         " triangles with non-finite vertex coordinates skipped");

  // Random rays: every hit is finite, on a kept triangle or the floor.
  Rng rng(31);
  const Bounds3 world(Vec3(-2.0f), Vec3(2.0f));
  for (int i = 0; i < 20000; ++i) {
    Ray ray = rstest::random_ray(rng, world, {});
    SurfaceHit h;
    if (!s.intersect(ray, h)) continue;
    ASSERT_TRUE(std::isfinite(h.t) && h.t > 0.0f && all_finite(h.p) && all_finite(h.ng) &&
                all_finite(h.ns));
    if (h.object == 0) {
      ASSERT_FALSE(skipped[h.prim]) << "hit a skipped triangle";
    }
  }
  Framebuffer fb = render_scene(s, 64, 48, 2);
  EXPECT_EQ(count_nonfinite(fb), 0u);
}

TEST(InvalidInput, AMeshWithNoFiniteTriangleIsAnError) {
  // Every triangle has a non-finite corner (though some points are finite):
  // nothing of the mesh could be drawn, and a blank picture is not an answer.
  // commit() refuses it as every front end refuses a mesh without triangles.
  TriangleMesh m = make_icosphere(Vec3(0.0f), 1.0f, 1);
  m.name = "gone";
  for (const glm::uvec3& t : m.triangles) m.positions[t.x] = Vec3(kNaN, 0.0f, kInfinity);
  ASSERT_EQ(m.nonfinite_triangles(), m.triangles.size());
  Scene s = mesh_scene(m);
  try {
    s.commit();
    FAIL() << "a mesh whose every triangle is non-finite was committed";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "mesh 'gone': all " + std::to_string(m.triangles.size()) +
                  " triangles have non-finite (NaN or infinite) vertex coordinates");
  }
  // One finite triangle left: committed, the rest skipped with the warning.
  const uint32_t first = uint32_t(m.positions.size());
  for (const Vec3& p : {Vec3(0.0f), Vec3(1.0f, 0.0f, 0.0f), Vec3(0.0f, 1.0f, 0.0f)}) {
    m.positions.push_back(p);
    if (!m.normals.empty()) m.normals.push_back(Vec3(0.0f, 0.0f, 1.0f));
  }
  m.triangles[0] = glm::uvec3(first, first + 1, first + 2);
  Scene kept = mesh_scene(m);
  kept.commit();
  EXPECT_EQ(kept.summary().skipped_triangles, m.nonfinite_triangles());
}

TEST(InvalidInput, NonFiniteNormalsAndColorsFallBackAndAreReported) {
  // The torus has per-vertex normals and colors. Where they are not finite,
  // the geometric normal and the material color are used: with every normal
  // NaN the image is exactly the one without normals, with every color
  // infinite exactly the one without colors.
  const TriangleMesh torus = make_torus(Vec3(0.0f), 0.9f, 0.35f, 32, 16);
  auto image = [](const TriangleMesh& m) { return render_scene(mesh_scene(m), 64, 48, 2); };

  TriangleMesh nan_normals = torus, no_normals = torus;
  for (Vec3& n : nan_normals.normals) n = Vec3(kNaN, 0.0f, 1.0f);
  no_normals.normals.clear();
  Framebuffer a = image(nan_normals), b = image(no_normals), smooth = image(torus);
  EXPECT_EQ(count_nonfinite(a), 0u);
  EXPECT_TRUE(same_colors(a, b));
  EXPECT_FALSE(same_colors(a, smooth));  // the normals do matter where they are valid

  TriangleMesh inf_colors = torus, no_colors = torus;
  for (Color& c : inf_colors.colors) c = Color(kInfinity, 0.5f, 0.5f);
  no_colors.colors.clear();
  a = image(inf_colors);
  b = image(no_colors);
  EXPECT_EQ(count_nonfinite(a), 0u);
  EXPECT_TRUE(same_colors(a, b));

  // A few bad normals and colors among good ones: reported with counts.
  TriangleMesh some = torus;
  some.name = "torus";
  some.normals[3] = Vec3(kInfinity, 0.0f, 0.0f);
  some.normals[40] = Vec3(0.0f, -kInfinity, kNaN);
  some.normals[41] = Vec3(kNaN);
  some.colors[7] = Color(kNaN);
  Scene s = mesh_scene(some);
  s.commit();
  EXPECT_EQ(s.summary().nonfinite_normals, 3u);
  EXPECT_EQ(s.summary().nonfinite_colors, 1u);
  EXPECT_TRUE(any_warning_contains(s.summary(), "mesh 'torus': 3 vertex normals are not finite"));
  EXPECT_TRUE(any_warning_contains(s.summary(), "mesh 'torus': 1 vertex colors are not finite"));
  EXPECT_EQ(count_nonfinite(image(some)), 0u);
}

TEST(InvalidInput, ZeroAreaTrianglesAndDuplicateVerticesKeepTheMeshClosed) {
  // An unwelded icosphere: every triangle has its own copies of its vertices
  // (duplicate positions, as in STL files). Shared edges then exist only as
  // bit-identical coordinates, which is all the watertight test looks at.
  // Added: zero-area triangles inside it, which must never be hit: a repeated
  // index, three identical points, and exactly collinear points (coordinates
  // k * e with e a short binary fraction, so every point is exact), one of
  // them along the x axis through the center.
  const Vec3 center(0.25f, -0.125f, 0.5f);
  const TriangleMesh ico = make_icosphere(center, 1.0f, 3);
  TriangleMesh m;
  m.name = "unwelded";
  for (const glm::uvec3& t : ico.triangles) {
    uint32_t b = uint32_t(m.positions.size());
    for (int k = 0; k < 3; ++k) m.positions.push_back(ico.positions[t[k]]);
    m.triangles.emplace_back(b, b + 1, b + 2);
  }
  const size_t closed = m.triangles.size();
  auto add = [&](Vec3 a, Vec3 b, Vec3 c) {
    uint32_t i = uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c});
    m.triangles.emplace_back(i, i + 1, i + 2);
  };
  m.triangles.emplace_back(0, 0, 1);  // repeated index
  m.triangles.emplace_back(5, 7, 5);
  add(center, center, center);  // one point
  const Vec3 e(0.25f, 0.5f, -0.125f);
  add(center - e, center, center + e);  // collinear
  add(center + e, center - e, center + 0.5f * e);
  add(center - Vec3(0.75f, 0.0f, 0.0f), center, center + Vec3(0.75f, 0.0f, 0.0f));
  const size_t degenerate = m.triangles.size() - closed;

  Scene s;
  s.meshes = {m};
  s.commit();
  EXPECT_EQ(s.summary().degenerate_triangles, degenerate);
  EXPECT_EQ(s.summary().triangles, m.triangles.size());
  EXPECT_TRUE(s.summary().warnings.empty());  // legal input

  Rng rng(77);
  size_t escaped = 0, degenerate_hits = 0, rays = 0;
  auto trace = [&](const Vec3& o, const Vec3& d) {
    Ray ray{o, d, kInfinity};
    SurfaceHit h;
    ++rays;
    if (!s.intersect(ray, h) || !s.occluded(ray))
      ++escaped;
    else if (h.prim >= closed)
      ++degenerate_hits;
  };
  for (int i = 0; i < 50000; ++i)
    trace(to_f(to_d(center) + 0.9 * rng.in_unit_ball()), to_f(rng.unit_vector()));
  // Rays through the points of the zero-area triangles, from all around.
  for (size_t t = closed; t < m.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = m.positions[m.triangles[t][k]];
      for (int j = 0; j < 200; ++j) {
        Vec3 o = to_f(to_d(center) + 0.9 * rng.in_unit_ball());
        if (o != p) trace(o, p - o);
      }
    }
  // Rays lying in the plane of the axis-aligned zero-area triangle.
  for (int j = 0; j < 2000; ++j) {
    Vec3 o = center + Vec3(float(rng.uniform(-0.5, 0.5)), 0.0f, 0.0f);
    DVec3 u = rng.unit_vector();
    u.y = 0.0;
    if (u == DVec3(0.0)) continue;
    trace(o, to_f(u));
  }
  std::printf("%zu rays, %zu escaped, %zu hit a zero-area triangle\n", rays, escaped,
              degenerate_hits);
  EXPECT_EQ(escaped, 0u);
  EXPECT_EQ(degenerate_hits, 0u);
}

TEST(InvalidInput, NonFiniteSpheresPlanesLightsAndCameraAreErrors) {
  // What cannot be worked around is an error naming the object (commit()) or
  // the camera (render()), never a silent NaN image.
  auto commit_error = [](Scene s) -> std::string {
    try {
      s.commit();
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  Scene s = make_default_scene();
  s.spheres[0].center.y = kNaN;
  EXPECT_NE(commit_error(s).find("sphere 'mirror sphere'"), std::string::npos);
  s = make_default_scene();
  s.spheres[1].radius = kInfinity;
  EXPECT_NE(commit_error(s).find("sphere 'glass sphere'"), std::string::npos);
  s = make_default_scene();
  s.planes[0].normal = Vec3(0.0f, kNaN, 0.0f);
  EXPECT_NE(commit_error(s).find("plane 'floor'"), std::string::npos);
  s = make_default_scene();
  s.lights[0].position.x = -kInfinity;
  EXPECT_NE(commit_error(s).find("light 'key'"), std::string::npos);
  s = make_default_scene();
  s.camera.eye.z = kNaN;
  EXPECT_THROW(render_scene(s, 8, 8, 1), std::invalid_argument);
}

TEST(InvalidInput, RaysWithNaNInfiniteOrZeroComponentsNeverHit) {
  // Origins and directions with NaN, +-inf or zero components, and NaN tmax:
  // such a ray has no closest hit. intersect() and occluded() say so (no crash,
  // no hit with a NaN distance), and the integrator returns the background.
  Scene s = make_default_scene();
  s.commit();
  ASSERT_TRUE(s.summary().walks_structure);
  const Vec3 good_o(0.3f, 1.0f, 6.0f), good_d(-0.05f, -0.1f, -1.0f);
  std::vector<Vec3> origins = {good_o}, dirs = {good_d, Vec3(0.0f), -Vec3(0.0f)};
  for (float bad : {kNaN, kInfinity, -kInfinity})
    for (int a = 0; a < 3; ++a) {
      Vec3 o = good_o, d = good_d;
      o[a] = bad;
      d[a] = bad;
      origins.push_back(o);
      dirs.push_back(d);
    }
  origins.push_back(Vec3(kNaN));
  dirs.push_back(Vec3(kNaN));
  dirs.push_back(Vec3(kInfinity, 0.0f, 0.0f));

  RenderSettings rs;
  RayCounters counters;
  NullRecorder rec;
  WhittedIntegrator<NullRecorder> integrator(s, rs, counters, rec);
  size_t cases = 0;
  for (const Vec3& o : origins)
    for (const Vec3& d : dirs)
      for (float tmax : {kInfinity, kNaN}) {
        const bool valid = all_finite(o) && all_finite(d) && d != Vec3(0.0f) && !std::isnan(tmax);
        if (valid) continue;
        ++cases;
        Ray ray{o, d, tmax};
        SurfaceHit h;
        PrimHit ph;
        EXPECT_FALSE(s.intersect(ray, h))
            << "o=" << o.x << "," << o.y << "," << o.z << " d=" << d.x << "," << d.y << "," << d.z
            << " tmax=" << tmax << ": hit at t=" << h.t;
        EXPECT_FALSE(s.intersect(ray, ph));
        EXPECT_FALSE(s.occluded(ray));
        Color c = integrator.trace(ray, RayKind::Primary, 0, Color(1.0f), -1);
        EXPECT_EQ(c, s.background);
      }
  EXPECT_GT(cases, 100u);
  // The valid ray does hit (the mirror sphere): the cases above are not
  // vacuous.
  SurfaceHit h;
  EXPECT_TRUE(s.intersect(Ray{good_o, good_d, kInfinity}, h));
}

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

// ===========================================================================
// 2b. Tiny and huge scene scales
// ===========================================================================
//
// The default scene scaled about the origin by 1e-5 and 1e5 (camera, lights,
// radii and checker size included) is the same scene in other units. Nothing
// in the tracer has an absolute epsilon, so the image must match the unit-scale
// render: positions differ from exactly scaled ones only by one rounding
// (relative 6e-8), which moves a handful of silhouette and checker-edge
// samples. Measured (160x120, 2x2 samples): PSNR 49.5 dB at both 1e-5 and
// 1e5, 53 of 19200 pixels off by more than 1/255. Required: 45 dB.
TEST(Scale, DefaultSceneAtOneHundredThousandthAndHundredThousandfold) {
  const Scene base = make_default_scene();
  const Framebuffer ref = render_scene(base, 160, 120, 2);
  for (double scale : {1e-5, 1e5}) {
    Framebuffer fb = render_scene(transformed(base, scale, DVec3(0.0)), 160, 120, 2);
    EXPECT_EQ(count_nonfinite(fb), 0u);
    double p = psnr(ref, fb);
    std::printf("scale %g: PSNR %.2f dB, %zu of %zu pixels differ by more than 1/255\n", scale, p,
                pixels_differing(ref, fb), fb.color.size());
    EXPECT_GE(p, 45.0) << "scale " << scale;
  }
}

// ===========================================================================
// 3. Translation invariance
// ===========================================================================
//
// The default scene moved by (D, D, D) with its camera and lights, against the
// same scene at the origin, for D up to 1e7 (geospatial data: UTM, ECEF).
//  - "local origin": as the scene parser and the VTK module build it, with
//    positions kept in double until they are made relative to the scene's
//    origin (the moved look_at) and rounded to float once. The tracer then sees
//    the scene at the origin, up to one rounding of coordinates that differ
//    from the unmoved ones by look_at (exact in double). Measured (160x120,
//    2x2 samples): 71.9 dB at 1e5, 1e6 and 1e7 alike (5 pixels off by more
//    than 1/255, at silhouettes). Required: 40 dB, the target; a
//    single rounding of the scene's coordinates measured 49.5 dB in the Scale
//    test above, so the bound leaves room for that and nothing more.
//  - "world coordinates": the scene built directly at (D, D, D) in float with
//    the world's origin, as a C++ caller who ignores Scene::origin does. Not a
//    target, a measurement of what the local origin buys (positions quantised
//    to the float spacing there: 7.8e-3 at 1e5, 1 at 1e7): measured 25.6 dB at
//    1e5, 19.1 at 1e6, 12.4 at 1e7 (5282, 8323, 12953 pixels off). Required
//    only to render without non-finite values (at 1e7 the spheres' normals,
//    computed from rounded hit points, once had length sqrt(3) and made 91
//    pixels infinite).
TEST(Translation, DefaultSceneFarFromTheOriginRendersTheSameImage) {
  const Scene base = make_default_scene();
  const Framebuffer ref = render_scene(base, 160, 120, 2);
  for (double d : {1e5, 1e6, 1e7}) {
    const DVec3 off(d);
    const Framebuffer local = render_scene(transformed(base, 1.0, off, true), 160, 120, 2);
    const Framebuffer world = render_scene(transformed(base, 1.0, off, false), 160, 120, 2);
    EXPECT_EQ(count_nonfinite(local), 0u);
    EXPECT_EQ(count_nonfinite(world), 0u);
    const double p_local = psnr(ref, local), p_world = psnr(ref, world);
    std::printf("offset %g: PSNR local origin %.2f dB (%zu pixels > 1/255), world %.2f dB (%zu)\n",
                d, p_local, pixels_differing(ref, local), p_world, pixels_differing(ref, world));
    EXPECT_GE(p_local, 40.0) << "offset " << d;
  }
}

// ===========================================================================
// 4. Total internal reflection, nested dielectrics, energy
// ===========================================================================
//
// Scenes lit only by a white background of radiance 1 (no lights, ambient
// light 0): nothing emits, so no ray can return more than 1 per channel. Each
// interface splits a ray's weight w into w * (reflectivity + transparency * R)
// and w * transparency * (1 - R), at most w * (1 + 4 eps) in float; the color a
// ray returns is the same weighted sum of its children's colors. Over a
// recursion of depth d the rounding compounds to at most (1 + 8 eps)^d - 1 <
// 1e-5 for d <= 24, the tolerance used. The integrator has no medium stack:
// every interface is treated as air against the material (a sphere inside a
// sphere is entered from index 1), which is physically approximate but must
// still conserve energy.
constexpr float kEnergyTol = 1e-5f;

Material dielectric(const std::string& name, float ior, float transparency, float reflectivity) {
  Material m;
  m.name = name;
  m.color = Color(1.0f);
  m.ambient = 0.0f;
  m.diffuse = 0.0f;
  m.specular = 0.0f;
  m.ior = ior;
  m.transparency = transparency;
  m.reflectivity = reflectivity;
  return m;
}

Scene dielectric_scene() {
  Scene s;
  s.background = Color(1.0f);
  s.ambient_light = Color(0.0f);
  s.materials = {dielectric("glass", 1.5f, 1.0f, 0.0f), dielectric("water", 1.33f, 0.9f, 0.1f),
                 dielectric("diamond", 2.42f, 1.0f, 0.0f),
                 // An air bubble in water modelled as a material of index < 1:
                 // total internal reflection happens when entering it.
                 dielectric("bubble", 0.75f, 1.0f, 0.0f), dielectric("mirror", 1.0f, 0.0f, 1.0f),
                 dielectric("coated", 1.6f, 0.55f, 0.45f)};
  s.spheres = {
      Sphere{"outer glass", Vec3(0.0f), 1.0f, 0},
      Sphere{"inner water", Vec3(0.1f, 0.05f, 0.0f), 0.5f, 1},     // nested in the glass
      Sphere{"inner diamond", Vec3(0.15f, 0.05f, 0.1f), 0.2f, 2},  // nested in the water
      Sphere{"bubble", Vec3(-0.5f, -0.3f, 0.2f), 0.25f, 3},  // in the glass, cutting the water
      Sphere{"coincident glass", Vec3(2.2f, 0.0f, 0.0f), 0.7f, 0},  // two surfaces in one place
      Sphere{"coincident diamond", Vec3(2.2f, 0.0f, 0.0f), 0.7f, 2},
      Sphere{"touching glass", Vec3(-2.0f, 0.0f, 0.0f), 0.6f, 0},
      Sphere{"touching water", Vec3(-2.0f, 1.0f, 0.0f), 0.4f, 1},  // touches at y = 0.6
      Sphere{"mirror", Vec3(0.0f, 0.0f, -2.5f), 0.8f, 4},
  };
  // A coarse glass icosphere: its smooth shading normals differ from the
  // geometric ones by up to ~20 degrees, which exercises the integrator's
  // fallbacks to the geometric normal.
  TriangleMesh ico = make_icosphere(Vec3(0.0f, 1.7f, 0.3f), 0.6f, 1);
  ico.name = "coarse glass";
  ico.material = 5;
  s.meshes = {ico};
  // Everything below y = -1.2 is glass: rays entering it can only leave
  // upwards, and rays inside meet its surface at every angle.
  s.planes = {Plane{"glass floor", Vec3(0.0f, -1.2f, 0.0f), Vec3(0.0f, 1.0f, 0.0f), 0}};
  s.camera.eye = Vec3(0.0f, 1.0f, 5.0f);
  s.camera.look_at = Vec3(0.0f, 0.0f, 0.0f);
  s.camera.vfov_degrees = 55.0f;
  return s;
}

// Checks a recorded ray tree: finite values, returned colors in [0, 1 + tol],
// children's weights (reflection + refraction) summing to at most the
// parent's, Fresnel weights in [0, 1] summing to 1. Returns the number of
// violations and reports the first few.
size_t check_tree(const std::vector<RayRecord>& rays, const std::string& what) {
  size_t bad = 0;
  auto fail = [&](const std::string& msg) {
    if (++bad <= 5) ADD_FAILURE() << what << ": " << msg;
  };
  for (const RayRecord& r : rays) {
    if (!finite_color(r.color) || !finite_color(r.weight)) {
      fail("non-finite color or weight at ray " + std::to_string(r.id));
      continue;
    }
    for (int c = 0; c < 3; ++c)
      if (r.color[c] < 0.0f || r.color[c] > 1.0f + kEnergyTol)
        fail("ray " + std::to_string(r.id) + " returned " + std::to_string(r.color[c]));
    Color sum(0.0f);
    for (int child : r.children)
      if (rays[size_t(child)].kind != RayKind::Shadow) sum += rays[size_t(child)].weight;
    for (int c = 0; c < 3; ++c)
      if (sum[c] > r.weight[c] * (1.0f + 1e-6f))
        fail("children of ray " + std::to_string(r.id) + " weigh " + std::to_string(sum[c]) +
             " > " + std::to_string(r.weight[c]));
    if (r.has_refraction) {
      const RefractionEvent& e = r.refraction;
      if (!(e.fresnel_reflect >= 0.0f && e.fresnel_reflect <= 1.0f && e.fresnel_transmit >= 0.0f &&
            e.fresnel_transmit <= 1.0f &&
            std::abs(e.fresnel_reflect + e.fresnel_transmit - 1.0f) <= 0x1p-23f))
        fail("Fresnel weights R " + std::to_string(e.fresnel_reflect) + " T " +
             std::to_string(e.fresnel_transmit));
      if (e.total_internal_reflection && e.fresnel_reflect != 1.0f)
        fail("total internal reflection with R != 1");
      if (!std::isfinite(e.cos_incidence) || !std::isfinite(e.cos_transmission))
        fail("non-finite angles");
    }
  }
  return bad;
}

TEST(Dielectrics, NestedSpheresRenderWithoutNaNOrEnergyGain) {
  Scene s = dielectric_scene();
  RayCounters counters;
  const int w = 96, h = 72;
  Framebuffer fb = render_scene(s, w, h, 2, 16, 1e-4f, &counters);
  EXPECT_EQ(count_nonfinite(fb), 0u);
  float max_c = 0.0f, min_c = 1.0f;
  for (const Color& c : fb.color) {
    max_c = std::max(max_c, max_component(c));
    min_c = std::min(min_c, std::min(c.r, std::min(c.g, c.b)));
  }
  std::printf("pixels in [%.9g, %.9g]; %llu refraction rays, %llu total internal reflections\n",
              double(min_c), double(max_c),
              (unsigned long long)counters.rays[int(RayKind::Refraction)],
              (unsigned long long)counters.total_internal_reflections);
  EXPECT_LE(max_c, 1.0f + kEnergyTol);
  EXPECT_GE(min_c, 0.0f);
  EXPECT_GT(counters.total_internal_reflections, 1000u);  // the scene does exercise TIR

  // The ray trees of every 3rd pixel in both directions (all samples).
  s.commit();
  RenderSettings rs;
  rs.width = w;
  rs.height = h;
  rs.samples = 2;
  rs.max_depth = 16;
  rs.min_contribution = 1e-4f;
  prepare_frame(s, rs);
  size_t bad = 0, rays = 0;
  const int step = stress_scale() >= 0.5 ? 3 : 9;
  for (int y = 1; y < h; y += step)
    for (int x = 1; x < w; x += step) {
      PixelRecord rec = record_pixel(s, rs, x, y);
      rays += rec.rays.size();
      bad += check_tree(rec.rays, "pixel " + std::to_string(x) + "," + std::to_string(y));
    }
  std::printf("%zu recorded rays checked\n", rays);
  EXPECT_EQ(bad, 0u);
}

TEST(Dielectrics, RaysAtAndAroundTheCriticalAngle) {
  // Rays inside a dielectric meeting its surface at the critical angle
  // asin(1 / n) and within +-48 ulps of it (~3e-6 rad either side), and
  // rays entering the bubble (n = 0.75 < 1) around asin(0.75): on the glass
  // floor (a plane: the incidence angle is exact up to the rounding of the
  // direction), at the top of the outer glass sphere and of the coincident
  // spheres. Then a sweep of incidence angles from 0 to 90 degrees. Each ray is
  // traced with weight 1 to depth 24 and min contribution 1e-5; its tree must
  // pass check_tree, and each set of +-48 ulps must contain both total
  // internal reflection and transmission at the first hit.
  Scene s = dielectric_scene();
  s.commit();
  RenderSettings rs;
  rs.max_depth = 24;
  rs.min_contribution = 1e-5f;
  RayCounters counters;

  struct Config {
    const char* name;
    Vec3 hit;      // where the ray meets the surface
    Vec3 normal;   // outward normal there
    float n1, n2;  // from n1 into n2 (what the integrator uses there)
    bool inside;   // the ray starts inside the object
  };
  const std::vector<Config> configs = {
      {"glass floor from inside", Vec3(0.3f, -1.2f, 0.4f), Vec3(0, 1, 0), 1.5f, 1.0f, true},
      {"outer glass sphere from inside", Vec3(0.0f, 1.0f, 0.0f), Vec3(0, 1, 0), 1.5f, 1.0f, true},
      // Of two coincident spheres, the one with the lower index is reported
      // (Scene::intersect's tie rule): the glass one.
      {"coincident spheres from inside", Vec3(2.2f, 0.7f, 0.0f), Vec3(0, 1, 0), 1.5f, 1.0f, true},
      {"nested diamond from inside", Vec3(0.15f, 0.25f, 0.1f), Vec3(0, 1, 0), 2.42f, 1.0f, true},
      {"entering the bubble", Vec3(-0.5f, -0.05f, 0.2f), Vec3(0, 1, 0), 1.0f, 0.75f, false},
  };
  size_t bad = 0, traced = 0;
  auto trace = [&](const Config& c, float theta, const DVec3& tangent, bool& tir) {
    // Direction toward the hit point at angle theta to the normal; origin a
    // short way back along it.
    DVec3 n = to_d(c.normal), dir = (c.inside ? 1.0 : -1.0) * std::cos(double(theta)) * n +
                                    std::sin(double(theta)) * tangent;
    Vec3 d = to_f(dir);
    Vec3 o = to_f(to_d(c.hit) - 0.05 * dir);
    RayTreeRecorder rec;
    WhittedIntegrator<RayTreeRecorder> integrator(s, rs, counters, rec);
    rec.begin_sample(0);
    Color col = integrator.trace(Ray{o, d, kInfinity}, RayKind::Primary, 0, Color(1.0f), -1);
    ++traced;
    bad += check_tree(rec.rays, std::string(c.name) + " theta " + std::to_string(theta));
    if (!finite_color(col) || max_component(col) > 1.0f + kEnergyTol) ++bad;
    tir = !rec.rays.empty() && rec.rays[0].has_refraction &&
          rec.rays[0].refraction.total_internal_reflection;
    return rec.rays.empty() ? 0.0f : rec.rays[0].refraction.n1;
  };
  Rng rng(12);
  for (const Config& c : configs) {
    const float crit = critical_angle(c.n1, c.n2);
    ASSERT_LT(crit, 0.5f * kPi) << c.name;
    size_t tir_count = 0, transmit_count = 0;
    for (int tangent_k = 0; tangent_k < 4; ++tangent_k) {
      DVec3 tangent = glm::normalize(glm::cross(to_d(c.normal), rng.unit_vector()));
      float theta = crit;
      for (int k = 0; k < 48; ++k) theta = next_float_down(theta);
      for (int k = -48; k <= 48; ++k, theta = next_float_up(theta)) {
        bool tir = false;
        float n1 = trace(c, theta, tangent, tir);
        EXPECT_EQ(n1, c.n1) << c.name << ": the ray did not hit the intended surface first";
        (tir ? tir_count : transmit_count)++;
      }
    }
    std::printf(
        "%s: critical angle %.9g rad; +-48 ulps: %zu total internal reflections, %zu "
        "transmissions\n",
        c.name, double(crit), tir_count, transmit_count);
    EXPECT_GT(tir_count, 0u) << c.name;
    EXPECT_GT(transmit_count, 0u) << c.name;
    // A sweep over all incidence angles, grazing ones included.
    for (int i = 0; i <= int(scaled(4000)); ++i) {
      bool tir;
      trace(c, float(0.5 * M_PI * i / double(scaled(4000))) * (1.0f - 1e-7f),
            glm::normalize(glm::cross(to_d(c.normal), rng.unit_vector())), tir);
    }
  }
  std::printf("%zu rays traced, %llu total internal reflections\n", traced,
              (unsigned long long)counters.total_internal_reflections);
  EXPECT_EQ(bad, 0u);
}

}  // namespace
