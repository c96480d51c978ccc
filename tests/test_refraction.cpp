// Optics of material.h: mirror reflection, Snell's law (refract), Fresnel
// reflectance and total internal reflection, against double-precision physics;
// then dielectrics in a scene: nested spheres render without NaN and without
// creating energy, and rays at and around the critical angle (within 48 ulps)
// both reflect totally and transmit, their ray trees within energy bounds.
//
// Tolerances: every quantity is a handful of float operations (< 16) on values
// of magnitude <= max(n1/n2, 1) (eta) and 1, so absolute errors are below
// gamma(16) * (1 + eta) ~ 1e-6 * (1 + eta). Where a quantity passes through a
// square root of a difference (cos_t = sqrt(1 - sin^2_t)), its absolute error
// is ~sqrt(eps) ~ 2.4e-4 very close to the critical angle; the checks that are
// sensitive to that keep away from the critical angle by 1e-3 rad, where the
// amplification is at most ~1/sqrt(2e-3) ~ 22.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "rayscope/integrator.h"
#include "rayscope/material.h"
#include "rayscope/recorder.h"
#include "rayscope/render.h"
#include "rayscope/replay.h"
#include "rayscope/scene.h"
#include "rayscope/shapes.h"
#include "scene_test_util.h"
#include "test_util.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

constexpr double kEps = double(kMachineEpsilon);

// Unit incident direction at angle theta to -n (in the plane of n and a random
// tangent), and the unit normal, both in float.
void incident(Rng& rng, double theta, Vec3& d, Vec3& n, DVec3& nd, DVec3& tangent) {
  nd = rng.unit_vector();
  n = glm::normalize(to_f(nd));
  nd = to_d(n);  // the exact float normal is the reference normal
  DVec3 t = glm::cross(nd, rng.unit_vector());
  tangent = glm::normalize(t);
  d = to_f(-std::cos(theta) * nd + std::sin(theta) * tangent);
}

// Fresnel in double: reflectance and (independently) transmittance from the
// amplitude transmission coefficients, and dR/dcos_t (for the error analysis).
// Returns false past the critical angle.
bool ref_fresnel(double cos_i, double n1, double n2, double& R, double& T, double* dR = nullptr,
                 double* cos_t_out = nullptr) {
  double sin_i = std::sqrt(std::max(0.0, 1 - cos_i * cos_i));
  double sin_t = n1 / n2 * sin_i;
  if (sin_t >= 1) {
    R = 1;
    T = 0;
    return false;
  }
  double cos_t = std::sqrt(1 - sin_t * sin_t);
  double rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
  double rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
  double ts = 2 * n1 * cos_i / (n1 * cos_i + n2 * cos_t);
  double tp = 2 * n1 * cos_i / (n2 * cos_i + n1 * cos_t);
  R = 0.5 * (rs * rs + rp * rp);
  T = (n2 * cos_t) / (n1 * cos_i) * 0.5 * (ts * ts + tp * tp);
  if (dR) {
    double ds = -2 * n1 * n2 * cos_i / std::pow(n1 * cos_i + n2 * cos_t, 2);
    double dp = -2 * n1 * n2 * cos_i / std::pow(n2 * cos_i + n1 * cos_t, 2);
    *dR = rs * ds + rp * dp;
  }
  if (cos_t_out) *cos_t_out = cos_t;
  return true;
}

TEST(Reflect, MirrorLaw) {
  Rng rng(1);
  for (int i = 0; i < 20000; ++i) {
    Vec3 n = glm::normalize(to_f(rng.unit_vector()));
    Vec3 d = to_f(rng.unit_vector() * rng.log_uniform(1e-3, 1e3));
    Vec3 r = reflect(d, n);
    double dl = glm::length(to_d(d));
    // Length preserved, normal component flipped, tangential kept. In units
    // of |d|: the dot, product and subtraction cost ~5 eps, and n is unit only
    // to ~3 eps after float normalisation, which the reflection doubles: 16.
    EXPECT_NEAR(glm::length(to_d(r)), dl, 16 * kEps * dl);
    EXPECT_NEAR(glm::dot(to_d(r), to_d(n)), -glm::dot(to_d(d), to_d(n)), 16 * kEps * dl);
    DVec3 dt = to_d(d) - glm::dot(to_d(d), to_d(n)) * to_d(n);
    DVec3 rt = to_d(r) - glm::dot(to_d(r), to_d(n)) * to_d(n);
    EXPECT_LE(rstest::max_abs(dt - rt), 16 * kEps * dl);
  }
}

