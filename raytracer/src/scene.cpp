#include "rayscope/scene.h"

#include "rayscope/huge_pages.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rayscope {

void Scene::commit(const AccelConfig& config) {
  if (materials.empty()) throw std::invalid_argument("scene has no materials");
  if (!std::isfinite(origin.x) || !std::isfinite(origin.y) || !std::isfinite(origin.z))
    throw std::invalid_argument("the scene's origin is not finite");
  auto check_material = [&](uint32_t m, const std::string& what) {
    if (m >= materials.size())
      throw std::invalid_argument(what + ": material index " + std::to_string(m) + " out of range");
  };
  summary_ = SceneSummary{};
  tri_offsets_.clear();
  uint32_t ntri = 0;
  for (const TriangleMesh& m : meshes) {
    check_material(m.material, "mesh '" + m.name + "'");
    if (!m.normals.empty() && m.normals.size() != m.positions.size())
      throw std::invalid_argument("mesh '" + m.name + "': normals must match positions");
    if (!m.colors.empty() && m.colors.size() != m.positions.size())
      throw std::invalid_argument("mesh '" + m.name + "': colors must match positions");
    for (const glm::uvec3& t : m.triangles)
      if (t.x >= m.positions.size() || t.y >= m.positions.size() || t.z >= m.positions.size())
        throw std::invalid_argument("mesh '" + m.name + "': vertex index out of range");
    tri_offsets_.push_back(ntri);
    ntri += uint32_t(m.triangles.size());
  }
  tri_offsets_.push_back(ntri);
  num_triangles_ = ntri;
  for (const Sphere& s : spheres) {
    check_material(s.material, "sphere '" + s.name + "'");
    if (!all_finite(s.center) || !std::isfinite(s.radius) || !(s.radius > 0.0f))
      throw std::invalid_argument("sphere '" + s.name +
                                  "': center and radius must be finite, radius > 0");
  }
  for (const Plane& p : planes) {
    check_material(p.material, "plane '" + p.name + "'");
    if (!all_finite(p.point) || !all_finite(p.normal) || p.normal == Vec3(0.0f))
      throw std::invalid_argument("plane '" + p.name +
                                  "': point and normal must be finite, normal non-zero");
  }
  for (const Light& l : lights)
    if (!all_finite(l.position) || !all_finite(l.direction) || !all_finite(l.color) ||
        !std::isfinite(l.intensity))
      throw std::invalid_argument("light '" + l.name + "': values must be finite");

  // Bounds and centroids of every valid primitive; the builder sees nothing else.
  std::vector<Bounds3> bounds;
  std::vector<Vec3> centroids;
  std::vector<uint32_t> ids;
  reserve_huge(bounds, ntri + spheres.size());
  reserve_huge(centroids, ntri + spheres.size());
  reserve_huge(ids, ntri + spheres.size());
  auto warn = [&](const TriangleMesh& m, size_t n, const std::string& what) {
    if (n) summary_.warnings.push_back("mesh '" + m.name + "': " + std::to_string(n) + " " + what);
  };
  for (size_t mi = 0; mi < meshes.size(); ++mi) {
    const TriangleMesh& m = meshes[mi];
    size_t skipped = 0, degenerate = 0;
    for (size_t ti = 0; ti < m.triangles.size(); ++ti) {
      const glm::uvec3& t = m.triangles[ti];
      if (!m.finite(t)) {
        skipped++;
        continue;
      }
      const Vec3 &a = m.positions[t.x], &b = m.positions[t.y], &c = m.positions[t.z];
      if (glm::cross(b - a, c - a) == Vec3(0.0f)) degenerate++;
      Bounds3 box(a);
      box.extend(b);
      box.extend(c);
      bounds.push_back(box);
      centroids.push_back(box.center());
      ids.push_back(tri_offsets_[mi] + uint32_t(ti));
    }
    size_t bad_normals = size_t(std::count_if(m.normals.begin(), m.normals.end(),
                                              [](const Vec3& n) { return !all_finite(n); }));
    size_t bad_colors = size_t(std::count_if(m.colors.begin(), m.colors.end(),
                                             [](const Color& c) { return !all_finite(c); }));
    // A mesh with nothing left to trace is an error, as a mesh without
    // triangles is in every front end: its picture would be blank.
    if (skipped > 0 && skipped == m.triangles.size())
      throw std::invalid_argument("mesh '" + m.name + "': all " + std::to_string(skipped) +
                                  " triangles have non-finite (NaN or infinite) vertex "
                                  "coordinates");
    warn(m, skipped, "triangles with non-finite vertex coordinates skipped");
    warn(m, bad_normals,
         "vertex normals are not finite (their triangles are shaded with the geometric normal)");
    warn(m, bad_colors, "vertex colors are not finite (their triangles get the material color)");
    summary_.skipped_triangles += skipped;
    summary_.degenerate_triangles += degenerate;
    summary_.nonfinite_normals += bad_normals;
    summary_.nonfinite_colors += bad_colors;
  }
  for (size_t si = 0; si < spheres.size(); ++si) {
    const Sphere& s = spheres[si];
    bounds.emplace_back(s.center - Vec3(s.radius), s.center + Vec3(s.radius));
    centroids.push_back(s.center);
    ids.push_back(ntri + uint32_t(si));
  }
  auto record_of = [&](size_t i) {
    const uint32_t id = ids[i];
    PrimRecord r;
    r.id = id;
    r.pad = 0;
    if (id < ntri) {
      const uint32_t mi = prim_object(id);
      const glm::uvec3& t = meshes[mi].triangles[id - tri_offsets_[mi]];
      r.a = meshes[mi].positions[t.x];
      r.b = meshes[mi].positions[t.y];
      r.c = meshes[mi].positions[t.z];
    } else {
      const Sphere& s = spheres[id - ntri];
      r.a = s.center;
      r.b = Vec3(s.radius, 0.0f, 0.0f);
      r.c = Vec3(0.0f);
    }
    return r;
  };
  std::vector<PlaneRecord> plane_records;
  // The unit normal goes into the aggregate's record; the scene's plane keeps
  // the normal it was given, so that committing again gives the same record
  // (normalizing a normalized vector may move it by an ulp).
  for (const Plane& p : planes) plane_records.push_back({p.point, normalize_any_length(p.normal)});
  accel_.build(bounds, centroids, record_of, ntri, std::move(plane_records), config);

  summary_.walks_structure = accel_.walks_structure();
  summary_.triangles = ntri - summary_.skipped_triangles;
  summary_.spheres = spheres.size();
  summary_.planes = planes.size();
  summary_.lights = lights.size();
  auto note = [&](uint32_t m) {
    summary_.reflective |= materials[m].reflective();
    summary_.refractive |= materials[m].refractive();
  };
  for (const TriangleMesh& m : meshes) note(m.material);
  for (const Sphere& s : spheres) note(s.material);
  for (const Plane& p : planes) note(p.material);
}

