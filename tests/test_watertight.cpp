// Watertightness: no ray from inside a closed triangle mesh escapes through a
// crack between triangles. The mesh is an icosphere (make_icosphere, level 5:
// 20480 triangles) traced through Scene::intersect, i.e. through the BVH and
// the watertight triangle test together.
//
// Centers at the origin, at (1e3, 1e3, 1e3) and at (1e5, 1e5, 1e5) with radii
// 1, 10 and 100. Float spacing there is 1.2e-7, 6.1e-5 and 7.8e-3, while the
// triangle edges are ~0.033 r = 0.033, 0.33 and 3.3 long: every triangle is
// resolved by hundreds of ulps, so the mesh is a proper closed surface in
// float, and the far-from-origin cases exercise the translation of vertices to
// the ray origin where absolute rounding errors are large.
//
// WatertightDegenerate: the opposite, closed spheres so small for their
// distance from the origin that float rounding of the vertices leaves many
// triangles of zero area, plus duplicated triangles; rays from outside aimed
// exactly at vertices and edge midpoints (which may lie on the silhouette)
// and from inside must never escape, through the BVH and without one.
// WatertightEdgeFunctions: an edge function that float rounds to zero is
// decided by its exact sign.
//
// WatertightMillion: the same at scale, a closed icosphere of 1,310,720
// triangles centred at (1e6, 1e6, 1e6): 1e6 random rays from interior points
// and rays aimed exactly at every vertex and every edge midpoint never escape
// (scaled down by stress_scale() in sanitizer and unoptimised builds).
// WatertightUnwelded: an icosphere whose triangles each have their own
// vertices (as STL files store them), with zero-area triangles inside: no ray
// escapes, none hits a zero-area triangle.
// WatertightTubes: polylines drawn as tubes (capsules) with bends up to
// nearly back on themselves, equal and varying radii, near and far from the
// origin: rays aimed at the joints and at the circles where a capsule's side
// meets its caps never slip through, from outside or from inside.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "rayscope/scene.h"
#include "rayscope/shapes.h"
#include "test_util.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::Rng;
using rstest::stress_scale;
using rstest::to_d;
using rstest::to_f;

// Every vertex of a mesh, then every edge's midpoint (each edge once),
// computed in float: targets that rays pass through exactly (vertices) or to
// within rounding (midpoints, on the shared edge).
std::vector<Vec3> vertex_and_edge_targets(const TriangleMesh& mesh) {
  std::vector<Vec3> targets = mesh.positions;
  for (const glm::uvec3& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) {
      uint32_t a = t[e], b = t[(e + 1) % 3];
      if (a < b) targets.push_back(0.5f * (mesh.positions[a] + mesh.positions[b]));
    }
  return targets;
}

struct IcoConfig {
  Vec3 center;
  float radius;
  int levels;
};

class Watertight : public ::testing::TestWithParam<IcoConfig> {
 protected:
  void SetUp() override {
    const IcoConfig& s = GetParam();
    mesh_ = make_icosphere(s.center, s.radius, s.levels);
    ASSERT_EQ(mesh_.triangles.size(), size_t(20) << (2 * s.levels));
    scene_.meshes = {mesh_};
    scene_.commit();
    ASSERT_TRUE(scene_.summary().walks_structure);
    ASSERT_EQ(scene_.summary().triangles, mesh_.triangles.size());
  }

  // Traces a ray that starts inside; counts and reports escapes. The hit must
  // also lie on the mesh: between the inscribed radius (the flat triangles sit
  // at most r (1 - cos 0.02) ~ 2e-4 r inside the sphere) and r, with slack for
  // float rounding of the vertices.
  void trace(const Vec3& o, const Vec3& d, const char* what) {
    const IcoConfig& s = GetParam();
    Ray ray{o, d, kInfinity};
    SurfaceHit hit;
    bool found = scene_.intersect(ray, hit);
    bool blocked = scene_.occluded(ray);
    ++rays_;
    if (!found || !blocked) {
      if (++misses_ <= 5)
        ADD_FAILURE() << what << ": ray escaped (intersect " << found << ", occluded " << blocked
                      << ") " << std::hexfloat << "o=(" << o.x << "," << o.y << "," << o.z
                      << ") d=(" << d.x << "," << d.y << "," << d.z << ")";
      return;
    }
    double dist = glm::length(to_d(hit.p) - to_d(s.center));
    double slack = 1e-6 * rstest::max_abs(to_d(s.center)) + 1e-6 * s.radius;
    if (!(hit.t > 0 && dist <= s.radius + slack && dist >= 0.999 * s.radius - slack)) {
      if (++bad_hits_ <= 5)
        ADD_FAILURE() << what << ": hit at distance " << dist << " from the center, t=" << hit.t;
    }
  }