TEST(Refract, SnellsLawCoplanarUnitLength) {
  // n1 sin(theta_i) = n2 sin(theta_t), checked as the stronger vector form:
  // the tangential components satisfy n1 d_t = n2 t_t (this is Snell's law and
  // coplanarity at once); t leaves on the other side and is unit length.
  Rng rng(2);
  int refracted = 0, tir = 0;
  double worst = 0;
  for (int i = 0; i < 50000; ++i) {
    double n1 = rng.uniform(1.0, 2.5), n2 = rng.uniform(1.0, 2.5);
    if (rng.coin()) n1 = 1.0;
    float f1 = rstest::round_f(n1), f2 = rstest::round_f(n2);
    Vec3 d, n;
    DVec3 nd, tg;
    incident(rng, rng.uniform(0, 0.5 * kPi), d, n, nd, tg);
    // The function treats d as unit; the reference uses the exact direction of
    // the float d.
    DVec3 dd = glm::normalize(to_d(d));
    double cos_i = -glm::dot(dd, nd);
    if (cos_i <= 0) continue;
    double sin_i = glm::length(glm::cross(dd, nd));
    double sin_t_exact = double(f1) / f2 * sin_i;
    Vec3 t;
    bool ok = refract(d, n, f1, f2, t);
    if (std::abs(sin_t_exact - 1) < 1e-5) continue;  // at the critical angle either is right
    ASSERT_EQ(ok, sin_t_exact < 1) << "n1=" << f1 << " n2=" << f2 << " sin_t=" << sin_t_exact;
    if (!ok) {
      ++tir;
      continue;
    }
    ++refracted;
    DVec3 td = to_d(t);
    double eta = double(f1) / f2;
    double tol = 16 * kEps * (1 + eta);
    // Near the critical angle cos_t is the square root of a small difference:
    // sin^2_t = eta^2 (1 - cos_i^2) carries an absolute error of ~(4 eta^2 + 1)
    // eps (cos_i from a dot of float unit vectors: ~3 eps), which the square
    // root turns into an error of that / (2 cos_t) in cos_t (doubled here).
    double cos_t = std::sqrt(1 - sin_t_exact * sin_t_exact);
    double tol_ct = tol + (4 * eta * eta + 1) * kEps / std::max(cos_t, 1e-4);
    EXPECT_NEAR(glm::length(td), 1.0, tol_ct);
    EXPECT_LT(glm::dot(td, nd), 0.0);
    DVec3 d_tan = dd - glm::dot(dd, nd) * nd, t_tan = td - glm::dot(td, nd) * nd;
    DVec3 mismatch = double(f1) * d_tan - double(f2) * t_tan;
    EXPECT_LE(rstest::max_abs(mismatch), double(f2) * tol)
        << "Snell violated: n1 sin_i=" << f1 * sin_i << " n2 sin_t=" << f2 * glm::length(t_tan);
    EXPECT_NEAR(double(f1) * sin_i, double(f2) * glm::length(glm::cross(td, nd)),
                double(f2) * tol_ct);
    EXPECT_NEAR(-glm::dot(td, nd), cos_t, tol_ct);
    // Coplanar with d and n.
    DVec3 plane_n = glm::cross(dd, nd);
    if (glm::length(plane_n) > 1e-3) {
      EXPECT_LE(std::abs(glm::dot(td, glm::normalize(plane_n))), tol);
    }
    worst = std::max(worst, rstest::max_abs(mismatch) / (double(f2) * kEps * (1 + eta)));
  }
  std::printf(
      "snell: %d refracted, %d total internal reflections; worst tangential mismatch "
      "%.2f eps (limit 16)\n",
      refracted, tir, worst);
  EXPECT_GT(refracted, 30000);
  EXPECT_GT(tir, 2000);
}

TEST(Refract, NormalIncidenceGoesStraightThrough) {
  Rng rng(3);
  for (int i = 0; i < 1000; ++i) {
    Vec3 n = glm::normalize(to_f(rng.unit_vector()));
    Vec3 t;
    float n2 = rstest::round_f(rng.uniform(1.0, 3.0));
    ASSERT_TRUE(refract(-n, n, 1.0f, n2, t));
    EXPECT_LE(rstest::max_abs(to_d(t) + to_d(n)), 16 * kEps * (1 + 1.0 / n2));
    ASSERT_TRUE(refract(-n, n, n2, 1.0f, t));  // never TIR at normal incidence
    EXPECT_LE(rstest::max_abs(to_d(t) + to_d(n)), 16 * kEps * (1 + n2));
  }
}

