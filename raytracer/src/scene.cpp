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
  prim_offsets_.clear();
  // Global primitive indices are 32-bit; the last one is ~0u's neighbour.
  size_t count = 0;
  auto add_prims = [&](size_t n) {
    prim_offsets_.push_back(uint32_t(count));
    count += n;
    if (count > size_t(~0u) - 1)
      throw std::invalid_argument("the scene has more than 2^32 - 2 primitives");
  };
  for (const TriangleMesh& m : meshes) {
    check_material(m.material, "mesh '" + m.name + "'");
    if (!m.normals.empty() && m.normals.size() != m.positions.size())
      throw std::invalid_argument("mesh '" + m.name + "': normals must match positions");
    if (!m.colors.empty() && m.colors.size() != m.positions.size())
      throw std::invalid_argument("mesh '" + m.name + "': colors must match positions");
    for (const glm::uvec3& t : m.triangles)
      if (t.x >= m.positions.size() || t.y >= m.positions.size() || t.z >= m.positions.size())
        throw std::invalid_argument("mesh '" + m.name + "': vertex index out of range");
    add_prims(m.triangles.size());
  }
  const uint32_t ntri = uint32_t(count);
  num_triangles_ = ntri;
  // Per-position arrays and the one radius of a set without radii: wrong
  // sizes and a radius no segment could have are errors in whatever built
  // the scene, not in the data.
  auto check_set = [&](const std::string& what, size_t positions, size_t radii, float radius,
                       size_t colors, uint32_t material) {
    check_material(material, what);
    if (radii != 0 && radii != positions)
      throw std::invalid_argument(what + ": radii must match positions");
    if (colors != 0 && colors != positions)
      throw std::invalid_argument(what + ": colors must match positions");
    if (radii == 0 && (!std::isfinite(radius) || !(radius > 0.0f)))
      throw std::invalid_argument(what + ": radius must be finite and > 0");
  };
  for (const TubeSet& ts : tubes) {
    const std::string what = "tubes '" + ts.name + "'";
    check_set(what, ts.positions.size(), ts.radii.size(), ts.radius, ts.colors.size(), ts.material);
    for (const glm::uvec2& sg : ts.segments)
      if (sg.x >= ts.positions.size() || sg.y >= ts.positions.size())
        throw std::invalid_argument(what + ": position index out of range");
    add_prims(ts.segments.size());
  }
  for (const PointSet& ps : points) {
    check_set("points '" + ps.name + "'", ps.positions.size(), ps.radii.size(), ps.radius,
              ps.colors.size(), ps.material);
    add_prims(ps.positions.size());
  }
  sphere_base_ = uint32_t(count);
  prim_offsets_.push_back(sphere_base_);
  if (count + spheres.size() > size_t(~0u) - 1)
    throw std::invalid_argument("the scene has more than 2^32 - 2 primitives");
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

  // Bounds and centroids of every valid primitive (prim_box()'s rules, so that
  // the aggregate can build the same hierarchy again from its records); the
  // builder sees nothing else.
  std::vector<Bounds3> bounds;
  std::vector<Vec3> centroids;
  auto add_box = [&](const PrimBox& p) {
    bounds.push_back(p.bounds);
    centroids.push_back(p.centroid);
  };
  std::vector<uint32_t> ids;
  reserve_huge(bounds, count + spheres.size());
  reserve_huge(centroids, count + spheres.size());
  reserve_huge(ids, count + spheres.size());
  auto warn_about = [&](const std::string& object, size_t n, const std::string& what) {
    if (n) summary_.warnings.push_back(object + ": " + std::to_string(n) + " " + what);
  };
  auto warn = [&](const TriangleMesh& m, size_t n, const std::string& what) {
    warn_about("mesh '" + m.name + "'", n, what);
  };
  auto count_nonfinite = [](const std::vector<Color>& colors) {
    return size_t(
        std::count_if(colors.begin(), colors.end(), [](const Color& c) { return !all_finite(c); }));
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
      add_box(triangle_box(a, b, c));
      ids.push_back(prim_offsets_[mi] + uint32_t(ti));
    }
    size_t bad_normals = size_t(std::count_if(m.normals.begin(), m.normals.end(),
                                              [](const Vec3& n) { return !all_finite(n); }));
    size_t bad_colors = count_nonfinite(m.colors);
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
  // Tube segments and points: the box of each one traced (their index in the
  // set: 0..count-1, ids from `first`); a set with nothing left to trace is an
  // error, as a mesh is (above). Returns how many were left out.
  auto add_round_set = [&](const std::string& what, uint32_t first, size_t count, auto traced,
                           auto box, const char* items, const char* why_skipped,
                           size_t bad_colors) {
    size_t skipped = 0;
    for (size_t j = 0; j < count; ++j) {
      if (!traced(j)) {
        skipped++;
        continue;
      }
      add_box(box(j));
      ids.push_back(first + uint32_t(j));
    }
    if (skipped > 0 && skipped == count)
      throw std::invalid_argument(what + ": all " + std::to_string(skipped) + " " + items +
                                  " have a non-finite position or a radius not finite and > 0");
    warn_about(what, skipped, std::string(items) + " with " + why_skipped + " skipped");
    warn_about(what, bad_colors,
               std::string("colors are not finite (their ") + items + " get the material color)");
    summary_.nonfinite_colors += bad_colors;
    return skipped;
  };
  for (size_t k = 0; k < tubes.size(); ++k) {
    const TubeSet& ts = tubes[k];
    const size_t skipped = add_round_set(
        "tubes '" + ts.name + "'", prim_offsets_[meshes.size() + k], ts.segments.size(),
        [&](size_t j) { return ts.traced(j); },
        [&](size_t j) {
          return capsule_box(ts.positions[ts.segments[j].x], ts.positions[ts.segments[j].y],
                             ts.segment_radius(j));
        },
        "segments", "a non-finite end or an end's radius not finite and > 0",
        count_nonfinite(ts.colors));
    summary_.skipped_segments += skipped;
    summary_.tube_segments += ts.segments.size() - skipped;
  }
  for (size_t k = 0; k < points.size(); ++k) {
    const PointSet& ps = points[k];
    const size_t skipped = add_round_set(
        "points '" + ps.name + "'", prim_offsets_[meshes.size() + tubes.size() + k],
        ps.positions.size(), [&](size_t j) { return ps.traced(j); },
        [&](size_t j) { return capsule_box(ps.positions[j], ps.positions[j], ps.point_radius(j)); },
        "points", "a non-finite position or a radius not finite and > 0",
        count_nonfinite(ps.colors));
    summary_.skipped_points += skipped;
    summary_.points += ps.positions.size() - skipped;
  }
  for (size_t si = 0; si < spheres.size(); ++si) {
    add_box(sphere_box(spheres[si].center, spheres[si].radius));
    ids.push_back(sphere_base_ + uint32_t(si));
  }
  auto record_of = [&](size_t i) { return prim_record(ids[i]); };
  std::vector<PlaneRecord> plane_records;
  // The unit normal goes into the aggregate's record; the scene's plane keeps
  // the normal it was given, so that committing again gives the same record
  // (normalizing a normalized vector may move it by an ulp).
  for (const Plane& p : planes) plane_records.push_back({p.point, normalize_any_length(p.normal)});
  accel_.build(bounds, centroids, record_of, ntri, std::move(plane_records), config);

  summary_.walks_structure = accel_.walks_structure();
  summary_.triangles = ntri - summary_.skipped_triangles;
  summary_.tube_sets = tubes.size();
  summary_.point_sets = points.size();
  summary_.spheres = spheres.size();
  summary_.planes = planes.size();
  summary_.lights = lights.size();
  auto note = [&](uint32_t m) {
    summary_.reflective |= materials[m].reflective();
    summary_.refractive |= materials[m].refractive();
  };
  for (const TriangleMesh& m : meshes) note(m.material);
  for (const TubeSet& t : tubes) note(t.material);
  for (const PointSet& p : points) note(p.material);
  for (const Sphere& s : spheres) note(s.material);
  for (const Plane& p : planes) note(p.material);
}