  void report(const char* what) {
    std::printf("%s: %zu rays, %zu escaped, %zu bad hits\n", what, rays_, misses_, bad_hits_);
    EXPECT_EQ(misses_, 0u) << what;
    EXPECT_EQ(bad_hits_, 0u) << what;
    rays_ = misses_ = bad_hits_ = 0;
  }

  TriangleMesh mesh_;
  Scene scene_;
  size_t rays_ = 0, misses_ = 0, bad_hits_ = 0;
};

TEST_P(Watertight, RandomRaysFromInsideAndFromTheCenter) {
  const IcoConfig& s = GetParam();
  Rng rng(20240 + uint32_t(s.radius));
  // 1e5 rays from random interior points (within 0.98 r: inside the inscribed
  // radius) in random directions of random length, 2e4 from the center.
  for (int i = 0; i < 100000; ++i) {
    Vec3 o = to_f(to_d(s.center) + 0.98 * double(s.radius) * rng.in_unit_ball());
    Vec3 d = to_f(rng.unit_vector() * rng.log_uniform(1e-3, 1e3));
    trace(o, d, "random interior ray");
  }
  report("random interior rays");
  for (int i = 0; i < 20000; ++i) {
    Vec3 d = to_f(rng.unit_vector() * rng.log_uniform(1e-3, 1e3));
    trace(s.center, d, "ray from the center");
  }
  report("rays from the center");
}

TEST_P(Watertight, RaysAtEveryVertexAndEdgeMidpoint) {
  // From the center, aimed exactly at every vertex (v - center is exact: both
  // are floats of the same binade, Sterbenz), so each ray passes exactly
  // through a point shared by 5 or 6 triangles; and at every edge midpoint
  // computed in float, which lies on the shared edge to within rounding.
  // Then the same from a few random interior points (directions rounded: rays
  // pass within an ulp or so of the vertex or edge).
  const IcoConfig& s = GetParam();
  Rng rng(555);
  const std::vector<Vec3> targets = vertex_and_edge_targets(mesh_);
  ASSERT_EQ(targets.size(), mesh_.positions.size() + mesh_.triangles.size() * 3 / 2);
  for (const Vec3& v : targets) {
    Vec3 d = v - s.center;
    ASSERT_EQ(to_d(d), to_d(v) - to_d(s.center));
    trace(s.center, d, "ray from the center at a vertex/edge midpoint");
  }
  report("center to vertices and edge midpoints");
  for (int k = 0; k < 4; ++k) {
    Vec3 o = to_f(to_d(s.center) + 0.5 * double(s.radius) * rng.in_unit_ball());
    for (const Vec3& v : targets) trace(o, v - o, "interior point to a vertex/edge midpoint");
  }
  report("interior points to vertices and edge midpoints");
}

TEST_P(Watertight, AxisAlignedAndCoordinatePlaneDirections) {
  // Directions with zero components: slabs of the BVH boxes are then hit with
  // infinite reciprocals, and rays from the center run in the coordinate
  // planes that contain many vertices and edges of the icosphere.
  const IcoConfig& s = GetParam();
  Rng rng(99);
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {1.0f, -1.0f}) {
      Vec3 d(0.0f);
      d[axis] = sign;
      trace(s.center, d, "axis direction from the center");
    }
  for (int i = 0; i < 20000; ++i) {
    DVec3 u = rng.unit_vector();
    u[rng.integer(0, 2)] = 0.0;
    if (i % 2) u[rng.integer(0, 2)] = 0.0;
    if (u == DVec3(0.0)) u.x = 1.0;
    trace(s.center, to_f(u), "coordinate-plane direction from the center");
  }
  report("zero-component directions");
}

std::string config_name(const ::testing::TestParamInfo<IcoConfig>& info) {
  static const char* const kNames[] = {"Origin_R1", "At1e3_R10", "At1e5_R100"};
  return kNames[info.index];
}

