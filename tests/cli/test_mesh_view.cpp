// frame_bounds(), the camera `rayscope render MESH_FILE` views a mesh with: the
// whole box is in the picture, its bounding sphere just fits the narrower field
// of view, and the view direction, up vector and projection are kept.
// (fit_bounds(), which it calls, is also the VTK module's ResetCamera: tests/vtk.)
#include <gtest/gtest.h>

#include <cmath>

#include "rayscope/camera.h"

namespace {

using namespace rayscope;

// Where a point lands on the image plane, in units of the half image height
// (x within +-aspect and y within +-1 is in the picture).
glm::vec2 project(const Camera& c, float tan_half, const Vec3& p) {
  Vec3 v = p - c.eye;
  float z = glm::dot(v, c.forward());
  glm::vec2 s(glm::dot(v, c.right()), glm::dot(v, c.up_vector()));
  return c.parallel ? s / c.parallel_scale : s / (z * tan_half);
}

TEST(MeshView, FrameBoundsShowsTheWholeBoxAndFillsTheNarrowerSide) {
  const Bounds3 box(Vec3(-3.0f, 10.0f, 2.0f), Vec3(1.0f, 12.0f, 2.5f));
  const float radius = 0.5f * glm::length(box.extent());
  for (bool parallel : {false, true})
    for (float aspect : {0.5f, 1.0f, 2.0f}) {
      Camera view;
      view.eye = Vec3(1.0f, 2.0f, 3.0f);
      view.look_at = Vec3(1.0f, 1.0f, 1.0f);
      view.vfov_degrees = 30.0f;
      view.parallel = parallel;
      Camera c = frame_bounds(box, aspect, view);
      c.prepare(int(100 * aspect), 100);
      SCOPED_TRACE(testing::Message() << "parallel " << parallel << " aspect " << aspect);
      EXPECT_EQ(c.look_at, box.center());
      EXPECT_NEAR(
          glm::dot(glm::normalize(c.eye - c.look_at), glm::normalize(view.eye - view.look_at)),
          1.0f, 1e-6f);
      EXPECT_EQ(c.up, view.up);
      EXPECT_EQ(c.vfov_degrees, view.vfov_degrees);
      const float tan_half = std::tan(0.5f * glm::radians(c.vfov_degrees));
      for (int k = 0; k < 8; ++k) {
        Vec3 corner((k & 1) ? box.hi.x : box.lo.x, (k & 2) ? box.hi.y : box.lo.y,
                    (k & 4) ? box.hi.z : box.lo.z);
        glm::vec2 s = project(c, tan_half, corner);
        EXPECT_LE(std::abs(s.x), aspect * 1.0001f) << k;
        EXPECT_LE(std::abs(s.y), 1.0001f) << k;
        EXPECT_GT(glm::dot(corner - c.eye, c.forward()), 0.0f) << k;  // in front of the eye
      }
      // The bounding sphere touches the narrower side: its angular radius (or
      // its radius, parallel) equals the half field of view of that side.
      const float half_narrow = std::min(aspect, 1.0f);
      if (parallel) {
        EXPECT_NEAR(radius / c.parallel_scale, half_narrow, 1e-5f);
      } else {
        float d = glm::length(c.eye - c.look_at);
        EXPECT_NEAR(std::tan(std::asin(radius / d)) / tan_half, half_narrow, 1e-5f);
      }
    }
}

TEST(MeshView, FrameBoundsOfEmptyOrPointBoxes) {
  // An empty box frames the unit sphere at the origin, looking along the view.
  Camera c = frame_bounds(Bounds3(), 1.0f);
  EXPECT_EQ(c.look_at, Vec3(0.0f));
  const float d = 1.0f / std::sin(0.5f * glm::radians(Camera{}.vfov_degrees));
  EXPECT_NEAR(glm::length(c.eye - Vec3(0.0f, 0.0f, d)), 0.0f, 1e-5f);
  // A point: the sphere of radius 0.5 around it, as vtkRenderer::ResetCamera
  // frames a point; coinciding eye and look_at look along -z.
  Camera same;
  same.eye = same.look_at = Vec3(4.0f);
  c = frame_bounds(Bounds3(Vec3(7.0f, 8.0f, 9.0f)), 1.0f, same);
  EXPECT_EQ(c.look_at, Vec3(7.0f, 8.0f, 9.0f));
  EXPECT_NEAR(glm::length(c.eye - Vec3(7.0f, 8.0f, 9.0f + 0.5f * d)), 0.0f, 1e-5f);
}

TEST(MeshView, FrameBoundsRepairsAnUpAlongTheView) {
  // An up vector parallel to the view direction is replaced (+y, or -z for a
  // view along y), so that the fitted camera can be prepared.
  Camera view;
  view.eye = Vec3(0.0f, 0.0f, 5.0f);
  view.up = Vec3(0.0f, 0.0f, 2.0f);
  Camera c = frame_bounds(Bounds3(Vec3(-1.0f), Vec3(1.0f)), 1.0f, view);
  EXPECT_EQ(c.up, Vec3(0.0f, 1.0f, 0.0f));
  view.eye = Vec3(0.0f, 5.0f, 0.0f);
  view.up = Vec3(0.0f, 1.0f, 0.0f);
  c = frame_bounds(Bounds3(Vec3(-1.0f), Vec3(1.0f)), 1.0f, view);
  EXPECT_EQ(c.up, Vec3(0.0f, 0.0f, -1.0f));
  EXPECT_NO_THROW(c.prepare(10, 10));
}

}  // namespace
