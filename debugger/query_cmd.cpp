// `rayscope query [SCENE] --box ... | --sphere ... | --knn ...`: a range query
// (range_query.h) through the chosen structure; prints the objects found and
// what the query cost.
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "rayscope/stats.h"
#include "scene_options.h"
#include "text_file.h"

namespace rayscope::cli {
namespace {

struct QueryOptions {
  SceneOptions scene;
  std::string box, sphere, knn;
  std::string format = "text";
  std::string output;
};

enum class QueryKind { Box, Sphere, Knn };

// A query as given (world coordinates) and its result.
struct Query {
  QueryKind kind;
  DVec3 a{0.0}, b{0.0};  // box: the corners; sphere, knn: a is the point
  double radius = 0.0;
  uint32_t k = 0;
};

Vec3 to_float(const DVec3& v) {
  return Vec3(v);
}

// Parses the one query option given and checks its values with the range's
// own check (in world coordinates, as the user typed them), the message
// prefixed with the option.
Query parse_query(const QueryOptions& o) {
  const int given = !o.box.empty() + !o.sphere.empty() + !o.knn.empty();
  if (given != 1)
    throw std::invalid_argument(
        "give exactly one of --box X0,Y0,Z0,X1,Y1,Z1, --sphere X,Y,Z,R or --knn X,Y,Z,K");
  Query q{};
  double v[6];
  auto checked = [](const char* option, auto check) {
    try {
      check();
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string(option) + ": " + e.what());
    }
  };
  if (!o.box.empty()) {
    if (!parse_numbers(o.box, 6, v))
      throw std::invalid_argument("--box: expected X0,Y0,Z0,X1,Y1,Z1 (six numbers), got '" + o.box +
                                  "'");
    q.kind = QueryKind::Box;
    q.a = DVec3(v[0], v[1], v[2]);
    q.b = DVec3(v[3], v[4], v[5]);
    Bounds3 box;
    box.lo = to_float(q.a);
    box.hi = to_float(q.b);
    checked("--box", [&] { BoxRange::check(box); });
  } else if (!o.sphere.empty()) {
    if (!parse_numbers(o.sphere, 4, v))
      throw std::invalid_argument("--sphere: expected X,Y,Z,R (four numbers), got '" + o.sphere +
                                  "'");
    q.kind = QueryKind::Sphere;
    q.a = DVec3(v[0], v[1], v[2]);
    q.radius = v[3];
    checked("--sphere", [&] { SphereRange::check(to_float(q.a), float(q.radius)); });
  } else {
    const size_t comma = o.knn.rfind(',');
    long long k = 0;
    bool ok = comma != std::string::npos && parse_numbers(o.knn.substr(0, comma), 3, v);
    if (ok) {
      const std::string ks = o.knn.substr(comma + 1);
      char* stop = nullptr;
      k = std::strtoll(ks.c_str(), &stop, 10);
      ok = !ks.empty() && stop == ks.c_str() + ks.size();
    }
    if (!ok)
      throw std::invalid_argument(
          "--knn: expected X,Y,Z,K (three numbers and a whole number K), got '" + o.knn + "'");
    q.kind = QueryKind::Knn;
    q.a = DVec3(v[0], v[1], v[2]);
    // K beyond the object count gives every object; beyond 2^32 - 1 it is
    // that count anyway.
    q.k = k < 1 ? 0u : uint32_t(std::min<long long>(k, std::numeric_limits<uint32_t>::max()));
    checked("--knn", [&] { KnnRange::check(to_float(q.a), q.k); });
  }
  return q;
}

const char* kind_name(QueryKind k) {
  switch (k) {
    case QueryKind::Box:
      return "box";
    case QueryKind::Sphere:
      return "sphere";
    case QueryKind::Knn:
      return "knn";
  }
  return "?";
}

std::string fmt_g(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.7g", v);
  return buf;
}

std::string fmt_v(const DVec3& v) {
  return "(" + fmt_g(v.x) + ", " + fmt_g(v.y) + ", " + fmt_g(v.z) + ")";
}

// An object found, as people and tools name it.
struct Named {
  std::string kind;    // "triangle", "segment", "point", "sphere", "plane"
  std::string object;  // its object's name
  uint32_t object_id;  // Scene object id
  uint32_t index;      // triangle, segment or point index in its object (else 0)
};

Named name_of(const Scene& s, const RangeHit& h) {
  if (h.plane >= 0) {
    const uint32_t id = s.plane_object(uint32_t(h.plane));
    return {"plane", s.object_name(id), id, 0};
  }
  const uint32_t id = s.prim_object(h.prim);
  const ObjectType type = s.object_type(id);
  const char* kind = type == ObjectType::Mesh     ? "triangle"
                     : type == ObjectType::Tubes  ? "segment"
                     : type == ObjectType::Points ? "point"
                                                  : "sphere";
  return {kind, s.object_name(id), id, s.prim_in_object(h.prim)};
}

// The structure the query walked, and what its build made.
struct StructureFigures {
  std::string text;
  nlohmann::ordered_json json;
};

StructureFigures structure_figures(const Aggregate& a) {
  StructureFigures f;
  f.json["accel"] = to_string(a.kind());
  f.json["memory_bytes"] = a.memory_bytes();
  char buf[512];
  if (!a.walks_structure()) {
    f.json["walked"] = false;
    if (std::holds_alternative<BruteForce>(a.structure())) {
      f.text = "none: every primitive tested";
    } else {
      std::snprintf(buf, sizeof buf,
                    "%s skipped: %zu primitives, all tested (scenes of at most %zu skip the "
                    "structure)",
                    to_string(a.kind()), a.prim_count(), Aggregate::kBruteForceMax);
      f.text = buf;
    }
    return f;
  }
  f.json["walked"] = true;
  if (!std::holds_alternative<BvhWalk>(a.structure())) {
    // The structure's own figures, as `rayscope accel compare` gives them.
    const AccelFigures q = a.figures();
    std::snprintf(buf, sizeof buf,
                  "%s: %zu nodes or cells, %zu holding primitives, depth %u, %.2f references "
                  "per primitive, built in %.1f ms",
                  to_string(a.kind()), q.nodes, q.leaves, q.depth, q.refs_per_prim,
                  q.build_seconds * 1e3);
    f.text = buf;
    f.json["nodes"] = q.nodes;
    f.json["leaves"] = q.leaves;
    f.json["depth"] = q.depth;
    f.json["references_per_primitive"] = q.refs_per_prim;
    f.json["build_ms"] = q.build_seconds * 1e3;
  } else {
    // The BVH walks: range queries walk the binary tree either way.
    const BvhQuality q = a.bvh().quality();
    std::snprintf(buf, sizeof buf,
                  "binary BVH (range queries walk its nodes whatever the ray walk): %u nodes, "
                  "%u leaves, depth %u, SAH cost %.4g",
                  q.nodes, q.leaves, q.depth, q.sah_cost);
    f.text = buf;
    f.json["nodes"] = q.nodes;
    f.json["leaves"] = q.leaves;
    f.json["depth"] = q.depth;
    f.json["sah_cost"] = q.sah_cost;
  }
  std::snprintf(buf, sizeof buf, "; %.1f KB in all", double(a.memory_bytes()) / 1024.0);
  f.text += buf;
  return f;
}

int run_query(const QueryOptions& o) {
  const Query q = parse_query(o);
  LoadedScene loaded = o.scene.load();
  for (const std::string& w : loaded.scene.summary().warnings)
    std::fprintf(stderr, "rayscope: warning: %s: %s\n",
                 o.scene.scene.empty() ? "default scene" : o.scene.scene.c_str(), w.c_str());
  const Scene& scene = loaded.scene;
  const Aggregate& accel = scene.accel();

  PixelCost cost;
  StatsRecorder::Observer obs(&cost);
  std::vector<RangeHit> found;
  const Vec3 a = scene.to_local(q.a);
  switch (q.kind) {
    case QueryKind::Box: {
      Bounds3 box;
      box.lo = a;
      box.hi = scene.to_local(q.b);
      found = accel.query_box(box, obs);
      break;
    }
    case QueryKind::Sphere:
      found = accel.query_sphere(a, float(q.radius), obs);
      break;
    case QueryKind::Knn:
      found = accel.nearest(a, q.k, obs);
      break;
  }
  const bool with_distance = q.kind != QueryKind::Box;
  const StructureFigures structure = structure_figures(accel);
  const size_t planes = scene.planes.size();

  std::string text;
  if (o.format == "json") {
    nlohmann::ordered_json j;
    nlohmann::ordered_json query;
    query["kind"] = kind_name(q.kind);
    auto arr = [](const DVec3& v) { return nlohmann::ordered_json::array({v.x, v.y, v.z}); };
    if (q.kind == QueryKind::Box) {
      query["min"] = arr(q.a);
      query["max"] = arr(q.b);
    } else {
      query["center"] = arr(q.a);
      if (q.kind == QueryKind::Sphere)
        query["radius"] = q.radius;
      else
        query["k"] = q.k;
    }
    j["query"] = query;
    nlohmann::ordered_json objects = nlohmann::ordered_json::array();
    for (const RangeHit& h : found) {
      const Named n = name_of(scene, h);
      nlohmann::ordered_json e;
      if (h.plane >= 0)
        e["plane"] = h.plane;
      else
        e["prim"] = h.prim;
      e["kind"] = n.kind;
      e["object"] = n.object;
      e["object_id"] = n.object_id;
      if (n.kind == "triangle" || n.kind == "segment" || n.kind == "point") e[n.kind] = n.index;
      if (with_distance) e["distance"] = h.distance;
      objects.push_back(e);
    }
    j["found"] = objects;
    j["cost"] = {{"nodes_visited", cost.nodes},     {"boxes_tested", cost.boxes},
                 {"nodes_culled", cost.culled},     {"primitives_tested", cost.prims},
                 {"planes_tested", planes},         {"objects_found", found.size()},
                 {"primitives", accel.prim_count()}};
    j["structure"] = structure.json;
    text = j.dump(2) + "\n";
  } else {
    char buf[512];
    switch (q.kind) {
      case QueryKind::Box:
        text = "box query: " + fmt_v(q.a) + " to " + fmt_v(q.b);
        break;
      case QueryKind::Sphere:
        text = "sphere query: within " + fmt_g(q.radius) + " of " + fmt_v(q.a);
        break;
      case QueryKind::Knn:
        text = "k-nearest query: the " + (q.k == 1 ? std::string() : std::to_string(q.k) + " ") +
               "nearest to " + fmt_v(q.a);
        break;
    }
    text += std::string(", --accel ") + to_string(accel.kind()) + "\n";
    std::snprintf(buf, sizeof buf, "found %zu object%s%s\n", found.size(),
                  found.size() == 1 ? "" : "s", found.empty() ? "" : ":");
    text += buf;
    for (const RangeHit& h : found) {
      const Named n = name_of(scene, h);
      std::string id =
          h.plane >= 0 ? "plane " + std::to_string(h.plane) : "prim " + std::to_string(h.prim);
      std::string what =
          n.kind == "triangle"
              ? "triangle " + std::to_string(n.index) + " of mesh \"" + n.object + "\""
          : n.kind == "segment"
              ? "segment " + std::to_string(n.index) + " of tubes \"" + n.object + "\""
          : n.kind == "point"
              ? "point " + std::to_string(n.index) + " of points \"" + n.object + "\""
              : n.kind + " \"" + n.object + "\"";
      std::snprintf(buf, sizeof buf, "  %-12s %-40s", id.c_str(), what.c_str());
      std::string line = buf;
      if (with_distance) line += "  distance " + fmt_g(h.distance);
      while (!line.empty() && line.back() == ' ') line.pop_back();
      text += line + "\n";
    }
    auto count = [](size_t n, const char* one, const char* many) {
      return std::to_string(n) + " " + (n == 1 ? one : many);
    };
    text += "cost: " + count(cost.nodes, "node", "nodes") + " visited, " +
            count(cost.boxes, "box", "boxes") + " tested, " + std::to_string(cost.culled) +
            " culled, " + std::to_string(cost.prims) + " of " +
            count(accel.prim_count(), "primitive", "primitives") + " tested, " +
            count(planes, "plane", "planes") + " tested beside the structure, " +
            std::to_string(found.size()) + " found\n";
    text += "structure: " + structure.text + "\n";
  }
  write_text_output(text, o.output);
  return 0;
}

}  // namespace

