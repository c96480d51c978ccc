#include "rayscope/scene_io.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <type_traits>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "rayscope/input_file.h"
#include "rayscope/printable_text.h"

namespace rayscope {
namespace {

using json = nlohmann::json;

// Most leading bytes (a byte order mark, white space) read before the first
// character of a scene file is looked at; longer runs are left to the parser.
constexpr size_t kMaxJsonLead = 4096;

// Where the first value of JSON `text` starts, after an optional UTF-8 byte
// order mark and white space; npos when `text` holds nothing else.
size_t json_start(std::string_view text) {
  const size_t skip = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
  return text.find_first_not_of(" \t\r\n", skip);
}

// Walks the JSON with a path for error messages ("objects[2].radius").
struct Reader {
  std::string file;

  /// A scene is a JSON object: refused by its first character, before the
  /// rest is parsed, when it starts anything else.
  void check_object_start(std::string_view text) const {
    const size_t i = json_start(text);
    if (i != std::string::npos && text[i] != '{')
      fail("", "expected an object ('{'), the file starts with '" + std::string(text.substr(i, 1)) +
                   "'");
  }

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    // Keys, names and the JSON library's "last read" come from the file.
    throw SceneError(file + ": " +
                     printable_text(where.empty() ? what : where + ": " + what, kMaxMessageBytes));
  }

  void keys(const json& j, const std::string& where, std::initializer_list<const char*> allowed) {
    if (!j.is_object()) fail(where, "expected an object");
    std::set<std::string> ok(allowed.begin(), allowed.end());
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!ok.count(it.key())) fail(where, "unknown key '" + printable_text(it.key()) + "'");
  }

  /// A finite number that float can hold, kept in double.
  double number_d(const json& j, const std::string& where) {
    if (!j.is_number()) fail(where, "expected a number");
    double v = j.get<double>();
    if (!std::isfinite(v) || std::abs(v) > 3.0e38) fail(where, "number is not finite");
    return v;
  }
  float number(const json& j, const std::string& where) { return float(number_d(j, where)); }
  float number(const json& j, const std::string& where, float lo, float hi) {
    float v = number(j, where);
    if (v < lo || v > hi) {
      std::ostringstream s;
      s << "value " << v << " is outside [" << lo << ", " << hi << "]";
      fail(where, s.str());
    }
    return v;
  }
  /// An integer that fits T (a type check: the setting's range is checked elsewhere).
  template <class T>
  T integer(const json& j, const std::string& where) {
    if (!j.is_number_integer()) fail(where, "expected an integer");
    const bool fits = j.is_number_unsigned() ? std::in_range<T>(j.get<uint64_t>())
                                             : std::in_range<T>(j.get<int64_t>());
    if (!fits)
      fail(where, j.dump() + " is not a " + std::to_string(sizeof(T) * 8) + "-bit " +
                      (std::is_signed_v<T> ? "" : "unsigned ") + "integer");
    return j.get<T>();
  }
  bool boolean(const json& j, const std::string& where) {
    if (!j.is_boolean()) fail(where, "expected true or false");
    return j.get<bool>();
  }
  std::string string(const json& j, const std::string& where) {
    if (!j.is_string()) fail(where, "expected a string");
    return j.get<std::string>();
  }
  /// Three numbers in double: positions stay in double until they are made
  /// scene-local (Scene::to_local).
  DVec3 dvec3(const json& j, const std::string& where) {
    if (!j.is_array() || j.size() != 3) fail(where, "expected an array of 3 numbers");
    return DVec3(number_d(j[0], where + "[0]"), number_d(j[1], where + "[1]"),
                 number_d(j[2], where + "[2]"));
  }
  Vec3 vec3(const json& j, const std::string& where) { return Vec3(dvec3(j, where)); }
  Color color(const json& j, const std::string& where) {
    Vec3 c = vec3(j, where);
    if (c.r < 0 || c.g < 0 || c.b < 0) fail(where, "color components must be >= 0");
    return c;
  }
};