ObjectType Scene::object_type(uint32_t object) const {
  size_t end = meshes.size();
  if (object < end) return ObjectType::Mesh;
  if (object < (end += tubes.size())) return ObjectType::Tubes;
  if (object < (end += points.size())) return ObjectType::Points;
  if (object < end + spheres.size()) return ObjectType::Sphere;
  return ObjectType::Plane;
}

const std::string& Scene::object_name(uint32_t object) const {
  static const std::string none = "(none)";
  if (object < meshes.size()) return meshes[object].name;
  object -= uint32_t(meshes.size());
  if (object < tubes.size()) return tubes[object].name;
  object -= uint32_t(tubes.size());
  if (object < points.size()) return points[object].name;
  object -= uint32_t(points.size());
  if (object < spheres.size()) return spheres[object].name;
  object -= uint32_t(spheres.size());
  if (object < planes.size()) return planes[object].name;
  return none;
}

uint32_t Scene::prim_object(uint32_t prim) const {
  // Objects with no primitives share their offset with the next one:
  // upper_bound finds the last object starting at or before prim.
  if (prim < sphere_base_)
    return uint32_t(std::upper_bound(prim_offsets_.begin(), prim_offsets_.end(), prim) -
                    prim_offsets_.begin()) -
           1;
  return uint32_t(meshes.size() + tubes.size() + points.size()) + (prim - sphere_base_);
}