INSTANTIATE_TEST_SUITE_P(IcosphereLevel5, Watertight,
                         ::testing::Values(IcoConfig{Vec3(0.0f), 1.0f, 5},
                                           IcoConfig{Vec3(1e3f), 10.0f, 5},
                                           IcoConfig{Vec3(1e5f), 100.0f, 5}),
                         config_name);

}  // namespace

// ---------------------------------------------------------------------------
// Float-degenerate meshes: closed spheres so small for their distance from the
// origin that rounding the vertices to float leaves many triangles with zero
// area (collinear or coincident vertices), plus duplicated triangles.

namespace degenerate {

// Latitude-longitude sphere: slivers near the poles, one vertex per pole.
TriangleMesh make_uv_sphere(const DVec3& c, double r, int rings, int segments) {
  TriangleMesh m;
  m.name = "uv sphere";
  m.positions.push_back(to_f(c + DVec3(0, r, 0)));
  for (int i = 1; i < rings; ++i) {
    double th = M_PI * i / rings;
    for (int j = 0; j < segments; ++j) {
      double ph = 2 * M_PI * j / segments;
      m.positions.push_back(to_f(
          c + r * DVec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph))));
    }
  }
  m.positions.push_back(to_f(c - DVec3(0, r, 0)));
  const uint32_t south = uint32_t(m.positions.size() - 1);
  auto id = [&](int i, int j) { return uint32_t(1 + (i - 1) * segments + (j % segments)); };
  for (int j = 0; j < segments; ++j) {
    m.triangles.emplace_back(0, id(1, j + 1), id(1, j));
    m.triangles.emplace_back(south, id(rings - 1, j), id(rings - 1, j + 1));
  }
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      uint32_t a = id(i, j), b = id(i, j + 1), cc = id(i + 1, j + 1), d = id(i + 1, j);
      m.triangles.emplace_back(a, b, cc);
      m.triangles.emplace_back(a, cc, d);
    }
  return m;
}

size_t zero_area(const TriangleMesh& m) {
  size_t n = 0;
  for (const glm::uvec3& t : m.triangles) {
    DVec3 a = to_d(m.positions[t.x]), b = to_d(m.positions[t.y]), c = to_d(m.positions[t.z]);
    if (glm::cross(b - a, c - a) == DVec3(0.0)) ++n;  // exact: few-ulp differences
  }
  return n;
}

// ===========================================================================
// Watertightness of a 1.3M-triangle mesh far from the origin
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

  const size_t n = rstest::stress_scaled(1000000);
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
  const std::vector<Vec3> targets = vertex_and_edge_targets(*mesh_);
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

TEST(WatertightUnwelded, ZeroAreaTrianglesAndDuplicateVerticesKeepTheMeshClosed) {
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

}  // namespace degenerate

// Meshes: icospheres (level 5, 20480 triangles) of radius 0.004 and 0.03 at
// ~(3000, -2000, 2500), where a float step is 2.4e-4: edges of ~0.6 and ~4
// ulps, so that rounding makes collinear and coincident vertices (9908 of
// 23406 triangles have zero area at r = 0.004; none at 0.03, whose vertices
// are rounded by a sixth of an edge); and
// UV spheres (96 x 192) of radius 0.1 and 1 at ~(-1e5, 1.2e5, 9e4) (float
// step 0.0078), whose pole slivers collapse (35710 and 2674 zero-area
// triangles of 41692). Every 7th triangle is added again (duplicates).
struct DegenerateConfig {
  const char* name;
  bool uv;
  double radius;
  bool has_zero_area;  ///< Whether rounding leaves zero-area triangles.
};

class WatertightDegenerate : public ::testing::TestWithParam<DegenerateConfig> {
 protected:
  void SetUp() override {
    const DegenerateConfig& c = GetParam();
    const DVec3 ico_center(3001.7, -1999.3, 2500.1), uv_center(-1.0e5 - 0.3, 1.2e5 + 0.7, 0.9e5);
    if (c.uv) {
      mesh_ = degenerate::make_uv_sphere(uv_center, c.radius, 96, 192);
      center_ = uv_center;
    } else {
      mesh_ = make_icosphere(to_f(ico_center), float(c.radius), 5);
      center_ = to_d(to_f(ico_center));
    }
    const size_t base = mesh_.triangles.size();
    for (size_t i = 0; i < base; i += 7) mesh_.triangles.push_back(mesh_.triangles[i]);
    zero_area_ = degenerate::zero_area(mesh_);
  }