// An object's transform, in double precision: it is applied to the file's
// points before they are rounded to float (MeshOptions::to_scene).
glm::dmat4 parse_transform(Reader& r, const json& j, const std::string& where) {
  r.keys(j, where, {"translate", "rotate", "scale", "matrix"});
  if (j.contains("matrix")) {
    if (j.size() != 1) r.fail(where, "'matrix' cannot be combined with translate/rotate/scale");
    const json& m = j["matrix"];
    if (!m.is_array() || m.size() != 16)
      r.fail(where + ".matrix", "expected 16 numbers (row-major)");
    glm::dmat4 out(1.0);
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 4; ++col)
        out[col][row] =
            r.number_d(m[row * 4 + col], where + ".matrix[" + std::to_string(row * 4 + col) + "]");
    return out;
  }
  glm::dmat4 t(1.0);
  if (j.contains("translate")) t = glm::translate(t, r.dvec3(j["translate"], where + ".translate"));
  if (j.contains("rotate")) {
    DVec3 a = r.dvec3(j["rotate"], where + ".rotate");  // degrees about x, then y, then z
    t = glm::rotate(t, glm::radians(a.z), DVec3(0, 0, 1));
    t = glm::rotate(t, glm::radians(a.y), DVec3(0, 1, 0));
    t = glm::rotate(t, glm::radians(a.x), DVec3(1, 0, 0));
  }
  if (j.contains("scale")) {
    DVec3 sc;
    if (j["scale"].is_number())
      sc = DVec3(r.number_d(j["scale"], where + ".scale"));
    else
      sc = r.dvec3(j["scale"], where + ".scale");
    if (sc.x == 0 || sc.y == 0 || sc.z == 0) r.fail(where + ".scale", "scale must be non-zero");
    t = glm::scale(t, sc);
  }
  return t;
}

// A mesh's "color_by" object: an array, its association, a range and a map.
MeshColorBy parse_color_by(Reader& r, const json& j, const std::string& where) {
  r.keys(j, where, {"array", "association", "range", "map"});
  MeshColorBy c;
  if (!j.contains("array")) r.fail(where, "needs an 'array' (the name of a point or cell array)");
  c.array = r.string(j["array"], where + ".array");
  if (c.array.empty()) r.fail(where + ".array", "must not be empty");
  if (j.contains("association")) {
    const std::string a = r.string(j["association"], where + ".association");
    if (a == "point")
      c.association = MeshColorBy::Association::Point;
    else if (a == "cell")
      c.association = MeshColorBy::Association::Cell;
    else
      r.fail(where + ".association",
             "expected \"point\" or \"cell\", got \"" + printable_text(a) + "\"");
  }
  if (j.contains("range")) {
    const json& g = j["range"];
    if (!g.is_array() || g.size() != 2) r.fail(where + ".range", "expected [lo, hi]");
    const double lo = r.number(g[0], where + ".range[0]"), hi = r.number(g[1], where + ".range[1]");
    if (!(lo < hi)) r.fail(where + ".range", "lo must be less than hi");
    c.range = std::array<double, 2>{lo, hi};
  }
  if (j.contains("map")) {
    const std::string m = r.string(j["map"], where + ".map");
    auto it = std::find_if(kColorMapNames.begin(), kColorMapNames.end(),
                           [&](const char* name) { return m == name; });
    if (it == kColorMapNames.end()) {
      std::string names;
      for (const char* name : kColorMapNames)
        names += std::string(names.empty() ? "" : ", ") + "\"" + name + "\"";
      r.fail(where + ".map", "expected one of " + names + ", got \"" + printable_text(m) + "\"");
    }
    c.map = ColorMap(it - kColorMapNames.begin());
  }
  return c;
}

// The positions, radius or radii and colors of a tube or point set (TubeSet,
// PointSet): positions in world coordinates made scene-local, every radius in
// the range a sphere's may have.
template <class Set>
void parse_round_set(Reader& r, const Scene& s, const json& j, const std::string& w, Set& set) {
  if (!j.contains("positions")) r.fail(w, "needs 'positions' (an array of [x, y, z])");
  const json& ps = j["positions"];
  if (!ps.is_array() || ps.empty())
    r.fail(w + ".positions", "expected a non-empty array of [x, y, z]");
  for (size_t k = 0; k < ps.size(); ++k)
    set.positions.push_back(
        s.to_local(r.dvec3(ps[k], w + ".positions[" + std::to_string(k) + "]")));
  if (j.contains("radius") && j.contains("radii"))
    r.fail(w, "give either 'radius' or 'radii', not both");
  if (j.contains("radius")) set.radius = r.number(j["radius"], w + ".radius", 1e-30f, 1e30f);
  auto per_position = [&](const char* key, auto&& one) {
    if (!j.contains(key)) return;
    const json& a = j[key];
    const std::string wk = w + "." + key;
    if (!a.is_array() || a.size() != ps.size())
      r.fail(wk, "expected an array of " + std::to_string(ps.size()) + " (one per position)");
    for (size_t k = 0; k < a.size(); ++k) one(a[k], wk + "[" + std::to_string(k) + "]");
  };
  per_position("radii", [&](const json& v, const std::string& wk) {
    set.radii.push_back(r.number(v, wk, 1e-30f, 1e30f));
  });
  per_position("colors",
               [&](const json& v, const std::string& wk) { set.colors.push_back(r.color(v, wk)); });
}

}  // namespace

