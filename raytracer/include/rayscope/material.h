// Materials and the optics of the lecture: Phong / Blinn-Phong local
// illumination, mirror reflection, Snell's law, Fresnel weights and total
// internal reflection.
#pragma once

#include <string>

#include "rayscope/math.h"

namespace rayscope {

enum class ShadingModel { Phong, BlinnPhong };

struct Material {
  std::string name = "default";
  Color color{0.8f};  ///< Diffuse (and ambient) color.
  float ambient = 0.1f;
  float diffuse = 0.9f;
  float specular = 0.0f;
  Color specular_color{1.0f};
  float shininess = 32.0f;    ///< Phong exponent.
  float reflectivity = 0.0f;  ///< Weight of the mirror reflection.
  float transparency = 0.0f;  ///< Weight of the dielectric (Fresnel-split reflect/refract).
  float ior = 1.5f;           ///< Index of refraction of the inside.
  ShadingModel model = ShadingModel::BlinnPhong;
  /// Optional 3D checkerboard: color alternates with checker_color in cubes of
  /// side checker_size (world units).
  bool checker = false;
  Color checker_color{0.1f};
  float checker_size = 1.0f;

  bool reflective() const { return reflectivity > 0.0f; }
  bool refractive() const { return transparency > 0.0f; }
};

/// Mirror reflection of incident direction d about unit normal n (lecture: "reflect
/// ray across normal"). |result| == |d|.
inline Vec3 reflect(const Vec3& d, const Vec3& n) {
  return d - 2.0f * glm::dot(d, n) * n;
}

/// Refraction of unit incident direction d through a surface with unit normal n
/// facing the incident side (dot(d, n) < 0), going from index n1 to n2 (Snell:
/// n1 sin(theta_i) = n2 sin(theta_t)). Returns false on total internal reflection.
inline bool refract(const Vec3& d, const Vec3& n, float n1, float n2, Vec3& t) {
  float eta = n1 / n2;
  float cos_i = -glm::dot(d, n);
  float sin2_t = eta * eta * std::max(0.0f, 1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) return false;
  float cos_t = std::sqrt(1.0f - sin2_t);
  t = eta * d + (eta * cos_i - cos_t) * n;
  return true;
}

/// Unpolarised Fresnel reflectance for light arriving at cos_i (>= 0) from index
/// n1 onto index n2. 1 past the critical angle (total internal reflection).
/// The transmitted weight is 1 - fresnel_dielectric(...).
inline float fresnel_dielectric(float cos_i, float n1, float n2) {
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  float sin_i = std::sqrt(std::max(0.0f, 1.0f - cos_i * cos_i));
  float sin_t = n1 / n2 * sin_i;
  if (sin_t >= 1.0f) return 1.0f;
  float cos_t = std::sqrt(std::max(0.0f, 1.0f - sin_t * sin_t));
  float rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
  float rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
  return std::clamp(0.5f * (rs * rs + rp * rp), 0.0f, 1.0f);
}

/// Critical angle (radians) for light going from n1 into n2 < n1; pi/2 otherwise.
inline float critical_angle(float n1, float n2) {
  return n2 < n1 ? std::asin(n2 / n1) : 0.5f * kPi;
}

namespace checker_detail {
/// The cell index of world coordinate `world` in cells of side `size`. A point
/// on a cell face (a floor at y = 0, any plane at a multiple of the size)
/// belongs to the cell above it: its world coordinate, rebuilt from the
/// rounded local one, lies a few float ulps of the face either side, and
/// flooring that would flip the face's color with the choice of origin or a
/// last-bit difference. `tol` is that rounding band in cells.
inline double cell(double world, double size, double tol) {
  const double u = world / size, r = std::round(u);
  return std::abs(u - r) <= tol ? r : std::floor(u);
}
/// +1 for an even cell index, -1 for an odd one. Converting to an integer
/// type instead is undefined beyond the type's range and for NaN (found by
/// fuzz_scene_parser: a checker size of 1e-30); doubles of magnitude >= 2^53
/// are even integers.
inline double parity_sign(double cell_index) {
  const bool odd = std::abs(cell_index) < 9007199254740992.0 && std::fmod(cell_index, 2.0) != 0.0;
  return odd ? -1.0 : 1.0;
}
/// The integral from 0 to u of the square wave (-1)^floor(t): a triangle wave
/// of period 2 rising from 0 at even integers to 1 at odd ones.
inline double square_wave_integral(double u) {
  const double f = u - 2.0 * std::floor(0.5 * u);
  return f <= 1.0 ? f : 2.0 - f;
}
/// The mean of the square wave (-1)^floor(t / size) over [world - half,
/// world + half]: the per-axis factor of the box-filtered checker. A
/// footprint within the rounding band `tol` (in cells), or one that lies in
/// a single cell, gives the point value exactly (+1 or -1).
inline double box_mean(double world, double half, double size, double tol) {
  const double point = parity_sign(cell(world, size, tol));
  if (!(half / size > tol)) return point;  // also NaN footprints
  const double u0 = (world - half) / size, u1 = (world + half) / size;
  if (!(u1 > u0) || !std::isfinite(u0) || !std::isfinite(u1) || std::floor(u0) == std::floor(u1))
    return point;
  const double m = (square_wave_integral(u1) - square_wave_integral(u0)) / (u1 - u0);
  return std::clamp(m, -1.0, 1.0);
}
}  // namespace checker_detail

/// Surface color of a material at the scene-local point p of a scene whose
/// local origin is `origin` (Scene::origin): the checkerboard is evaluated in
/// world space, in double precision, so it stays where it is in the world
/// whatever origin the scene is traced around.
inline Color material_color(const Material& m, const Vec3& p, const DVec3& origin) {
  if (!m.checker) return m.color;
  using namespace checker_detail;
  const double size = double(m.checker_size);
  const double tol = 4.0 * double(kMachineEpsilon) * double(max_component(glm::abs(p))) / size;
  const DVec3 w = DVec3(p) + origin;
  const double s = parity_sign(cell(w.x, size, tol)) * parity_sign(cell(w.y, size, tol)) *
                   parity_sign(cell(w.z, size, tol));
  return s < 0.0 ? m.checker_color : m.color;
}

/// The box-filtered surface color: the mean of material_color() over the
/// axis-aligned world box centred on p with half-sides `half_width` (the
/// bounding box of a pixel's footprint, footprint_half_width()). The 3D
/// checker is (a + b) / 2 + (a - b) / 2 * s(x) s(y) s(z) with s the square
/// wave +-1 of each axis, so its mean over a box is the same expression with
/// each s replaced by its mean over the box's side, a closed form (the
/// integral of a square wave is a triangle wave). A zero footprint, or one
/// inside a single cell, gives material_color() exactly.
inline Color material_color_filtered(const Material& m, const Vec3& p, const Vec3& half_width,
                                     const DVec3& origin) {
  if (!m.checker) return m.color;
  using namespace checker_detail;
  const double size = double(m.checker_size);
  const double tol = 4.0 * double(kMachineEpsilon) * double(max_component(glm::abs(p))) / size;
  const DVec3 w = DVec3(p) + origin;
  const double s = box_mean(w.x, double(half_width.x), size, tol) *
                   box_mean(w.y, double(half_width.y), size, tol) *
                   box_mean(w.z, double(half_width.z), size, tol);
  if (s == 1.0) return m.color;
  if (s == -1.0) return m.checker_color;
  const float f = float(s);
  return 0.5f * (m.color + m.checker_color) + (0.5f * f) * (m.color - m.checker_color);
}

/// Phong / Blinn-Phong factors for light arriving from unit direction l, seen
/// from unit direction v, at unit normal n: the diffuse factor max(0, n.l) and the
/// specular factor (r.v)^shininess (Phong) or (n.h)^shininess (Blinn-Phong).
struct PhongTerms {
  float diffuse = 0.0f;
  float specular = 0.0f;
};
inline PhongTerms phong_terms(const Material& m, const Vec3& n, const Vec3& l, const Vec3& v) {
  PhongTerms t;
  float ndotl = glm::dot(n, l);
  if (ndotl <= 0.0f) return t;
  t.diffuse = ndotl;
  if (m.specular > 0.0f) {
    float s;
    if (m.model == ShadingModel::Phong) {
      s = glm::dot(reflect(-l, n), v);
    } else {
      Vec3 h = l + v;
      float hl = glm::length(h);
      s = hl > 0.0f ? glm::dot(n, h) / hl : 0.0f;
    }
    t.specular = s > 0.0f ? std::pow(s, m.shininess) : 0.0f;
  }
  return t;
}

}  // namespace rayscope