  // Rays at targets on the surface: every vertex, and every edge midpoint
  // that float computes exactly (0.5f * (a + b) == (a + b) / 2 in double; the
  // others are off the surface). From outside: origins at 1.5..20 r in random
  // directions; d = v - o is exact (checked: o and v agree to within a
  // factor 2 in every coordinate, Sterbenz), so the ray passes exactly through
  // the target, which may lie on the silhouette. From inside (within 0.9 r):
  // every float midpoint, exact or not, since any ray from inside must leave.
  // An escape is a ray that neither intersect() nor occluded() finds a hit
  // for. Returns the escapes; counts the rays in `rays`.
  size_t shoot(const Scene& scene, size_t stride, bool inside, bool exact_mids_only, bool vertices,
               uint32_t seed, size_t& rays) {
    const double r = GetParam().radius;
    Rng rng(seed);
    std::vector<Vec3> targets;
    if (vertices) {
      targets = mesh_.positions;
    } else {
      for (const glm::uvec3& t : mesh_.triangles)
        for (int e = 0; e < 3; ++e) {
          const Vec3 a = mesh_.positions[t[e]], b = mesh_.positions[t[(e + 1) % 3]];
          const Vec3 mid = 0.5f * (a + b);
          if (!exact_mids_only || to_d(mid) == 0.5 * (to_d(a) + to_d(b))) targets.push_back(mid);
        }
    }
    size_t escaped = 0;
    for (size_t i = 0; i < targets.size(); i += stride) {
      const Vec3 o = to_f(inside ? center_ + 0.9 * r * rng.in_unit_ball()
                                 : center_ + r * rng.log_uniform(1.5, 20) * rng.unit_vector());
      const Vec3 d = targets[i] - o;
      EXPECT_EQ(to_d(d), to_d(targets[i]) - to_d(o));
      ++rays;
      const Ray ray{o, d, kInfinity};
      PrimHit h;
      if (!scene.intersect(ray, h) || !scene.occluded(ray)) {
        if (++escaped <= 3)
          ADD_FAILURE() << std::hexfloat << "escaped: o=(" << o.x << ", " << o.y << ", " << o.z
                        << ") d=(" << d.x << ", " << d.y << ", " << d.z << ")";
      }
    }
    return escaped;
  }

  TriangleMesh mesh_;
  DVec3 center_;
  size_t zero_area_ = 0;
};

TEST_P(WatertightDegenerate, RaysAtVerticesAndEdgesNeverEscape) {
  EXPECT_EQ(zero_area_ > 0, GetParam().has_zero_area);
  // Through the BVH (AccelKind::Bvh) every target (a stride under
  // sanitizers), and without a structure (AccelKind::None: O(n) per ray) every
  // 97th, so that the triangle test alone is checked too.
  const size_t stride = rstest::stress_stride();
  for (AccelKind kind : {AccelKind::Bvh, AccelKind::None}) {
    AccelConfig config;
    config.kind = kind;
    Scene scene;
    scene.meshes = {mesh_};
    scene.commit(config);
    const size_t s = kind == AccelKind::None ? 97 * stride : stride;
    size_t rv = 0, re = 0, ri = 0;
    const size_t ev = shoot(scene, s, false, true, true, 1, rv);
    const size_t ee = shoot(scene, s, false, true, false, 2, re);
    const size_t ei = shoot(scene, s, true, false, false, 3, ri);
    std::printf(
        "%s, %s: %zu triangles (%zu zero-area); from outside: %zu/%zu vertex rays and "
        "%zu/%zu edge-midpoint rays escaped; from inside: %zu/%zu\n",
        GetParam().name, to_string(kind), mesh_.triangles.size(), zero_area_, ev, rv, ee, re, ei,
        ri);
    EXPECT_EQ(ev + ee + ei, 0u) << to_string(kind);
    EXPECT_GT(re, rv / 4) << "too few exact edge midpoints";
  }
}