LoadedScene parse_scene(const std::string& text, const std::string& name,
                        const std::filesystem::path& base_dir, const MeshLoader& mesh_loader) {
  Reader r{name};
  r.check_object_start(text);
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    std::string msg = e.what();
    auto pos = msg.find("parse error");
    r.fail("", "malformed JSON: " + (pos == std::string::npos ? msg : msg.substr(pos)));
  } catch (const json::exception& e) {
    // e.g. out_of_range 406: "number overflow parsing '1e400'" (not a finite number).
    std::string msg = e.what();
    auto pos = msg.find("] ");
    r.fail("", "malformed JSON: " + (pos == std::string::npos ? msg : msg.substr(pos + 2)) +
                   " (not a finite number)");
  }
  r.keys(root, "",
         {"camera", "render", "materials", "lights", "objects", "background", "ambient_light"});
  LoadedScene out;
  Scene& s = out.scene;
  RenderSettings& rs = out.settings;
  s.lights.clear();
  if (root.contains("background")) s.background = r.color(root["background"], "background");
  if (root.contains("ambient_light"))
    s.ambient_light = r.color(root["ambient_light"], "ambient_light");

  if (root.contains("camera")) {
    const json& c = root["camera"];
    r.keys(c, "camera", {"eye", "look_at", "up", "fov", "parallel", "parallel_scale"});
    // The scene's local origin, when it is far from the world's, is the
    // point the camera looks at: what is rendered lies around it (within
    // about the viewing distance), and a scene moved as a whole then keeps
    // the same local coordinates (Scene::origin).
    DVec3 eye = DVec3(s.camera.eye), look_at = DVec3(s.camera.look_at);
    if (c.contains("eye")) eye = r.dvec3(c["eye"], "camera.eye");
    if (c.contains("look_at")) look_at = r.dvec3(c["look_at"], "camera.look_at");
    s.origin = choose_local_origin(look_at, glm::length(eye - look_at));
    s.camera.eye = s.to_local(eye);
    s.camera.look_at = s.to_local(look_at);
    if (c.contains("up")) s.camera.up = r.vec3(c["up"], "camera.up");
    if (c.contains("fov")) s.camera.vfov_degrees = r.number(c["fov"], "camera.fov");
    if (c.contains("parallel")) s.camera.parallel = r.boolean(c["parallel"], "camera.parallel");
    if (c.contains("parallel_scale"))
      s.camera.parallel_scale = r.number(c["parallel_scale"], "camera.parallel_scale");
    // The core's check of the camera rendering will use, reported here with
    // the file's name.
    const Camera& k = s.camera;
    if (std::string e = camera_error(DVec3(k.eye), DVec3(k.look_at), DVec3(k.up), k.vfov_degrees,
                                     k.parallel, k.parallel_scale);
        !e.empty())
      r.fail("camera", e);
  }

  if (root.contains("render")) {
    // Only types here; the ranges are RenderSettings::validate()'s.
    const json& j = root["render"];
    r.keys(j, "render",
           {"width", "height", "samples", "max_depth", "min_contribution", "seed", "max_samples",
            "target_error", "texture_filter"});
    if (j.contains("width")) rs.width = r.integer<int>(j["width"], "render.width");
    if (j.contains("height")) rs.height = r.integer<int>(j["height"], "render.height");
    if (j.contains("samples")) rs.samples = r.integer<int>(j["samples"], "render.samples");
    if (j.contains("max_depth")) rs.max_depth = r.integer<int>(j["max_depth"], "render.max_depth");
    if (j.contains("min_contribution"))
      rs.min_contribution = r.number(j["min_contribution"], "render.min_contribution");
    if (j.contains("seed")) rs.seed = r.integer<uint32_t>(j["seed"], "render.seed");
    if (j.contains("max_samples"))
      rs.max_samples = r.integer<int>(j["max_samples"], "render.max_samples");
    if (j.contains("target_error"))
      rs.target_error = r.number(j["target_error"], "render.target_error");
    if (j.contains("texture_filter"))
      rs.texture_filter = r.boolean(j["texture_filter"], "render.texture_filter");
    try {
      rs.validate();
    } catch (const std::invalid_argument& e) {
      r.fail("render", e.what());
    }
  }

  std::map<std::string, uint32_t> material_ids;
  s.materials = {Material{}};  // index 0: the default material
  material_ids["default"] = 0;
  if (root.contains("materials")) {
    const json& ms = root["materials"];
    if (!ms.is_object()) r.fail("materials", "expected an object of named materials");
    for (auto it = ms.begin(); it != ms.end(); ++it) {
      std::string w = "materials." + it.key();
      const json& j = it.value();
      r.keys(j, w,
             {"color", "ambient", "diffuse", "specular", "specular_color", "shininess",
              "reflectivity", "transparency", "ior", "model", "checker"});
      Material m;
      m.name = it.key();
      if (j.contains("color")) m.color = r.color(j["color"], w + ".color");
      if (j.contains("ambient")) m.ambient = r.number(j["ambient"], w + ".ambient", 0.0f, 1e3f);
      if (j.contains("diffuse")) m.diffuse = r.number(j["diffuse"], w + ".diffuse", 0.0f, 1e3f);
      if (j.contains("specular")) m.specular = r.number(j["specular"], w + ".specular", 0.0f, 1e3f);
      if (j.contains("specular_color"))
        m.specular_color = r.color(j["specular_color"], w + ".specular_color");
      if (j.contains("shininess"))
        m.shininess = r.number(j["shininess"], w + ".shininess", 0.0f, 1e5f);
      if (j.contains("reflectivity"))
        m.reflectivity = r.number(j["reflectivity"], w + ".reflectivity", 0.0f, 1.0f);
      if (j.contains("transparency"))
        m.transparency = r.number(j["transparency"], w + ".transparency", 0.0f, 1.0f);
      if (m.reflectivity + m.transparency > 1.0f)
        r.fail(w, "reflectivity + transparency must not exceed 1");
      if (j.contains("ior")) m.ior = r.number(j["ior"], w + ".ior", 1e-3f, 100.0f);
      if (j.contains("model")) {
        std::string model = r.string(j["model"], w + ".model");
        if (model == "phong")
          m.model = ShadingModel::Phong;
        else if (model == "blinn-phong")
          m.model = ShadingModel::BlinnPhong;
        else
          r.fail(w + ".model",
                 "expected \"phong\" or \"blinn-phong\", got \"" + printable_text(model) + "\"");
      }
      if (j.contains("checker")) {
        const json& c = j["checker"];
        r.keys(c, w + ".checker", {"color", "size"});
        m.checker = true;
        if (c.contains("color")) m.checker_color = r.color(c["color"], w + ".checker.color");
        if (c.contains("size"))
          m.checker_size = r.number(c["size"], w + ".checker.size", 1e-30f, 1e30f);
      }
      if (it.key() == "default") {
        s.materials[0] = m;
      } else {
        material_ids[it.key()] = uint32_t(s.materials.size());
        s.materials.push_back(m);
      }
    }
  }
  auto material_ref = [&](const json& j, const std::string& where) -> uint32_t {
    if (!j.contains("material")) return 0;
    std::string mname = r.string(j["material"], where + ".material");
    auto it = material_ids.find(mname);
    if (it == material_ids.end())
      r.fail(where + ".material", "unknown material '" + printable_text(mname) + "'");
    return it->second;
  };

  if (root.contains("lights")) {
    const json& ls = root["lights"];
    if (!ls.is_array()) r.fail("lights", "expected an array");
    for (size_t i = 0; i < ls.size(); ++i) {
      std::string w = "lights[" + std::to_string(i) + "]";
      const json& j = ls[i];
      r.keys(j, w,
             {"type", "name", "position", "direction", "color", "intensity", "attenuation",
              "shadows"});
      Light l;
      std::string type = j.contains("type") ? r.string(j["type"], w + ".type") : "point";
      l.name = j.contains("name") ? r.string(j["name"], w + ".name") : "light" + std::to_string(i);
      DVec3 position(0.0);
      if (type == "point") {
        l.type = Light::Type::Point;
        if (!j.contains("position")) r.fail(w, "a point light needs a position");
        position = r.dvec3(j["position"], w + ".position");
        if (j.contains("direction")) r.fail(w, "a point light has no direction");
      } else if (type == "directional") {
        l.type = Light::Type::Directional;
        if (!j.contains("direction")) r.fail(w, "a directional light needs a direction");
        l.direction = r.vec3(j["direction"], w + ".direction");
        if (j.contains("position")) r.fail(w, "a directional light has no position");
      } else {
        r.fail(w + ".type",
               "expected \"point\" or \"directional\", got \"" + printable_text(type) + "\"");
      }
      if (j.contains("color")) l.color = r.vec3(j["color"], w + ".color");
      if (j.contains("intensity")) l.intensity = r.number(j["intensity"], w + ".intensity");
      if (j.contains("attenuation")) l.attenuation = r.vec3(j["attenuation"], w + ".attenuation");
      const bool point = l.type == Light::Type::Point;
      if (std::string e = light_error(l.type, point ? position : DVec3(l.direction), DVec3(l.color),
                                      l.intensity, DVec3(l.attenuation));
          !e.empty())
        r.fail(w, e);
      if (point)
        l.position = s.to_local(position);
      else
        l.direction = normalize_any_length(l.direction);  // only its direction counts
      if (j.contains("shadows")) l.casts_shadows = r.boolean(j["shadows"], w + ".shadows");
      s.lights.push_back(l);
    }
  }

  if (root.contains("objects")) {
    const json& os = root["objects"];
    if (!os.is_array()) r.fail("objects", "expected an array");
    for (size_t i = 0; i < os.size(); ++i) {
      std::string w = "objects[" + std::to_string(i) + "]";
      const json& j = os[i];
      if (!j.is_object()) r.fail(w, "expected an object");
      if (!j.contains("type")) r.fail(w, "missing 'type' (sphere, plane, mesh, tubes or points)");
      std::string type = r.string(j["type"], w + ".type");
      std::string oname =
          j.contains("name") ? r.string(j["name"], w + ".name") : type + std::to_string(i);
      if (type == "sphere") {
        r.keys(j, w, {"type", "name", "center", "radius", "material"});
        Sphere sp;
        sp.name = oname;
        if (!j.contains("center") || !j.contains("radius"))
          r.fail(w, "a sphere needs center and radius");
        sp.center = s.to_local(r.dvec3(j["center"], w + ".center"));
        sp.radius = r.number(j["radius"], w + ".radius", 1e-30f, 1e30f);
        sp.material = material_ref(j, w);
        s.spheres.push_back(sp);
      } else if (type == "plane") {
        r.keys(j, w, {"type", "name", "point", "normal", "material"});
        Plane p;
        p.name = oname;
        p.point = s.to_local(j.contains("point") ? r.dvec3(j["point"], w + ".point") : DVec3(0.0));
        if (j.contains("normal")) p.normal = r.vec3(j["normal"], w + ".normal");
        if (glm::dot(p.normal, p.normal) == 0.0f) r.fail(w + ".normal", "must be non-zero");
        p.material = material_ref(j, w);
        s.planes.push_back(p);
      } else if (type == "mesh") {
        r.keys(j, w,
               {"type", "name", "file", "transform", "material", "smooth", "color_by",
                "line_radius", "point_radius", "radius_array"});
        if (!j.contains("file")) r.fail(w, "a mesh needs a 'file'");
        MeshOptions mo;
        mo.file = r.string(j["file"], w + ".file");
        if (mo.file.is_relative()) mo.file = base_dir / mo.file;
        if (j.contains("smooth")) mo.smooth = r.boolean(j["smooth"], w + ".smooth");
        if (j.contains("color_by")) mo.color_by = parse_color_by(r, j["color_by"], w + ".color_by");
        if (j.contains("line_radius"))
          mo.line_radius = r.number(j["line_radius"], w + ".line_radius", 1e-30f, 1e30f);
        if (j.contains("point_radius"))
          mo.point_radius = r.number(j["point_radius"], w + ".point_radius", 1e-30f, 1e30f);
        if (j.contains("radius_array")) {
          mo.radius_array = r.string(j["radius_array"], w + ".radius_array");
          if (mo.radius_array.empty()) r.fail(w + ".radius_array", "must not be empty");
        }
        if (!mesh_loader) r.fail(w, "no mesh reader available for '" + mo.file.string() + "'");
        glm::dmat4 t(1.0);
        if (j.contains("transform")) {
          t = parse_transform(r, j["transform"], w + ".transform");
          if (glm::determinant(glm::dmat3(t)) == 0.0)
            r.fail(w + ".transform", "transform is singular");
        }
        mo.to_scene = glm::translate(glm::dmat4(1.0), -s.origin) * t;
        LoadedMeshFile loaded;
        try {
          loaded = mesh_loader(mo);
        } catch (const MeshOptionError& e) {
          // what() is "KEY: problem", KEY within the object (e.g. color_by.array).
          throw SceneError(name + ": " + w + "." + e.what());
        } catch (const std::exception& e) {
          std::string msg = e.what();
          throw SceneError(name + ": " + w + ".file: " + msg);
        }
        for (const std::string& warning :
             add_mesh_file_objects(s, std::move(loaded), oname, material_ref(j, w)))
          out.warnings.push_back(name + ": " + w + ".file: " + warning);
      } else if (type == "tubes") {
        r.keys(j, w,
               {"type", "name", "positions", "segments", "radius", "radii", "colors", "material"});
        TubeSet t;
        t.name = oname;
        parse_round_set(r, s, j, w, t);
        if (j.contains("segments")) {
          const json& sg = j["segments"];
          if (!sg.is_array()) r.fail(w + ".segments", "expected an array of [i, j] index pairs");
          for (size_t k = 0; k < sg.size(); ++k) {
            const std::string wk = w + ".segments[" + std::to_string(k) + "]";
            if (!sg[k].is_array() || sg[k].size() != 2) r.fail(wk, "expected [i, j]");
            glm::uvec2 e;
            for (int c = 0; c < 2; ++c) {
              e[c] = r.integer<uint32_t>(sg[k][c], wk);
              if (e[c] >= t.positions.size())
                r.fail(wk, "index " + std::to_string(e[c]) + " is not below the " +
                               std::to_string(t.positions.size()) + " positions");
            }
            t.segments.push_back(e);
          }
        } else {
          // One polyline through the positions in order.
          for (uint32_t k = 1; k < t.positions.size(); ++k) t.segments.push_back({k - 1, k});
        }
        if (t.segments.empty()) r.fail(w, "tubes need at least one segment (two positions)");
        t.material = material_ref(j, w);
        s.tubes.push_back(std::move(t));
      } else if (type == "points") {
        r.keys(j, w, {"type", "name", "positions", "radius", "radii", "colors", "material"});
        PointSet p;
        p.name = oname;
        parse_round_set(r, s, j, w, p);
        p.material = material_ref(j, w);
        s.points.push_back(std::move(p));
      } else {
        r.fail(w + ".type",
               "expected \"sphere\", \"plane\", \"mesh\", \"tubes\" or \"points\", got \"" +
                   printable_text(type) + "\"");
      }
    }
  }
  return out;
}