TEST(Fresnel, RangeEnergyConservationAndDoubleReference) {
  // R in [0, 1]; R + T = 1 with T from the transmission amplitudes (an
  // independent formula: energy conservation), to within the error of the
  // float computation: 32 eps for a dozen operations on O(1) values, plus the
  // error of cos_t = sqrt(1 - sin^2_t), (4 eta^2 + 1) eps / cos_t (see the
  // Snell test), times |dR/dcos_t|. Away from the critical angle that is a
  // few 1e-6; cases with cos_t < 1e-4 (amplification > 1e4) are left out.
  Rng rng(4);
  double worst = 0;
  int checked = 0;
  for (int i = 0; i < 100000; ++i) {
    float n1 = rstest::round_f(rng.uniform(1.0, 3.0)), n2 = rstest::round_f(rng.uniform(1.0, 3.0));
    if (i % 4 == 0) n1 = 1.0f;
    if (i % 4 == 1) n2 = 1.0f;
    float cos_i = rstest::round_f(i % 10 == 0 ? rng.log_uniform(1e-6, 1.0) : rng.uniform(0, 1));
    float R = fresnel_dielectric(cos_i, n1, n2);
    ASSERT_GE(R, 0.0f);
    ASSERT_LE(R, 1.0f);
    double Rr, Tr, dR = 0, cos_t = 0;
    bool below = ref_fresnel(cos_i, n1, n2, Rr, Tr, &dR, &cos_t);
    double sin_t = double(n1) / n2 * std::sqrt(1 - double(cos_i) * cos_i);
    if (std::abs(sin_t - 1) < 1e-7) continue;  // at the critical angle
    if (!below) {
      EXPECT_EQ(R, 1.0f) << "TIR: n1=" << n1 << " n2=" << n2 << " cos_i=" << cos_i;
      continue;
    }
    if (cos_t < 1e-4) continue;
    ++checked;
    EXPECT_NEAR(Rr + Tr, 1.0, 1e-12);  // the reference itself is consistent
    double eta = double(n1) / n2;
    double tol = 32 * kEps + std::abs(dR) * 2 * (4 * eta * eta + 1) * kEps / cos_t;
    EXPECT_NEAR(double(R) + Tr, 1.0, tol)
        << "n1=" << n1 << " n2=" << n2 << " cos_i=" << cos_i << " R=" << R << " T=" << Tr;
    worst = std::max(worst, std::abs(double(R) + Tr - 1.0) / tol);
  }
  EXPECT_GT(checked, 50000);
  std::printf("fresnel: worst |R + T - 1| = %.3g of the tolerance\n", worst);
}

TEST(Fresnel, NormalIncidenceAndKnownValues) {
  for (float n1 : {1.0f, 1.33f, 1.5f, 2.4f})
    for (float n2 : {1.0f, 1.33f, 1.5f, 2.4f}) {
      double r0 = (double(n1) - n2) / (double(n1) + n2);
      // A few float operations on O(1) values: 8 eps.
      EXPECT_NEAR(fresnel_dielectric(1.0f, n1, n2), r0 * r0, 8 * kEps) << n1 << " -> " << n2;
    }
  // Air to glass at normal incidence: 4%.
  EXPECT_NEAR(fresnel_dielectric(1.0f, 1.0f, 1.5f), 0.04, 1e-6);
  // Brewster's angle tan(theta_B) = n2 / n1: the p-polarised part vanishes, R
  // is half the s reflectance.
  double tb = std::atan(1.5), ci = std::cos(tb),
         ct = std::sqrt(1 - std::pow(std::sin(tb) / 1.5, 2));
  double rs = (ci - 1.5 * ct) / (ci + 1.5 * ct);
  EXPECT_NEAR(fresnel_dielectric(float(ci), 1.0f, 1.5f), 0.5 * rs * rs, 1e-6);
  // Grazing incidence reflects everything.
  EXPECT_NEAR(fresnel_dielectric(0.0f, 1.0f, 1.5f), 1.0f, 1e-6);
  // Reciprocity: R(theta_i, n1 -> n2) == R(theta_t, n2 -> n1).
  Rng rng(5);
  for (int i = 0; i < 10000; ++i) {
    double n1 = rng.uniform(1, 2.5), n2 = rng.uniform(1, 2.5);
    double th = rng.uniform(0, 1.5);
    double st = n1 / n2 * std::sin(th);
    if (st >= 0.999) continue;
    float a =
        fresnel_dielectric(rstest::round_f(std::cos(th)), rstest::round_f(n1), rstest::round_f(n2));
    float b = fresnel_dielectric(rstest::round_f(std::sqrt(1 - st * st)), rstest::round_f(n2),
                                 rstest::round_f(n1));
    EXPECT_NEAR(a, b, 1e-5) << n1 << " " << n2 << " " << th;
  }
}

