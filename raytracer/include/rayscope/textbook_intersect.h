// The lecture's intersection tests as it writes them, with every quantity a
// student computes by hand: for `rayscope inspect` and the viewer, which show
// them beside the hit the robust tests found (intersect.h), never for
// rendering. In double precision, so that what they show is the formula's
// value, not float rounding.
//
// The ray is P = P_r + λ t_r (λ >= 0), so λ is the distance along t_r as the
// ray stores it, the renderer's t.
#pragma once

#include "rayscope/math.h"

namespace rayscope {

/// Ray-plane: (P - P_0) · n = 0 gives λ = (P_0 - P_r) · n / (t_r · n), which
/// exists when t_r · n != 0 (the ray is not parallel to the plane).
struct TextbookPlane {
  double tr_dot_n = 0.0;
  double lambda = 0.0;  ///< Meaningful when tr_dot_n != 0.
  bool hit() const { return tr_dot_n != 0.0 && lambda >= 0.0; }
};
TextbookPlane textbook_plane(const Vec3& pr, const Vec3& tr, const Vec3& p0, const Vec3& n);

/// Ray-triangle: the ray-plane test on the plane of P_0, P_1, P_2 with
/// t_1 = P_1 - P_0, t_2 = P_2 - P_0, n = t_1 × t_2, then P = P_0 + λ_1 t_1 +
/// λ_2 t_2 solved for λ_1 and λ_2 at the plane's hit; P is in the triangle when
/// λ_1, λ_2 >= 0 and λ_1 + λ_2 <= 1.
struct TextbookTriangle {
  DVec3 t1{0.0}, t2{0.0}, n{0.0};
  TextbookPlane plane;
  double lambda1 = 0.0, lambda2 = 0.0;
  bool inside() const {
    return plane.hit() && lambda1 >= 0.0 && lambda2 >= 0.0 && lambda1 + lambda2 <= 1.0;
  }
};
TextbookTriangle textbook_triangle(const Vec3& pr, const Vec3& tr, const Vec3& p0, const Vec3& p1,
                                   const Vec3& p2);

/// Ray-sphere: (P_r + λ t_r - c)² - r² = 0 is the quadratic
/// a λ² + b λ + c' = 0 with a = t_r², b = 2 t_r · (P_r - c) and
/// c' = (P_r - c)² - r²; real roots when the discriminant b² - 4 a c' >= 0.
struct TextbookSphere {
  double a = 0.0, b = 0.0, c = 0.0;
  double discriminant = 0.0;
  double lambda_near = 0.0, lambda_far = 0.0;  ///< The roots, when discriminant >= 0.
  bool real_roots() const { return discriminant >= 0.0 && a > 0.0; }
  /// The λ the ray takes: the nearer root at or beyond 0, else the farther
  /// (from inside the sphere); -1 when neither is.
  double lambda() const {
    if (!real_roots()) return -1.0;
    return lambda_near >= 0.0 ? lambda_near : lambda_far >= 0.0 ? lambda_far : -1.0;
  }
};
TextbookSphere textbook_sphere(const Vec3& pr, const Vec3& tr, const Vec3& center, float radius);

}  // namespace rayscope