INSTANTIATE_TEST_SUITE_P(FloatRounded, WatertightDegenerate,
                         ::testing::Values(DegenerateConfig{"Ico_R0_004", false, 0.004, true},
                                           DegenerateConfig{"Ico_R0_03", false, 0.03, false},
                                           DegenerateConfig{"UV_R0_1", true, 0.1, true},
                                           DegenerateConfig{"UV_R1", true, 1.0, true}),
                         [](const ::testing::TestParamInfo<DegenerateConfig>& info) {
                           return info.param.name;
                         });

TEST(WatertightEdgeFunctions, ZeroInFloatIsDecidedExactly) {
  // The case the double-precision recomputation of zero edge functions in
  // intersect_triangle exists for. A ray along +z from the origin sees the
  // triangle unsheared (x' = x, y' = y). For the edge p1 p2 the products
  // x1 y2 = (1 + 2047 2^-23)^2 and y1 x2 = 1 + 4094 2^-23 differ by
  // 2047^2 2^-46 = 6e-8, less than half an ulp of either, so the float edge
  // function is exactly 0, which the test counts as inside; its exact sign
  // (+) is opposite to the other two (-): the ray passes ~1e-5 outside the edge
  // (found by an exact rational search). Without the recomputation the ray
  // hits.
  const Vec3 p0(0x1.8010e8p+1f, 0x1.8028e6p+1f, 1.0f);
  const Vec3 p1(0x1.000ffep+0f, 0x1.001ffcp+0f, 1.0f);
  const Vec3 p2(1.0f, 0x1.000ffep+0f, 1.0f);
  ASSERT_EQ(p1.x * p2.y - p1.y * p2.x, 0.0f);                   // the float edge function
  const double e0 = double(p1.x) * p2.y - double(p1.y) * p2.x;  // exact
  const double e1 = double(p2.x) * p0.y - double(p2.y) * p0.x;
  const double e2 = double(p0.x) * p1.y - double(p0.y) * p1.x;
  ASSERT_GT(e0, 0.0);
  ASSERT_LT(e1, 0.0);
  ASSERT_LT(e2, 0.0);
  TriangleHit h;
  EXPECT_FALSE(
      intersect_triangle(Ray{Vec3(0.0f), Vec3(0.0f, 0.0f, 1.0f), kInfinity}, p0, p1, p2, h))
      << "t=" << h.t;
}

// ---------------------------------------------------------------------------
// Tubes

