// Scenes far from the world's origin and at any scale, in the core (the
// default scene built in C++): moved by up to 1e7 with a local origin
// (Scene::origin, as the scene parser and the VTK module build it) it renders
// the image it renders at the origin; built in world coordinates it still
// renders without a non-finite value; scaled by 1e-5 and 1e5 it renders the
// same image. Scene and mesh files moved far away, through the front end that
// reads them with VTK: tests/vtk/test_vtk_far_origin.cpp.
#include <gtest/gtest.h>

#include <cstdio>

#include "image_compare.h"
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
using rstest::pixels_differing;
using rstest::psnr;
using rstest::render_scene;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

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

}  // namespace