ObjectType Scene::object_type(uint32_t object) const {
  if (object < meshes.size()) return ObjectType::Mesh;
  if (object < meshes.size() + spheres.size()) return ObjectType::Sphere;
  return ObjectType::Plane;
}

const std::string& Scene::object_name(uint32_t object) const {
  static const std::string none = "(none)";
  if (object < meshes.size()) return meshes[object].name;
  object -= uint32_t(meshes.size());
  if (object < spheres.size()) return spheres[object].name;
  object -= uint32_t(spheres.size());
  if (object < planes.size()) return planes[object].name;
  return none;
}

uint32_t Scene::prim_object(uint32_t prim) const {
  if (prim < num_triangles_)
    return uint32_t(std::upper_bound(tri_offsets_.begin(), tri_offsets_.end(), prim) -
                    tri_offsets_.begin()) -
           1;
  return uint32_t(meshes.size()) + (prim - num_triangles_);
}

SurfaceHit Scene::surface_hit(const Ray& ray, const PrimHit& ph) const {
  SurfaceHit hit;
  const float t = ph.t;
  hit.t = t;
  if (ph.plane >= 0) {
    const Plane& pl = planes[size_t(ph.plane)];
    const PlaneRecord& rec = accel_.plane_records()[size_t(ph.plane)];
    hit.p = plane_point(ray, t, rec.point, rec.normal, hit.p_error);
    hit.ng = hit.ns = rec.normal;
    hit.object = uint32_t(meshes.size() + spheres.size() + size_t(ph.plane));
    hit.prim = 0;
    hit.material = pl.material;
    return hit;
  }
  const PrimRecord& r = accel_.records()[ph.record];
  const TriangleHit th{t, ph.b0, ph.b1, ph.b2};
  if (r.id < num_triangles_) {
    uint32_t mi = prim_object(r.id);
    const TriangleMesh& m = meshes[mi];
    uint32_t ti = r.id - tri_offsets_[mi];
    const glm::uvec3& tri = m.triangles[ti];
    hit.p = triangle_point(th, r.a, r.b, r.c, hit.p_error);
    hit.bary = Vec3(th.b0, th.b1, th.b2);
    Vec3 n = glm::cross(r.b - r.a, r.c - r.a);
    float len = glm::length(n);
    hit.ng = len > 0.0f && std::isfinite(len) ? n / len : -glm::normalize(ray.dir);
    hit.ns = hit.ng;
    if (!m.normals.empty()) {
      Vec3 ns = th.b0 * m.normals[tri.x] + th.b1 * m.normals[tri.y] + th.b2 * m.normals[tri.z];
      float l2 = glm::dot(ns, ns);
      if (l2 > 0.0f && std::isfinite(l2)) {
        hit.ns = ns / std::sqrt(l2);
        // Trust the data's normals for the side of the surface.
        if (glm::dot(hit.ns, hit.ng) < 0.0f) hit.ng = -hit.ng;
      }
    }
    if (!m.colors.empty()) {
      hit.vertex_color =
          th.b0 * m.colors[tri.x] + th.b1 * m.colors[tri.y] + th.b2 * m.colors[tri.z];
      // A non-finite vertex color (reported by commit()) would make the pixel
      // NaN: the material color is used instead.
      hit.has_vertex_color = all_finite(hit.vertex_color);
    }
    hit.object = mi;
    hit.prim = ti;
    hit.material = m.material;
  } else {
    uint32_t si = r.id - num_triangles_;
    const Sphere& s = spheres[si];
    hit.p = sphere_point(ray, t, s.center, s.radius, hit.p_error, hit.ng);
    hit.ns = hit.ng;
    hit.object = uint32_t(meshes.size()) + si;
    hit.prim = 0;
    hit.material = s.material;
  }
  return hit;
}

}  // namespace rayscope
