// Point and directional lights. Point lights are attenuated as in VTK and
// OpenGL: 1 / (constant + linear d + quadratic d^2), by default not at all.
#pragma once

#include <string>

#include "rayscope/camera.h"
#include "rayscope/math.h"

namespace rayscope {

struct Light {
  enum class Type { Point, Directional };
  Type type = Type::Point;
  std::string name;
  Vec3 position{0.0f, 10.0f, 0.0f};   ///< Point lights.
  Vec3 direction{0.0f, -1.0f, 0.0f};  ///< Directional lights: direction light travels.
  Color color{1.0f};
  float intensity = 1.0f;
  Vec3 attenuation{1.0f, 0.0f, 0.0f};  ///< constant, linear, quadratic (point lights)
  bool casts_shadows = true;

  Color radiance_at(float distance) const {
    Color c = color * intensity;
    if (type == Type::Point) {
      float a = attenuation.x + attenuation.y * distance + attenuation.z * distance * distance;
      if (a > 0.0f) c /= a;
    }
    return c;
  }
};

/// A headlight: a light at the eye, which casts no shadow the eye can see.
/// For a central projection, a point light at camera.eye without
/// attenuation; for a parallel projection, whose eye is at infinity, a
/// directional light along the view. Shadow rays toward it are traced as
/// toward any light, so ray trees show them and a mirror can show the shadows
/// it casts; from a surface the eye sees they are never blocked. (VTK's
/// headlight shines along the view everywhere; traced with shadows, such a
/// light darkens every surface behind a depth edge of a perspective view,
/// bands VTK's own view never shows.) Named "headlight".
inline Light headlight(const Camera& camera, const Color& color = Color(1.0f),
                       float intensity = 1.0f) {
  Light l;
  l.name = "headlight";
  if (camera.parallel) {
    l.type = Light::Type::Directional;
    l.direction = glm::normalize(camera.look_at - camera.eye);
  } else {
    l.type = Light::Type::Point;
    l.position = camera.eye;
  }
  l.color = color;
  l.intensity = intensity;
  return l;
}

/// The largest light intensity a light may have.
inline constexpr double kMaxLightIntensity = 1e30;

/// What is wrong with a light's values, in words ("intensity must be ..."), or
/// "" for a usable light: a point light's position finite; a directional
/// light's direction finite and non-zero; color components finite and >= 0;
/// intensity in [0, kMaxLightIntensity]; attenuation coefficients finite,
/// >= 0 and not all zero. `v` is the position of a point light, the direction
/// of a directional one. The values are double as VTK's lights and a scene
/// file's positions are; those a Light holds in float are checked as float.
std::string light_error(Light::Type type, const DVec3& v, const DVec3& color, double intensity,
                        const DVec3& attenuation);

}  // namespace rayscope
