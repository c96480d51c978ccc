// Helpers of the tests that render or trace whole scenes (test_invalid_input,
// test_grazing, test_far_from_origin, test_refraction): render a scene with
// given settings, count non-finite pixels, a mesh in front of a camera.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

#include "rayscope/render.h"
#include "rayscope/scene.h"
#include "test_util.h"

namespace rstest {

inline bool finite_color(const rayscope::Color& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
}

inline size_t count_nonfinite(const rayscope::Framebuffer& fb) {
  return size_t(std::count_if(fb.color.begin(), fb.color.end(),
                              [](const rayscope::Color& c) { return !finite_color(c); }));
}

inline rayscope::Framebuffer render_scene(rayscope::Scene scene, int width, int height, int spp,
                                          int max_depth = 5, float min_contribution = 1e-3f,
                                          rayscope::RayCounters* counters = nullptr) {
  using namespace rayscope;
  scene.commit();
  RenderSettings rs;
  rs.width = width;
  rs.height = height;
  rs.samples = spp;
  rs.max_depth = max_depth;
  rs.min_contribution = min_contribution;
  return render(scene, rs, counters);
}

// A mesh in front of a camera on +z, lit by a point and a directional light,
// over a floor plane.
inline rayscope::Scene mesh_scene(rayscope::TriangleMesh mesh) {
  using namespace rayscope;
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

}  // namespace rstest