namespace {

struct TubeConfig {
  double center;    ///< The polyline starts at (center, center, center).
  double size;      ///< Segment lengths are 0.5..2 times this.
  bool vary_radii;  ///< Radii per position (a step at every joint) or one radius.
  AccelKind kind;
};

class WatertightTubes : public ::testing::TestWithParam<TubeConfig> {};

// A polyline of 40 segments turning by 0..175 degrees at each joint, drawn
// with radius 0.1..0.4 times the size. Targets, rounded to float and kept
// when they lie inside some capsule by at least 1e-9 of its radius (in long
// double): each joint (a float point on both segments' axes), points just
// inside the joint's ball, and points just inside each end circle of each
// capsule (its side meets its cap there). Every ray from outside aimed at a
// target must hit at or before it (t <= 1 + 1e-4: a ray that slipped in at
// the target's surface would exit on the far side, a chord later); every ray
// from a target must hit (it starts inside the tube).
TEST_P(WatertightTubes, RaysAtJointsAndSeamsNeverSlipThrough) {
  const TubeConfig& c = GetParam();
  Rng rng(uint32_t(81 + 7 * int(c.kind)) + (c.vary_radii ? 1000u : 0u));
  TubeSet tubes;
  tubes.name = "polyline";
  tubes.radius = rstest::round_f(0.25 * c.size);
  DVec3 p(c.center), dir = rng.unit_vector();
  for (int i = 0; i <= 40; ++i) {
    tubes.positions.push_back(to_f(p));
    tubes.radii.push_back(rstest::round_f(c.size * rng.uniform(0.1, 0.4)));
    if (i > 0) tubes.segments.push_back({uint32_t(i - 1), uint32_t(i)});
    // Turn by up to 175 degrees: a random direction, not straight back.
    DVec3 next;
    do {
      next = rng.unit_vector();
    } while (glm::dot(next, dir) < std::cos(glm::radians(175.0)));
    dir = next;
    p = to_d(tubes.positions.back()) + c.size * rng.uniform(0.5, 2.0) * dir;
  }
  if (!c.vary_radii) tubes.radii.clear();
  Scene scene;
  scene.tubes = {tubes};
  AccelConfig config;
  config.kind = c.kind;
  scene.commit(config);
  ASSERT_EQ(scene.summary().tube_segments, 40u);
  const TubeSet& t = scene.tubes[0];
  using rstest::LDVec3;
  using rstest::to_ld;
  // How deep q lies inside the tube (> 0: inside), relative to the radius of
  // the capsule it is deepest in.
  auto depth = [&](const Vec3& q) {
    long double best = -INFINITY;
    for (size_t j = 0; j < t.segments.size(); ++j) {
      const long double r = t.segment_radius(j);
      const long double d = rstest::ref_segment_distance(
          to_ld(q), to_ld(t.positions[t.segments[j].x]), to_ld(t.positions[t.segments[j].y]));
      best = std::max(best, (r - d) / r);
    }
    return best;
  };
  std::vector<Vec3> targets;
  auto add = [&](const DVec3& q) {
    const Vec3 f = to_f(q);
    if (depth(f) >= 1e-9L) targets.push_back(f);
  };
  for (size_t j = 0; j < t.segments.size(); ++j) {
    const DVec3 a = to_d(t.positions[t.segments[j].x]), b = to_d(t.positions[t.segments[j].y]);
    const double r = t.segment_radius(j);
    const DVec3 u = glm::normalize(b - a);
    targets.push_back(t.positions[t.segments[j].x]);  // the joint itself
    for (int k = 0; k < 8; ++k) {
      add(a + r * (1.0 - rng.log_uniform(1e-6, 1e-2)) * rng.unit_vector());  // the joint's ball
      DVec3 across = rng.unit_vector();
      across = glm::normalize(across - glm::dot(across, u) * u);
      const double in = 1.0 - rng.log_uniform(1e-6, 1e-2);
      add(a + r * in * across);  // the end circles
      add(b + r * in * across);
    }
  }
  size_t rays = 0, slipped = 0, escaped = 0;
  std::string first;
  for (const Vec3& q : targets)
    for (int k = 0; k < 4; ++k) {
      const Vec3 o = to_f(to_d(q) + c.size * rng.log_uniform(3, 30) * rng.unit_vector());
      if (depth(o) > 0.0L) continue;
      const Vec3 d = q - o;
      SurfaceHit hit;
      ++rays;
      if (!scene.intersect(Ray{o, d, kInfinity}, hit) || !(hit.t <= 1.0f + 1e-4f) ||
          !scene.occluded(Ray{o, d, kInfinity})) {
        if (++slipped == 1)
          first = "from outside through " + ::testing::PrintToString(q) + ", hit t " +
                  std::to_string(hit.t);
      }
      const Vec3 w = to_f(rng.unit_vector());
      if (!scene.intersect(Ray{q, w, kInfinity}, hit) || !scene.occluded(Ray{q, w, kInfinity})) {
        if (++escaped == 1) first = "from inside at " + ::testing::PrintToString(q);
      }
    }
  std::printf(
      "%s, tubes at %g, size %g, %s: %zu targets, %zu rays, %zu slipped through, %zu escaped\n",
      to_string(c.kind), c.center, c.size, c.vary_radii ? "radii per position" : "one radius",
      targets.size(), rays, slipped, escaped);
  EXPECT_GT(targets.size(), 40u * 12);
  EXPECT_EQ(slipped, 0u) << first;
  EXPECT_EQ(escaped, 0u) << first;
}

INSTANTIATE_TEST_SUITE_P(Tubes, WatertightTubes,
                         ::testing::Values(TubeConfig{0.0, 1.0, false, AccelKind::Bvh},
                                           TubeConfig{0.0, 1.0, true, AccelKind::Bvh},
                                           TubeConfig{0.0, 1e-4, true, AccelKind::None},
                                           TubeConfig{1e3, 1.0, true, AccelKind::Grid},
                                           TubeConfig{1e5, 100.0, true, AccelKind::Bvh},
                                           TubeConfig{1e5, 1.0, false, AccelKind::Bvh}));

}  // namespace
