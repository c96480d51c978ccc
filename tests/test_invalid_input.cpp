// Invalid input to the core: non-finite vertex coordinates, normals and
// colors (skipped or replaced, and reported in SceneSummary::warnings), a
// mesh with no finite triangle, non-finite spheres, planes, lights and
// camera (errors naming the object), rays with NaN, infinite or zero
// components (no hit, the background): no crash and no NaN pixel.
// (Input files: test_input_files; scene files: test_scene_io; degenerate
// but legal geometry: test_watertight; through every structure:
// test_accel_conformance.)
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayscope/integrator.h"
#include "rayscope/render.h"
#include "rayscope/scene.h"
#include "rayscope/shapes.h"
#include "scene_test_util.h"
#include "test_util.h"

namespace {

using namespace rayscope;
using rstest::count_nonfinite;
using rstest::DVec3;
using rstest::finite_color;
using rstest::mesh_scene;
using rstest::render_scene;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

bool same_colors(const Framebuffer& a, const Framebuffer& b) {
  if (a.color.size() != b.color.size()) return false;
  for (size_t i = 0; i < a.color.size(); ++i)
    if (a.color[i] != b.color[i]) return false;
  return true;
}

bool any_warning_contains(const SceneSummary& s, const std::string& what) {
  for (const std::string& w : s.warnings)
    if (w.find(what) != std::string::npos) return true;
  return false;
}

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

TEST(InvalidInput, TubesAndPointsSkipBadPositionsAndRadiiAndRefuseBadSets) {
  // Per-position data (from files: one bad value should not cost the
  // picture) is skipped and reported; what whoever built the scene got wrong
  // (sizes, indices, the one radius, a set with nothing left) is an error
  // naming the set.
  Scene base = mesh_scene(make_icosphere(Vec3(0.0f), 0.5f, 2));
  TubeSet tubes;
  tubes.name = "lines";
  for (int i = 0; i < 6; ++i) tubes.positions.push_back(Vec3(float(i) - 2.5f, 1.0f, 0.0f));
  for (uint32_t i = 0; i + 1 < 6; ++i) tubes.segments.push_back({i, i + 1});
  tubes.radii = {0.1f, 0.1f, 0.1f, 0.1f, 0.1f, 0.1f};
  tubes.colors.assign(6, Color(1.0f, 0.0f, 0.0f));
  PointSet points;
  points.name = "dots";
  for (int i = 0; i < 5; ++i) points.positions.push_back(Vec3(float(i) - 2.0f, -1.0f, 0.0f));
  points.radius = 0.2f;
  points.colors.assign(5, Color(0.0f, 1.0f, 0.0f));

  Scene s = base;
  s.tubes = {tubes};
  s.points = {points};
  s.tubes[0].positions[1].y = kNaN;        // segments 0 and 1
  s.tubes[0].radii[4] = -1.0f;             // segments 3 and 4 (a mean of 0.1 and -1 is < 0,
  s.tubes[0].radii[5] = 3.0f;              // of -1 and 3 is 1, but -1 is no radius)
  s.tubes[0].colors[3] = Color(kNaN);      // reported, the material color used
  s.points[0].positions[2].z = kInfinity;  // point 2
  s.commit();
  EXPECT_EQ(s.summary().skipped_segments, 4u);  // 0, 1, 3, 4
  EXPECT_EQ(s.summary().tube_segments, 1u);     // 2
  EXPECT_EQ(s.summary().skipped_points, 1u);
  EXPECT_EQ(s.summary().points, 4u);
  EXPECT_EQ(s.summary().nonfinite_colors, 1u);
  EXPECT_TRUE(any_warning_contains(s.summary(),
                                   "tubes 'lines': 4 segments with a non-finite end "
                                   "or an end's radius not finite and > 0 skipped"));
  EXPECT_TRUE(any_warning_contains(s.summary(),
                                   "points 'dots': 1 points with a non-finite "
                                   "position or a radius not finite and > 0 skipped"));
  EXPECT_TRUE(any_warning_contains(s.summary(), "tubes 'lines': 1 colors are not finite"));
  // No hit on what was skipped, every hit finite.
  Rng rng(32);
  const Bounds3 world(Vec3(-4.0f), Vec3(4.0f));
  int tube_hits = 0;
  for (int i = 0; i < 20000; ++i) {
    SurfaceHit h;
    if (!s.intersect(rstest::random_ray(rng, world, {}), h)) continue;
    ASSERT_TRUE(std::isfinite(h.t) && all_finite(h.p) && all_finite(h.ng));
    if (s.object_type(h.object) == ObjectType::Tubes) {
      ++tube_hits;
      ASSERT_EQ(h.prim, 2u) << "hit a skipped segment";
      if (h.has_vertex_color) {
        ASSERT_TRUE(finite_color(h.vertex_color));
      }
    }
    if (s.object_type(h.object) == ObjectType::Points) {
      ASSERT_NE(h.prim, 2u);
    }
  }
  EXPECT_GT(tube_hits, 0);
  EXPECT_EQ(count_nonfinite(render_scene(s, 48, 32, 1)), 0u);

  auto commit_error = [&](const std::function<void(Scene&)>& change) -> std::string {
    Scene bad = base;
    bad.tubes = {tubes};
    bad.points = {points};
    change(bad);
    try {
      bad.commit();
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(commit_error([](Scene& b) { b.tubes[0].segments[2].y = 6; }),
            "tubes 'lines': position index out of range");
  EXPECT_EQ(commit_error([](Scene& b) { b.tubes[0].radii.pop_back(); }),
            "tubes 'lines': radii must match positions");
  EXPECT_EQ(commit_error([](Scene& b) { b.points[0].colors.push_back(Color(0.0f)); }),
            "points 'dots': colors must match positions");
  EXPECT_EQ(commit_error([](Scene& b) { b.points[0].radius = 0.0f; }),
            "points 'dots': radius must be finite and > 0");
  EXPECT_EQ(commit_error([](Scene& b) {
              b.tubes[0].radii.clear();
              b.tubes[0].radius = kNaN;
            }),
            "tubes 'lines': radius must be finite and > 0");
  EXPECT_EQ(commit_error([](Scene& b) { b.tubes[0].material = 9; }),
            "tubes 'lines': material index 9 out of range");
  EXPECT_EQ(
      commit_error([](Scene& b) { b.points[0].radii.assign(5, kInfinity); }),
      "points 'dots': all 5 points have a non-finite position or a radius not finite and > 0");
  // The one radius is not checked when radii are given, nor is a set without
  // segments an error (nothing to trace, nothing drawn).
  EXPECT_EQ(commit_error([](Scene& b) { b.tubes[0].radius = kNaN; }), "");
  EXPECT_EQ(commit_error([](Scene& b) { b.tubes[0].segments.clear(); }), "");
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

}  // namespace
