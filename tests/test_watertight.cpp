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
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "rayscope/scene.h"
#include "rayscope/shapes.h"
#include "test_util.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

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
    ASSERT_TRUE(scene_.summary().bvh_used);
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
  std::vector<Vec3> targets = mesh_.positions;
  for (const glm::uvec3& t : mesh_.triangles)
    for (int e = 0; e < 3; ++e) {
      uint32_t a = t[e], b = t[(e + 1) % 3];
      if (a < b) targets.push_back(0.5f * (mesh_.positions[a] + mesh_.positions[b]));
    }
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
