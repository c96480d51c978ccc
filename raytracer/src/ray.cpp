#include "rayscope/ray.h"

namespace rayscope {

const char* to_string(RayKind kind) {
  switch (kind) {
    case RayKind::Primary:
      return "primary";
    case RayKind::Shadow:
      return "shadow";
    case RayKind::Reflection:
      return "reflection";
    case RayKind::Refraction:
      return "refraction";
  }
  return "unknown";
}

}  // namespace rayscope
