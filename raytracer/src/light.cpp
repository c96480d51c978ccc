#include "rayscope/light.h"

#include <cmath>

namespace rayscope {

std::string light_error(Light::Type type, const DVec3& v, const DVec3& color, double intensity,
                        const DVec3& attenuation) {
  if (type == Light::Type::Point) {
    // Positions stay in double until they are made scene-local.
    if (!(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)))
      return "position must be finite";
  } else {
    const Vec3 d(v);
    if (!all_finite(d)) return "direction must be finite";
    if (d == Vec3(0.0f)) return "direction must be non-zero";
  }
  const Vec3 c(color);
  if (!all_finite(c) || c.r < 0.0f || c.g < 0.0f || c.b < 0.0f)
    return "color components must be finite and >= 0";
  const float i = float(intensity);  // a Light holds it in float
  if (!(i >= 0.0f && i <= float(kMaxLightIntensity))) return "intensity must be in [0, 1e30]";
  const Vec3 a(attenuation);
  if (!all_finite(a) || a.x < 0.0f || a.y < 0.0f || a.z < 0.0f || a == Vec3(0.0f))
    return "attenuation coefficients must be finite, >= 0 and not all zero";
  return {};
}

}  // namespace rayscope