TEST(TotalInternalReflection, JustPastAndJustBeforeTheCriticalAngle) {
  // Going from the denser medium: past the critical angle refract() fails and
  // the reflectance is exactly 1; just before it (by 1e-5..0.3 rad, which
  // changes sin^2(theta_t) by > 1e-5, far above float resolution) refraction
  // happens and R < 1. Angles are measured in double on the float direction.
  Rng rng(6);
  int past = 0, before = 0;
  for (int i = 0; i < 20000; ++i) {
    float n1 = rstest::round_f(rng.uniform(1.05, 2.5)), n2 = 1.0f;
    if (i % 2) n2 = rstest::round_f(rng.uniform(1.0, double(n1) / 1.05));
    double crit = std::asin(double(n2) / n1);
    EXPECT_NEAR(critical_angle(n1, n2), crit, 4e-7 / std::cos(crit));
    double delta = rng.log_uniform(1e-5, 0.3);
    bool want_past = rng.coin();
    double theta = want_past ? crit + delta : crit - delta;
    if (theta >= 0.5 * kPi || theta <= 0) continue;
    Vec3 d, n;
    DVec3 nd, tg;
    incident(rng, theta, d, n, nd, tg);
    // Actual angle of the rounded float direction.
    double th = std::acos(std::clamp(-glm::dot(glm::normalize(to_d(d)), nd), -1.0, 1.0));
    if (std::abs(th - crit) < 5e-6) continue;
    bool is_past = th > crit;
    Vec3 t;
    bool ok = refract(d, n, n1, n2, t);
    float cos_i = -glm::dot(d, n);
    float R = fresnel_dielectric(cos_i, n1, n2);
    if (is_past) {
      ++past;
      EXPECT_FALSE(ok) << "n1=" << n1 << " n2=" << n2 << " theta-crit=" << th - crit;
      EXPECT_EQ(R, 1.0f) << "n1=" << n1 << " n2=" << n2 << " theta-crit=" << th - crit;
    } else {
      ++before;
      EXPECT_TRUE(ok) << "n1=" << n1 << " n2=" << n2 << " theta-crit=" << th - crit;
      EXPECT_LT(R, 1.0f) << "n1=" << n1 << " n2=" << n2 << " theta-crit=" << th - crit;
      if (ok) {
        EXPECT_LT(glm::dot(t, n), 0.0f);
      }
    }
  }
  EXPECT_GT(past, 8000);
  EXPECT_GT(before, 8000);
  // From the rarer medium there is no critical angle.
  EXPECT_EQ(critical_angle(1.0f, 1.5f), 0.5f * kPi);
  EXPECT_EQ(critical_angle(1.5f, 1.5f), 0.5f * kPi);
  Vec3 t;
  EXPECT_TRUE(refract(glm::normalize(Vec3(1.0f, -1e-3f, 0.0f)), Vec3(0, 1, 0), 1.0f, 1.5f, t));
  EXPECT_LT(fresnel_dielectric(1e-3f, 1.0f, 1.5f), 1.0f);
}

// ===========================================================================
// Dielectrics in a scene: total internal reflection, nested spheres, energy
// ===========================================================================

using rstest::count_nonfinite;
using rstest::finite_color;
using rstest::render_scene;
using rstest::stress_scale;

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
    for (int i = 0; i <= int(rstest::stress_scaled(4000)); ++i) {
      bool tir;
      trace(c, float(0.5 * M_PI * i / double(rstest::stress_scaled(4000))) * (1.0f - 1e-7f),
            glm::normalize(glm::cross(to_d(c.normal), rng.unit_vector())), tir);
    }
  }
  std::printf("%zu rays traced, %llu total internal reflections\n", traced,
              (unsigned long long)counters.total_internal_reflections);
  EXPECT_EQ(bad, 0u);
}

}  // namespace
