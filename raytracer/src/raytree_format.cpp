#include "rayscope/raytree_format.h"

#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayscope/printf_string.h"
#include "rayscope/textbook_intersect.h"

namespace rayscope {

namespace {

std::string v3(const Vec3& v) {
  return printf_string("(%.4g, %.4g, %.4g)", v.x, v.y, v.z);
}
// A scene-local position in world coordinates (Scene::origin); with more
// digits when the scene is far from the world's origin, where four would show
// only where the scene is, not where in it.
std::string world(const Scene& s, const Vec3& local) {
  const DVec3 w = s.to_world(local);
  if (s.origin == DVec3(0.0)) return v3(local);
  return printf_string("(%.10g, %.10g, %.10g)", w.x, w.y, w.z);
}
float degrees_from_cos(float c) {
  return glm::degrees(std::acos(std::clamp(c, -1.0f, 1.0f)));
}

const char* object_kind(const Scene& s, uint32_t o) {
  switch (s.object_type(o)) {
    case ObjectType::Mesh:
      return "mesh";
    case ObjectType::Tubes:
      return "tubes";
    case ObjectType::Points:
      return "points";
    case ObjectType::Sphere:
      return "sphere";
    case ObjectType::Plane:
      return "plane";
  }
  return "?";
}

const std::string& light_name(const Scene& s, int light) {
  static const std::string unknown = "?";
  return light >= 0 && size_t(light) < s.lights.size() ? s.lights[size_t(light)].name : unknown;
}

// The lecture's test of the primitive a ray hit (textbook_intersect.h), as
// JSON: {"test": "ray-triangle" | "ray-sphere" | "ray-plane", quantities...};
// null for a tube segment (the capsule test is not one of the lecture's).
nlohmann::json textbook_json(const Scene& s, const RayRecord& r) {
  const auto plane = [](const TextbookPlane& p) {
    return nlohmann::json{{"tr_dot_n", p.tr_dot_n}, {"lambda", p.lambda}};
  };
  const auto sphere = [&](const Vec3& c, float radius) {
    const TextbookSphere q = textbook_sphere(r.origin, r.dir, c, radius);
    return nlohmann::json{{"test", "ray-sphere"},
                          {"a", q.a},
                          {"b", q.b},
                          {"c", q.c},
                          {"discriminant", q.discriminant},
                          {"lambda_near", q.lambda_near},
                          {"lambda_far", q.lambda_far},
                          {"lambda", q.lambda()}};
  };
  uint32_t o = r.object;
  switch (s.object_type(o)) {
    case ObjectType::Mesh: {
      const TriangleMesh& m = s.meshes[o];
      const glm::uvec3 v = m.triangles[r.prim];
      const TextbookTriangle t =
          textbook_triangle(r.origin, r.dir, m.positions[v.x], m.positions[v.y], m.positions[v.z]);
      return {{"test", "ray-triangle"},
              {"plane", plane(t.plane)},
              {"lambda1", t.lambda1},
              {"lambda2", t.lambda2},
              {"inside", t.inside()}};
    }
    case ObjectType::Tubes:
      return nullptr;
    case ObjectType::Points: {
      const PointSet& ps = s.points[o - s.meshes.size() - s.tubes.size()];
      return sphere(ps.positions[r.prim], ps.point_radius(r.prim));
    }
    case ObjectType::Sphere: {
      const Sphere& sp = s.spheres[o - s.meshes.size() - s.tubes.size() - s.points.size()];
      return sphere(sp.center, sp.radius);
    }
    case ObjectType::Plane: {
      const Plane& pl = s.planes[o - s.plane_object(0)];
      nlohmann::json j = plane(textbook_plane(r.origin, r.dir, pl.point, pl.normal));
      j["test"] = "ray-plane";
      return j;
    }
  }
  return nullptr;
}

// The same as text: the lecture's formula with its numbers, one or two lines
// (the second continues the first); empty for a tube segment.
std::vector<std::string> textbook_text(const nlohmann::json& t) {
  if (t.is_null()) return {};
  const std::string test = t["test"];
  auto g = [&](const nlohmann::json& j, const char* key) { return j[key].get<double>(); };
  if (test == "ray-plane")
    return {printf_string("ray-plane: t_r.n = %.6g, lambda = (P_0 - P_r).n / t_r.n = %.6g",
                          g(t, "tr_dot_n"), g(t, "lambda"))};
  if (test == "ray-triangle") {
    const double l1 = g(t, "lambda1"), l2 = g(t, "lambda2");
    return {printf_string("ray-triangle: its plane: t_r.n = %.6g, lambda = %.6g",
                          g(t["plane"], "tr_dot_n"), g(t["plane"], "lambda")),
            printf_string(
                "P = P_0 + lambda1 t_1 + lambda2 t_2: lambda1 = %.6g, lambda2 = %.6g, sum %.6g: %s",
                l1, l2, l1 + l2, t["inside"].get<bool>() ? "inside" : "outside")};
  }
  return {
      "ray-sphere: a lambda^2 + b lambda + c = 0, a = t_r.t_r, b = 2 t_r.(P_r - center), "
      "c = (P_r - center)^2 - r^2",
      printf_string(
          "a = %.6g, b = %.6g, c = %.6g; discriminant b^2 - 4ac = %.6g: lambda = %.6g or %.6g",
          g(t, "a"), g(t, "b"), g(t, "c"), g(t, "discriminant"), g(t, "lambda_near"),
          g(t, "lambda_far"))};
}

void text_ray(const PixelRecord& rec, const Scene& s, int id, int indent, std::string& out) {
  const RayRecord& r = rec.rays[size_t(id)];
  std::string pad(size_t(indent) * 2, ' ');
  std::string line = pad + printf_string("#%d %s  depth %d  weight %.4g", r.id, to_string(r.kind),
                                         r.depth, max_component(r.weight));
  if (r.kind == RayKind::Shadow) {
    line += printf_string("  to light %d \"%s\": ", r.light, light_name(s, r.light).c_str());
    if (r.skipped)
      line += printf_string("skipped (%s)", to_string(r.skip_reason));
    else if (r.occluded)
      line += printf_string("occluded by \"%s\" (%s)", s.object_name(r.occluder).c_str(),
                            object_kind(s, r.occluder));
    else
      line += "visible, light " + v3(r.color);
  } else if (r.skipped) {
    line += printf_string("  skipped (%s)", to_string(r.skip_reason));
  } else if (r.hit) {
    // What was hit within its object: "mesh triangle 5", "tube segment 28"
    // (of a tube set), "point 16" (of a point set), "sphere", "plane".
    line += printf_string("  hit \"%s\" (", s.object_name(r.object).c_str());
    switch (s.object_type(r.object)) {
      case ObjectType::Mesh:
        line += printf_string("mesh triangle %u", r.prim);
        break;
      case ObjectType::Tubes:
        line += printf_string("tube segment %u", r.prim);
        break;
      case ObjectType::Points:
        line += printf_string("point %u", r.prim);
        break;
      case ObjectType::Sphere:
      case ObjectType::Plane:
        line += object_kind(s, r.object);
        break;
    }
    line += printf_string(", material \"%s\") t=%.5g", s.materials[r.material].name.c_str(), r.t);
    line += "\n" + pad + "   at " + world(s, r.point) + "  normal " + v3(r.ns);
    if (r.ns != r.ng) line += "  geometric " + v3(r.ng);
    const std::vector<std::string> test = textbook_text(textbook_json(s, r));
    for (size_t k = 0; k < test.size(); ++k)
      line += "\n" + pad + (k == 0 ? "   lecture's test: " : "                   ") + test[k];
    line += "\n" + pad + "   returned " + v3(r.color);
    line += "\n" + pad + "   local: ambient " + v3(r.ambient);
    for (const LightTerms& l : r.lights)
      line += "\n" + pad +
              printf_string("     + light %d \"%s\": diffuse ", l.light,
                            light_name(s, l.light).c_str()) +
              v3(l.diffuse) + " specular " + v3(l.specular);
  } else {
    line += "  miss (background) returned " + v3(r.color);
  }
  out += line + "\n";
  if (!r.skipped) {
    const TraversalRecord& w = r.traversal;
    out += pad + printf_string("   walk: %zu nodes visited, %u boxes tested, %u primitives tested",
                               w.nodes().size(), w.boxes_tested(), w.prims_tested);
    if (w.culled()) out += printf_string(", %u nodes culled", w.culled());
    if (w.early_terminated) out += ", early termination";
    if (w.hit_leaf != kNoNode) out += printf_string(", hit in leaf %u", w.hit_leaf);
    out += "\n";
  }
  if (r.has_refraction) {
    const RefractionEvent& e = r.refraction;
    out += pad + printf_string("   refraction: n1 %.4g -> n2 %.4g, incidence %.2f deg, ", e.n1,
                               e.n2, degrees_from_cos(e.cos_incidence));
    if (e.total_internal_reflection)
      out += "total internal reflection";
    else
      out += printf_string("transmission %.2f deg", degrees_from_cos(e.cos_transmission));
    out += printf_string(", Fresnel R %.4f T %.4f\n", e.fresnel_reflect, e.fresnel_transmit);
  }
  for (int c : r.children) text_ray(rec, s, c, indent + 1, out);
}

constexpr const char* kLocalLegend =
    "lecture's test: the lecture's formula for the primitive hit, in double precision, with\n"
    "  the ray P = P_r + lambda t_r (lambda is the t of the hit, which the robust test found)\n"
    "local: the hit's local illumination, ambient + per light reaching it diffuse and specular\n"
    "skipped: rays not traced (N.L <= 0: light behind the surface; depth limit; contribution\n"
    "  cutoff: weight below --min-contribution)\n";

// What the "walk:" line of each ray counts, for the structure the scene walks.
std::string walk_legend(const Scene& s) {
  const Aggregate& a = s.accel();
  std::string legend = "walk: " + a.walk_legend() + "\n";
  if (a.walks_structure())
    legend +=
        "  nodes visited = nodes entered, in order; boxes tested = boxes tested against the "
        "ray,\n  hit or missed (the root's, then every child box of each node entered, so more "
        "boxes\n  than nodes); primitives tested = the primitives in the leaves entered;"
        "\n  culled = boxes hit but skipped because a closer hit was found first (early "
        "termination);\n  hit in leaf = the leaf holding the primitive hit\n";
  return legend + kLocalLegend;
}

nlohmann::json jv(const Vec3& v) {
  return {v.x, v.y, v.z};
}
nlohmann::json jworld(const Scene& s, const Vec3& local) {
  if (s.origin == DVec3(0.0)) return jv(local);
  const DVec3 w = s.to_world(local);
  return {w.x, w.y, w.z};
}
nlohmann::json jf(float f) {
  if (std::isfinite(f)) return f;
  return nullptr;
}

}  // namespace

std::string format_text(const PixelRecord& rec, const Scene& s) {
  const int grid = rec.samples * rec.samples;
  std::string out =
      printf_string("pixel (%d, %d): %dx%d samples", rec.x, rec.y, rec.samples, rec.samples) +
      (rec.samples_taken == grid
           ? std::string()
           : printf_string(" (adaptive: took %d of %d)", rec.samples_taken, grid)) +
      ", color " + v3(rec.color) + printf_string(", %zu rays recorded\n", rec.rays.size());
  out += walk_legend(s);
  for (const RayRecord& r : rec.rays)
    if (r.parent < 0) {
      out += printf_string("sample %d\n", r.sample);
      text_ray(rec, s, r.id, 1, out);
    }
  return out;
}

std::string format_json(const PixelRecord& rec, const Scene& s, int indent) {
  using json = nlohmann::json;
  json rays = json::array();
  for (const RayRecord& r : rec.rays) {
    json j = {{"id", r.id},
              {"parent", r.parent},
              {"children", r.children},
              {"kind", to_string(r.kind)},
              {"depth", r.depth},
              {"sample", r.sample},
              {"origin", jworld(s, r.origin)},
              {"direction", jv(r.dir)},
              {"tmin", jf(r.tmin)},
              {"tmax", jf(r.tmax)},
              {"weight", jv(r.weight)},
              {"color", jv(r.color)},
              {"skipped", r.skipped}};
    if (r.skipped) j["skip_reason"] = to_string(r.skip_reason);
    json steps = json::array();
    for (const TraversalStep& st : r.traversal.steps)
      steps.push_back({to_string(st.kind), st.node});
    j["bvh"] = {
        {"nodes", r.traversal.nodes()},
        {"boxes_tested", r.traversal.boxes_tested()},
        {"primitives_tested", r.traversal.prims_tested},
        {"culled", r.traversal.culled()},
        {"early_termination", r.traversal.early_terminated},
        {"hit_leaf", r.traversal.hit_leaf == kNoNode ? json(nullptr) : json(r.traversal.hit_leaf)},
        {"steps", std::move(steps)}};
    if (r.kind == RayKind::Shadow) {
      j["light"] = r.light;
      j["occluded"] = r.occluded;
      if (r.occluded) {
        j["occluder"] = r.occluder;
        j["occluder_name"] = s.object_name(r.occluder);
        j["occluder_type"] = object_kind(s, r.occluder);
      }
    } else {
      j["hit"] = r.hit;
      if (r.hit) {
        j["t"] = r.t;
        j["point"] = jworld(s, r.point);
        j["geometric_normal"] = jv(r.ng);
        j["shading_normal"] = jv(r.ns);
        j["object"] = r.object;
        j["object_name"] = s.object_name(r.object);
        j["object_type"] = object_kind(s, r.object);
        j["primitive"] = r.prim;
        j["lecture_test"] = textbook_json(s, r);
        j["material"] = s.materials[r.material].name;
        json lights = json::array();
        for (const LightTerms& l : r.lights)
          lights.push_back({{"light", l.light},
                            {"name", light_name(s, l.light)},
                            {"diffuse", jv(l.diffuse)},
                            {"specular", jv(l.specular)}});
        j["local"] = {{"ambient", jv(r.ambient)}, {"lights", std::move(lights)}};
      }
    }
    if (r.has_refraction) {
      const RefractionEvent& e = r.refraction;
      j["refraction"] = {{"n1", e.n1},
                         {"n2", e.n2},
                         {"incidence_deg", degrees_from_cos(e.cos_incidence)},
                         {"transmission_deg", e.total_internal_reflection
                                                  ? json(nullptr)
                                                  : json(degrees_from_cos(e.cos_transmission))},
                         {"total_internal_reflection", e.total_internal_reflection},
                         {"fresnel_reflect", e.fresnel_reflect},
                         {"fresnel_transmit", e.fresnel_transmit}};
    }
    rays.push_back(std::move(j));
  }
  json root = {{"pixel", {rec.x, rec.y}},
               {"accel", to_string(s.accel().kind())},
               {"sample", rec.sample},
               {"samples_per_axis", rec.samples},
               {"samples_taken", rec.samples_taken},
               {"color", jv(rec.color)},
               {"rays", std::move(rays)}};
  return root.dump(indent);
}

}  // namespace rayscope
