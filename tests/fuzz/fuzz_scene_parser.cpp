// libFuzzer target for the JSON scene parser (rayscope::parse_scene) and what
// every accepted scene goes through next: Scene::commit(), Camera::prepare()
// and tracing a few pixels.
//
// The contract under test (docs/scene-format.md, scene_io.h): any input either
// is rejected with a SceneError, or gives a scene that commits, whose camera
// can be prepared and that can be rendered. Everything else is a finding: a
// crash, a sanitizer report (ASan, UBSan, LeakSanitizer), another exception
// type, an exception from commit()/prepare() for a scene the parser accepted,
// a plane normal commit() could not normalise, or a hang (libFuzzer -timeout).
//
// Built twice: as a libFuzzer binary (RAYSCOPE_FUZZ=ON, clang) and, linked
// with replay_main.cpp, as a plain program that replays the committed corpus
// and regressions in every build (tests/fuzz/CMakeLists.txt).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "rayscope/render.h"
#include "rayscope/scene_io.h"

namespace {

[[noreturn]] void finding(const char* stage, const char* what) {
  std::fprintf(stderr, "fuzz_scene_parser: FINDING in %s: %s\n", stage, what);
  std::fflush(stderr);
  std::abort();
}

// Stands in for the VTK mesh reader without touching the filesystem: the file
// name picks one of a few small meshes, so that the fuzzer can reach every
// branch of mesh handling (load errors, smooth normals, vertex colors,
// non-finite vertices, empty meshes). A missing file throws like the reader,
// and so does a color_by array named "missing"; smooth false drops normals.
rayscope::TriangleMesh fake_one_mesh(const rayscope::MeshOptions& options) {
  const std::filesystem::path& path = options.file;
  const std::string file = path.filename().string();
  if (file.find("missing") != std::string::npos)
    throw std::runtime_error(path.string() + ": file not found");
  rayscope::TriangleMesh m;
  if (file.find("empty") != std::string::npos) return m;
  // A tetrahedron around the origin.
  m.positions = {{0, 1, 0}, {-1, -1, 1}, {1, -1, 1}, {0, -1, -1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  const std::string ext = path.extension().string();
  if (ext == ".ply" || ext == ".vtp")
    for (const rayscope::Vec3& p : m.positions) m.normals.push_back(glm::normalize(p));
  if (ext == ".vtp" || ext == ".vtk") m.colors.assign(m.positions.size(), {0.9f, 0.5f, 0.1f});
  if (file.find("nan") != std::string::npos) m.positions[3].x = std::nanf("");
  if (options.color_by && options.color_by->array.find("missing") != std::string::npos)
    throw rayscope::MeshOptionError("color_by.array: " + path.string() + " has no array '" +
                                    options.color_by->array + "'");
  if (!options.smooth) m.normals.clear();
  return m;
}

// A file named "blocks*" is composite: two meshes, one per block, and a
// warning for a third left out.
rayscope::LoadedMeshFile fake_mesh(const rayscope::MeshOptions& options) {
  rayscope::LoadedMeshFile loaded;
  loaded.meshes.push_back(fake_one_mesh(options));
  if (options.file.filename().string().rfind("blocks", 0) == 0) {
    loaded.meshes.push_back(loaded.meshes[0]);
    loaded.meshes[0].name = "block 1";
    loaded.meshes[1].name = "block 2 (second)";
    loaded.warnings.push_back(options.file.string() + ": block 3: no surface triangles, left out");
  }
  return loaded;
}

void check_accepted_scene(rayscope::LoadedScene& loaded) {
  rayscope::Scene& scene = loaded.scene;
  try {
    loaded.settings.validate();  // the parser checks the "render" block with it
    scene.commit();
  } catch (const std::exception& e) {
    finding("commit of an accepted scene", e.what());
  }
  // Directions the renderer normalises must come out as unit vectors: a zero,
  // NaN or precision-starved result means a value the parser accepted breaks
  // shading. (normalize() of a well-scaled float vector is within a few ulps of
  // length 1; 1e-3 only flags such breakage.)
  auto unit = [](const rayscope::Vec3& v) {
    return rayscope::all_finite(v) && std::abs(glm::length(v) - 1.0f) <= 1e-3f;
  };
  // (A plane keeps the normal it was given; the aggregate holds it normalized.)
  const std::vector<rayscope::PlaneRecord>& planes = scene.accel().plane_records();
  for (size_t k = 0; k < planes.size(); ++k)
    if (!unit(planes[k].normal))
      finding("commit",
              ("plane '" + scene.planes[k].name + "': normal is not a unit vector").c_str());
  for (const rayscope::Light& l : scene.lights)
    if (l.type == rayscope::Light::Type::Directional && !unit(glm::normalize(l.direction)))
      finding("light", ("light '" + l.name + "': direction does not normalise").c_str());

  // Every pixel of a tiny image (the middle one looks at look_at), with a
  // bounded ray tree: max_depth up to RenderSettings::kMaxDepth with
  // min_contribution 0 is a legitimate, exponentially expensive request.
  rayscope::RenderSettings rs = loaded.settings;
  rs.width = 5;
  rs.height = 3;
  rs.samples = 1;
  rs.max_depth = std::min(rs.max_depth, 3);
  try {
    scene.camera.prepare(rs.width, rs.height);
  } catch (const std::exception& e) {
    finding("camera of an accepted scene", e.what());
  }
  const rayscope::Camera& cam = scene.camera;
  if (!unit(cam.forward()) || !unit(cam.right()) || !unit(cam.up_vector()))
    finding("camera", "the view basis is not made of unit vectors");
  rayscope::RayCounters counters;
  rayscope::NullRecorder recorder;
  rayscope::with_scene_features(scene, [&]<bool kShadows, bool kSecondary>() {
    for (int y = 0; y < rs.height; ++y)
      for (int x = 0; x < rs.width; ++x)
        rayscope::render_pixel<rayscope::NullRecorder, kShadows, kSecondary>(scene, rs, x, y,
                                                                             counters, recorder);
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  rayscope::LoadedScene loaded;
  try {
    loaded = rayscope::parse_scene(text, "fuzz.json", "/nonexistent", fake_mesh);
  } catch (const rayscope::SceneError&) {
    return 0;  // rejected with the documented error: fine
  } catch (const std::exception& e) {
    finding("parse_scene (not a SceneError)", e.what());
  }
  check_accepted_scene(loaded);
  return 0;
}
