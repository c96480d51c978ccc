#include "rayscope/textbook_intersect.h"

#include <cmath>

namespace rayscope {

TextbookPlane textbook_plane(const Vec3& pr, const Vec3& tr, const Vec3& p0, const Vec3& n) {
  TextbookPlane t;
  const DVec3 nd(n);
  t.tr_dot_n = glm::dot(DVec3(tr), nd);
  if (t.tr_dot_n != 0.0) t.lambda = glm::dot(DVec3(p0) - DVec3(pr), nd) / t.tr_dot_n;
  return t;
}

TextbookTriangle textbook_triangle(const Vec3& pr, const Vec3& tr, const Vec3& p0, const Vec3& p1,
                                   const Vec3& p2) {
  TextbookTriangle t;
  t.t1 = DVec3(p1) - DVec3(p0);
  t.t2 = DVec3(p2) - DVec3(p0);
  t.n = glm::cross(t.t1, t.t2);
  const double nn = glm::dot(t.n, t.n);
  if (nn == 0.0) return t;  // degenerate: no plane
  t.plane.tr_dot_n = glm::dot(DVec3(tr), t.n);
  if (t.plane.tr_dot_n == 0.0) return t;
  t.plane.lambda = glm::dot(DVec3(p0) - DVec3(pr), t.n) / t.plane.tr_dot_n;
  // P - P_0 = λ_1 t_1 + λ_2 t_2; crossing with t_2 and t_1 isolates each term:
  // (P - P_0) × t_2 = λ_1 n and t_1 × (P - P_0) = λ_2 n.
  const DVec3 d = DVec3(pr) + t.plane.lambda * DVec3(tr) - DVec3(p0);
  t.lambda1 = glm::dot(glm::cross(d, t.t2), t.n) / nn;
  t.lambda2 = glm::dot(glm::cross(t.t1, d), t.n) / nn;
  return t;
}

TextbookSphere textbook_sphere(const Vec3& pr, const Vec3& tr, const Vec3& center, float radius) {
  TextbookSphere s;
  const DVec3 t(tr), f = DVec3(pr) - DVec3(center);
  s.a = glm::dot(t, t);
  s.b = 2.0 * glm::dot(t, f);
  s.c = glm::dot(f, f) - double(radius) * double(radius);
  s.discriminant = s.b * s.b - 4.0 * s.a * s.c;
  if (s.real_roots()) {
    const double root = std::sqrt(s.discriminant);
    s.lambda_near = (-s.b - root) / (2.0 * s.a);
    s.lambda_far = (-s.b + root) / (2.0 * s.a);
  }
  return s;
}

}  // namespace rayscope
