// Lines drawn as tubes and points drawn as spheres in a scene: object and
// primitive numbering (meshes, tube sets, point sets, spheres, planes; a
// scene without tubes and points keeps its ids), names and types, what a hit
// carries (point on the surface, normal, interpolated color, segment or point
// index, material) and the summary's counts. The intersection itself is in
// test_intersect (Capsule.*), watertightness in test_watertight
// (WatertightTubes), spawned rays in test_self_intersection, every structure
// in test_accel_conformance, bad input in test_invalid_input.
#include <gtest/gtest.h>

#include <cmath>

#include "rayscope/scene.h"
#include "rayscope/shapes.h"
#include "scene_test_util.h"
#include "test_util.h"

namespace {

using namespace rayscope;

// A mesh, two tube sets (one empty), a point set, a sphere and a plane.
Scene mixed_scene() {
  Scene s;
  s.materials.push_back(Material{});
  s.materials.back().name = "tube material";
  s.meshes.push_back(make_icosphere(Vec3(0.0f, 0.0f, -10.0f), 1.0f, 1));  // 80 triangles
  TubeSet line;
  line.name = "line";
  line.positions = {Vec3(-4, 0, 0), Vec3(0, 0, 0), Vec3(4, 0, 0)};
  line.segments = {{0, 1}, {1, 2}};
  line.radius = 1.0f;
  line.colors = {Color(1, 0, 0), Color(0, 1, 0), Color(0, 0, 1)};
  line.material = 1;
  s.tubes.push_back(line);
  TubeSet empty;
  empty.name = "empty";
  s.tubes.push_back(empty);
  PointSet dots;
  dots.name = "dots";
  dots.positions = {Vec3(0, 5, 0), Vec3(3, 5, 0)};
  dots.radii = {0.5f, 1.0f};
  dots.colors = {Color(0.5f, 0.5f, 0), Color(0, 0.5f, 0.5f)};
  s.points.push_back(dots);
  s.spheres.push_back(Sphere{"ball", Vec3(0, -5, 0), 1.0f, 0});
  s.planes.push_back(Plane{"floor", Vec3(0, -20, 0), Vec3(0, 1, 0), 0});
  return s;
}

TEST(TubesAndPoints, ObjectsAndPrimitivesAreNumberedInOrder) {
  Scene s = mixed_scene();
  s.commit();
  ASSERT_EQ(s.object_count(), 6u);
  const ObjectType types[] = {ObjectType::Mesh,   ObjectType::Tubes,  ObjectType::Tubes,
                              ObjectType::Points, ObjectType::Sphere, ObjectType::Plane};
  const char* names[] = {"icosphere", "line", "empty", "dots", "ball", "floor"};
  for (uint32_t o = 0; o < 6; ++o) {
    EXPECT_EQ(s.object_type(o), types[o]) << o;
    EXPECT_EQ(s.object_name(o), names[o]) << o;
  }
  EXPECT_EQ(s.plane_object(0), 5u);
  // Primitives: 80 triangles, 2 segments, 2 points, 1 sphere.
  EXPECT_EQ(s.prim_object(79), 0u);
  EXPECT_EQ(s.prim_object(80), 1u);
  EXPECT_EQ(s.prim_in_object(81), 1u);
  EXPECT_EQ(s.prim_object(82), 3u);  // the empty tube set holds none
  EXPECT_EQ(s.prim_in_object(83), 1u);
  EXPECT_EQ(s.prim_object(84), 4u);
  EXPECT_EQ(s.prim_in_object(84), 0u);
  EXPECT_EQ(s.accel().records().size(), 85u);
  const SceneSummary& sum = s.summary();
  EXPECT_EQ(sum.triangles, 80u);
  EXPECT_EQ(sum.tube_segments, 2u);
  EXPECT_EQ(sum.tube_sets, 2u);
  EXPECT_EQ(sum.points, 2u);
  EXPECT_EQ(sum.point_sets, 1u);
  EXPECT_EQ(sum.spheres, 1u);
  EXPECT_TRUE(sum.warnings.empty());
  // Without tubes and points, the numbers are those of before.
  s.tubes.clear();
  s.points.clear();
  s.commit();
  EXPECT_EQ(s.object_type(1), ObjectType::Sphere);
  EXPECT_EQ(s.prim_object(80), 1u);
  EXPECT_EQ(s.plane_object(0), 2u);
}

TEST(TubesAndPoints, HitsCarryTheSurfaceNormalColorAndIndex) {
  Scene s = mixed_scene();
  s.commit();
  SurfaceHit h;
  // Down onto segment 1 (from (0,0,0) to (4,0,0)) a quarter along: color
  // 3/4 green + 1/4 blue, normal up, the point on top of the tube.
  ASSERT_TRUE(s.intersect(Ray{Vec3(1, 3, 0), Vec3(0, -1, 0), kInfinity}, h));
  EXPECT_EQ(h.t, 2.0f);
  EXPECT_EQ(h.object, 1u);
  EXPECT_EQ(h.prim, 1u);
  EXPECT_EQ(h.material, 1u);
  EXPECT_EQ(h.p, Vec3(1, 1, 0));
  EXPECT_EQ(h.ng, Vec3(0, 1, 0));
  EXPECT_EQ(h.ns, h.ng);
  EXPECT_EQ(h.bary, Vec3(0.75f, 0.25f, 0.0f));
  ASSERT_TRUE(h.has_vertex_color);
  EXPECT_EQ(h.vertex_color, Color(0, 0.75f, 0.25f));
  // Along the axis into the first cap: normal -x, the first end's color.
  ASSERT_TRUE(s.intersect(Ray{Vec3(-9, 0, 0), Vec3(1, 0, 0), kInfinity}, h));
  EXPECT_EQ(h.t, 4.0f);
  EXPECT_EQ(h.prim, 0u);
  EXPECT_EQ(h.ng, Vec3(-1, 0, 0));
  EXPECT_EQ(h.vertex_color, Color(1, 0, 0));
  // The error bound offsets spawned rays: one leaving the hit finds nothing
  // of the tube.
  EXPECT_FALSE(s.occluded(spawn_ray(h.p, h.p_error, h.ng, Vec3(-1, 0.3f, 0))));
  // A point: its own color and index, the set's material.
  ASSERT_TRUE(s.intersect(Ray{Vec3(3, 9, 0), Vec3(0, -1, 0), kInfinity}, h));
  EXPECT_EQ(h.t, 3.0f);
  EXPECT_EQ(h.object, 3u);
  EXPECT_EQ(h.prim, 1u);
  EXPECT_EQ(h.ng, Vec3(0, 1, 0));
  EXPECT_EQ(h.vertex_color, Color(0, 0.5f, 0.5f));
  // The sphere after them keeps its own material and no vertex color.
  ASSERT_TRUE(s.intersect(Ray{Vec3(0, -9, 0), Vec3(0, 1, 0), kInfinity}, h));
  EXPECT_EQ(h.object, 4u);
  EXPECT_EQ(h.prim, 0u);
  EXPECT_FALSE(h.has_vertex_color);
  // Shadow rays name the occluder's object (short of the floor, which any-hit
  // queries test first).
  uint32_t occluder = ~0u;
  ASSERT_TRUE(
      s.occluded(Ray{Vec3(3, 9, 0), Vec3(0, -1, 0), 4.0f}, NullTraversalObserver{}, &occluder));
  EXPECT_EQ(occluder, 3u);
}

TEST(TubesAndPoints, ASceneOfTubesAndPointsRendersWithoutNaN) {
  Scene s = rstest::mesh_scene(make_icosphere(Vec3(0.0f), 0.3f, 2));
  TubeSet helix;
  helix.name = "helix";
  for (int i = 0; i <= 60; ++i) {
    const float a = 0.25f * float(i);
    helix.positions.push_back(Vec3(std::cos(a), -1.0f + 0.04f * float(i), std::sin(a)));
    helix.colors.push_back(Color(float(i) / 60.0f, 0.2f, 1.0f - float(i) / 60.0f));
    if (i > 0) helix.segments.push_back({uint32_t(i - 1), uint32_t(i)});
  }
  helix.radius = 0.06f;
  s.tubes.push_back(helix);
  PointSet cloud;
  cloud.name = "cloud";
  rstest::Rng rng(9);
  for (int i = 0; i < 100; ++i) cloud.positions.push_back(rstest::to_f(1.5 * rng.in_unit_ball()));
  cloud.radius = 0.03f;
  s.points.push_back(cloud);
  const Framebuffer fb = rstest::render_scene(s, 64, 48, 1);
  EXPECT_EQ(rstest::count_nonfinite(fb), 0u);
}

}  // namespace