PrimRecord Scene::prim_record(uint32_t id) const {
  PrimRecord r;
  r.id = id;
  r.c = Vec3(0.0f);
  const uint32_t object = prim_object(id);
  const uint32_t index = prim_in_object(id);
  if (id < num_triangles_) {
    const TriangleMesh& m = meshes[object];
    const glm::uvec3& t = m.triangles[index];
    r.shape = PrimShape::Triangle;
    r.a = m.positions[t.x];
    r.b = m.positions[t.y];
    r.c = m.positions[t.z];
  } else if (object < meshes.size() + tubes.size()) {
    const TubeSet& ts = tubes[object - meshes.size()];
    r.shape = PrimShape::Capsule;
    r.a = ts.positions[ts.segments[index].x];
    r.b = ts.positions[ts.segments[index].y];
    r.c = Vec3(ts.segment_radius(index), 0.0f, 0.0f);
  } else if (id < sphere_base_) {
    const PointSet& ps = points[object - meshes.size() - tubes.size()];
    r.shape = PrimShape::Point;
    r.a = ps.positions[index];
    r.b = Vec3(ps.point_radius(index), 0.0f, 0.0f);
  } else {
    const Sphere& s = spheres[id - sphere_base_];
    r.shape = PrimShape::Sphere;
    r.a = s.center;
    r.b = Vec3(s.radius, 0.0f, 0.0f);
  }
  return r;
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
    hit.object = plane_object(uint32_t(ph.plane));
    hit.prim = 0;
    hit.material = pl.material;
    return hit;
  }
  const TriangleHit th{t, ph.b0, ph.b1, ph.b2};
  // A per-position color, unless it is not finite (reported by commit(),
  // it would make the pixel NaN: the material color is used instead).
  auto vertex_color = [&](const Color& c) {
    hit.vertex_color = c;
    hit.has_vertex_color = all_finite(c);
  };
  if (ph.prim < num_triangles_) {
    uint32_t mi = prim_object(ph.prim);
    const TriangleMesh& m = meshes[mi];
    uint32_t ti = ph.prim - prim_offsets_[mi];
    const glm::uvec3& tri = m.triangles[ti];
    const Vec3 &a = m.positions[tri.x], &b = m.positions[tri.y], &c = m.positions[tri.z];
    hit.p = triangle_point(th, a, b, c, hit.p_error);
    hit.bary = Vec3(th.b0, th.b1, th.b2);
    Vec3 n = glm::cross(b - a, c - a);
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
    if (!m.colors.empty())
      vertex_color(th.b0 * m.colors[tri.x] + th.b1 * m.colors[tri.y] + th.b2 * m.colors[tri.z]);
    hit.object = mi;
    hit.prim = ti;
    hit.material = m.material;
    return hit;
  }
  const PrimRecord r = prim_record(ph.prim);
  hit.object = prim_object(r.id);
  hit.prim = prim_in_object(r.id);
  if (r.shape == PrimShape::Capsule) {
    const TubeSet& ts = tubes[hit.object - meshes.size()];
    float s;
    hit.p = capsule_point(ray, t, r.a, r.b, r.c.x, hit.p_error, hit.ng, s);
    hit.ns = hit.ng;
    hit.bary = Vec3(1.0f - s, s, 0.0f);
    if (!ts.colors.empty()) {
      const glm::uvec2& sg = ts.segments[hit.prim];
      vertex_color((1.0f - s) * ts.colors[sg.x] + s * ts.colors[sg.y]);
    }
    hit.material = ts.material;
    return hit;
  }
  // A ball: a point of a point set or a sphere, from its record.
  hit.p = sphere_point(ray, t, r.a, r.b.x, hit.p_error, hit.ng);
  hit.ns = hit.ng;
  if (r.id < sphere_base_) {
    const PointSet& ps = points[hit.object - meshes.size() - tubes.size()];
    if (!ps.colors.empty()) vertex_color(ps.colors[hit.prim]);
    hit.material = ps.material;
  } else {
    hit.material = spheres[r.id - sphere_base_].material;
  }
  return hit;
}

}  // namespace rayscope