void add_query_command(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<QueryOptions>();
  CLI::App* cmd = app.add_subcommand(
      "query",
      "Range query through the chosen structure (--accel): the objects in a box, within a "
      "distance of a point, or nearest to it, and what the query cost");
  opts->scene.add_to(cmd, false);
  cmd->add_option("--box", opts->box,
                  "X0,Y0,Z0,X1,Y1,Z1: every object that intersects the closed box from corner "
                  "(X0,Y0,Z0) to corner (X1,Y1,Z1) (X0 <= X1 etc.; zero size allowed)");
  cmd->add_option("--sphere", opts->sphere,
                  "X,Y,Z,R: every object within distance R >= 0 of the point (X,Y,Z), with its "
                  "distance (0 on or inside it)");
  cmd->add_option("--knn", opts->knn,
                  "X,Y,Z,K: the K >= 1 objects nearest to the point (X,Y,Z), nearest first "
                  "(ties: primitives by index, then planes); all of them if there are fewer");
  cmd->add_option("--format", opts->format, "text or json")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();
  cmd->add_option("-o,--output", opts->output, "Write to this file instead of standard output");
  cmd->footer(
      "Coordinates are world coordinates of the scene. Objects are the scene's triangles "
      "(named by global primitive index and by their index in their mesh), spheres (solid "
      "balls) and planes (named by their index among the planes, after the primitives). The "
      "cost counts the walk: nodes (or cells) entered, boxes tested against the range, pushed "
      "nodes culled because a k-nearest range shrank, primitives tested exactly; the planes "
      "lie outside every structure and are always tested.");
  cmd->callback([opts, &exit_code]() { exit_code = run_query(*opts); });
}

}  // namespace rayscope::cli
