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

/// Surface color of a material at the scene-local point p of a scene whose
/// local origin is `origin` (Scene::origin): the checkerboard is evaluated in
/// world space, in double precision, so it stays where it is in the world
/// whatever origin the scene is traced around.
inline Color material_color(const Material& m, const Vec3& p, const DVec3& origin) {
  if (!m.checker) return m.color;
  // The cell of each world coordinate. A point on a cell face (a floor at
  // y = 0, any plane at a multiple of the size) belongs to the cell above
  // it: its world coordinate, rebuilt from the rounded local one, lies a few
  // float ulps of p either side of the face, and flooring that would flip
  // the face's color with the choice of origin or a last-bit difference.
  const double size = double(m.checker_size);
  const double tol = 4.0 * double(kMachineEpsilon) * double(max_component(glm::abs(p))) / size;
  auto cell = [&](double world) {
    const double u = world / size, r = std::round(u);
    return std::abs(u - r) <= tol ? r : std::floor(u);
  };
  const DVec3 w = DVec3(p) + origin;
  // The parity of each cell index. Converting to an integer type instead is
  // undefined beyond the type's range and for NaN (found by fuzz_scene_parser:
  // a checker size of 1e-30); doubles of magnitude >= 2^53 are even integers.
  auto odd = [](double f) { return std::abs(f) < 9007199254740992.0 && std::fmod(f, 2.0) != 0.0; };
  return (odd(cell(w.x)) != odd(cell(w.y))) != odd(cell(w.z)) ? m.checker_color : m.color;
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