std::vector<std::string> add_mesh_file_objects(Scene& scene, LoadedMeshFile&& file,
                                               const std::string& name, uint32_t material) {
  auto add = [&](auto& objects, auto& to) {
    for (auto& o : objects) {
      o.name = o.name.empty() ? name : name + " " + o.name;
      o.material = material;
      to.push_back(std::move(o));
    }
  };
  add(file.meshes, scene.meshes);
  add(file.tubes, scene.tubes);
  add(file.points, scene.points);
  return std::move(file.warnings);
}

LoadedScene load_scene(const std::filesystem::path& path, const MeshLoader& mesh_loader) {
  if (const std::string problem = input_file_problem(path); !problem.empty())
    throw SceneError(path.string() + ": " + problem);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path.string() + ": cannot open file");
  // The first character decides whether the file can be a scene at all,
  // before the rest is read and parsed (a 200 MB array took 9 s and 937 MB).
  std::string head;
  for (int c; head.size() < kMaxJsonLead && (c = in.get()) != EOF;) {
    head.push_back(char(c));
    if (json_start(head) != std::string::npos) break;
  }
  Reader{path.string()}.check_object_start(head);
  std::ostringstream ss;
  ss << head << in.rdbuf();
  return parse_scene(ss.str(), path.string(), path.parent_path(), mesh_loader);
}

}  // namespace rayscope
