#include "rayscope/shapes.h"

#include <map>
#include <utility>

namespace rayscope {

TriangleMesh subdivide(const TriangleMesh& in) {
  TriangleMesh out;
  out.name = in.name;
  out.material = in.material;
  out.positions = in.positions;
  out.normals = in.normals;
  out.colors = in.colors;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
  auto midpoint = [&](uint32_t a, uint32_t b) {
    auto key = std::minmax(a, b);
    auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    uint32_t i = uint32_t(out.positions.size());
    out.positions.push_back(0.5f * (in.positions[a] + in.positions[b]));
    if (!in.normals.empty()) {
      Vec3 n = in.normals[a] + in.normals[b];
      float l = glm::length(n);
      out.normals.push_back(l > 0.0f ? n / l : in.normals[a]);
    }
    if (!in.colors.empty()) out.colors.push_back(0.5f * (in.colors[a] + in.colors[b]));
    mid.emplace(key, i);
    return i;
  };
  out.triangles.reserve(in.triangles.size() * 4);
  for (const glm::uvec3& t : in.triangles) {
    uint32_t ab = midpoint(t.x, t.y), bc = midpoint(t.y, t.z), ca = midpoint(t.z, t.x);
    out.triangles.emplace_back(t.x, ab, ca);
    out.triangles.emplace_back(ab, t.y, bc);
    out.triangles.emplace_back(ca, bc, t.z);
    out.triangles.emplace_back(ab, bc, ca);
  }
  return out;
}

TriangleMesh make_icosphere(const Vec3& center, float radius, int levels) {
  const float g = (1.0f + std::sqrt(5.0f)) * 0.5f;
  TriangleMesh m;
  m.name = "icosphere";
  m.positions = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                 {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (Vec3& p : m.positions) p = glm::normalize(p);
  for (int i = 0; i < levels; ++i) {
    m = subdivide(m);
    for (Vec3& p : m.positions) p = glm::normalize(p);
  }
  m.normals = m.positions;
  for (Vec3& p : m.positions) p = center + radius * p;
  return m;
}

TriangleMesh make_torus(const Vec3& center, float R, float r, int segments, int sides) {
  TriangleMesh m;
  m.name = "torus";
  for (int i = 0; i < segments; ++i) {
    float u = 2.0f * kPi * float(i) / float(segments);
    Vec3 ring(std::cos(u), 0.0f, std::sin(u));
    // Rainbow around the ring.
    Color col = 0.5f + 0.5f * Vec3(std::cos(u), std::cos(u + 2.0944f), std::cos(u + 4.1888f));
    for (int j = 0; j < sides; ++j) {
      float v = 2.0f * kPi * float(j) / float(sides);
      Vec3 n = std::cos(v) * ring + Vec3(0.0f, std::sin(v), 0.0f);
      m.positions.push_back(center + R * ring + r * n);
      m.normals.push_back(n);
      m.colors.push_back(col);
    }
  }
  auto id = [&](int i, int j) { return uint32_t((i % segments) * sides + (j % sides)); };
  for (int i = 0; i < segments; ++i)
    for (int j = 0; j < sides; ++j) {
      uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      m.triangles.emplace_back(a, c, b);
      m.triangles.emplace_back(a, d, c);
    }
  return m;
}

Scene make_default_scene() {
  Scene s;
  s.camera.eye = Vec3(0.0f, 2.2f, 7.5f);
  s.camera.look_at = Vec3(0.0f, 0.8f, 0.0f);
  s.camera.up = Vec3(0.0f, 1.0f, 0.0f);
  s.camera.vfov_degrees = 40.0f;
  s.background = Color(0.55f, 0.7f, 0.9f);
  s.ambient_light = Color(1.0f);

  Material floor;
  floor.name = "checker";
  floor.color = Color(0.9f);
  floor.checker = true;
  floor.checker_color = Color(0.15f);
  floor.checker_size = 1.0f;
  floor.ambient = 0.15f;
  floor.diffuse = 0.85f;
  floor.reflectivity = 0.1f;
  Material mirror;
  mirror.name = "mirror";
  mirror.color = Color(0.9f);
  mirror.ambient = 0.0f;
  mirror.specular = 0.6f;
  mirror.shininess = 200.0f;
  mirror.reflectivity = 0.85f;
  Material glass;
  glass.name = "glass";
  glass.color = Color(1.0f);
  glass.ambient = 0.0f;
  glass.specular = 0.8f;
  glass.shininess = 300.0f;
  glass.transparency = 0.95f;
  glass.ior = 1.5f;
  Material plastic;
  plastic.name = "plastic";
  plastic.color = Color(0.8f);
  plastic.ambient = 0.15f;
  plastic.diffuse = 0.8f;
  plastic.specular = 0.4f;
  plastic.shininess = 48.0f;
  s.materials = {floor, mirror, glass, plastic};

  s.planes.push_back(Plane{"floor", Vec3(0.0f), Vec3(0.0f, 1.0f, 0.0f), 0});
  s.spheres.push_back(Sphere{"mirror sphere", Vec3(-1.3f, 1.0f, -0.6f), 1.0f, 1});
  s.spheres.push_back(Sphere{"glass sphere", Vec3(0.2f, 0.8f, 1.5f), 0.8f, 2});
  TriangleMesh torus = make_torus(Vec3(1.9f, 0.3f, -0.9f), 0.75f, 0.3f, 48, 24);
  torus.material = 3;
  s.meshes.push_back(std::move(torus));

  Light key;
  key.name = "key";
  key.position = Vec3(-4.0f, 7.0f, 5.0f);
  key.intensity = 0.8f;
  Light fill;
  fill.name = "fill";
  fill.type = Light::Type::Directional;
  fill.direction = Vec3(0.6f, -1.0f, -0.3f);
  fill.color = Color(1.0f, 0.95f, 0.85f);
  fill.intensity = 0.35f;
  s.lights = {key, fill};
  return s;
}

}  // namespace rayscope
