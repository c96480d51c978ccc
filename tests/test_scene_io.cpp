// Scene files (scene_io.h): a valid scene parses to the expected values;
// every kind of bad input throws a SceneError whose what() is one line "FILE:
// problem" naming the problem. Mesh files (OBJ, read by the tests' own
// loader: the core has no mesh reader) are written at run time into a
// temporary folder. The rayscope command's loader with scene files:
// tests/vtk/test_vtk_mesh_files.cpp.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <sstream>
#include <stdexcept>
#include <vector>

#include "obj_samples.h"
#include "rayscope/printable_text.h"
#include "rayscope/scene_io.h"

namespace {

using namespace rayscope;
namespace fs = std::filesystem;

// A regular tetrahedron (4 triangles).
const char* kTetraObj = R"(# tetrahedron
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4
)";

using rstest::kQuadObj;

// A cube's boundary as six quads: 12 triangles.
const char* kHexObj = R"(# cube
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
)";

// The mesh loader of these tests: OBJ files of vertices and faces (a face of
// n corners fanned into n - 2 triangles), the points moved by
// MeshOptions::to_scene in double before they are rounded, errors as "FILE:
// problem". A stand-in for the rayscope command's loader
// (load_obj: its files, formats and messages are tested with
// scene files in tests/vtk/test_vtk_mesh_files.cpp), so that the parser's
// tests need no VTK.
LoadedMeshFile load_obj(const MeshOptions& mo) {
  std::ifstream in(mo.file);
  if (!in) throw std::runtime_error(mo.file.string() + ": cannot be opened");
  TriangleMesh m;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    if (tag == "v") {
      glm::dvec4 p(0.0, 0.0, 0.0, 1.0);
      words >> p.x >> p.y >> p.z;
      const glm::dvec4 q = mo.to_scene * p;
      m.positions.push_back(Vec3(float(q.x), float(q.y), float(q.z)));
    } else if (tag == "f") {
      std::vector<uint32_t> corners;
      for (long i; words >> i;) corners.push_back(uint32_t(i - 1));
      for (size_t k = 2; k < corners.size(); ++k)
        m.triangles.push_back({corners[0], corners[k - 1], corners[k]});
    }
  }
  LoadedMeshFile f;
  f.meshes.push_back(std::move(m));
  return f;
}

class SceneIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rayscope_test_scene_io_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    write("tetra.obj", kTetraObj);
    write("quad.obj", kQuadObj);
    write("hex.obj", kHexObj);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path write(const std::string& name, const std::string& text) {
    fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p;
  }

  // Loads `text` as a scene file named `name` and expects a SceneError whose
  // message is one line, starts with the file name and contains `problem`.
  void expect_error(const std::string& name, const std::string& text, const std::string& problem) {
    fs::path p = write(name, text);
    try {
      load_scene(p, load_obj);
      ADD_FAILURE() << name << ": no error, expected one about \"" << problem << "\"";
    } catch (const SceneError& e) {
      std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
      EXPECT_EQ(msg.find('\r'), std::string::npos) << "not one line: " << msg;
      EXPECT_EQ(msg.rfind(p.string() + ": ", 0), 0u) << "does not start with the file: " << msg;
      EXPECT_NE(msg.find(problem), std::string::npos)
          << name << ": \"" << msg << "\" does not name the problem \"" << problem << "\"";
    } catch (const std::exception& e) {
      ADD_FAILURE() << name << ": threw a non-SceneError: " << e.what();
    }
  }

  fs::path dir_;
};

TEST_F(SceneIo, ValidSceneParsesToTheExpectedValues) {
  const char* text = R"({
    "camera": {"eye": [1, 2, 3], "look_at": [0, 0.5, 0], "up": [0, 1, 0], "fov": 35},
    "render": {"width": 320, "height": 200, "samples": 3, "max_depth": 4,
               "min_contribution": 0.01, "seed": 42},
    "background": [0.1, 0.2, 0.3],
    "ambient_light": [0.5, 0.25, 1],
    "materials": {
      "red": {"color": [0.9, 0.1, 0.1], "ambient": 0.2, "diffuse": 0.7, "specular": 0.3,
              "shininess": 64, "model": "phong"},
      "glass": {"transparency": 0.9, "ior": 1.33, "reflectivity": 0.05},
      "floor": {"checker": {"color": [0, 0, 0], "size": 0.5}}
    },
    "lights": [
      {"type": "point", "name": "key", "position": [0, 5, 0], "intensity": 2,
       "attenuation": [1, 0.1, 0]},
      {"type": "directional", "direction": [0, -1, 0], "color": [1, 0.9, 0.8], "shadows": false}
    ],
    "objects": [
      {"type": "sphere", "name": "ball", "center": [0, 1, 0], "radius": 0.5, "material": "red"},
      {"type": "plane", "point": [0, 0, 0], "normal": [0, 2, 0], "material": "floor"},
      {"type": "mesh", "file": "tetra.obj", "material": "glass",
       "transform": {"translate": [1, 0, 0], "scale": 2}},
      {"type": "mesh", "file": "quad.obj", "name": "q"},
      {"type": "mesh", "file": "hex.obj"}
    ]
  })";
  fs::path p = write("good.json", text);
  LoadedScene ls = load_scene(p, load_obj);
  const Scene& s = ls.scene;
  EXPECT_EQ(s.camera.eye, Vec3(1, 2, 3));
  EXPECT_EQ(s.camera.look_at, Vec3(0, 0.5f, 0));
  EXPECT_EQ(s.camera.vfov_degrees, 35.0f);
  EXPECT_FALSE(s.camera.parallel);
  EXPECT_EQ(ls.settings.width, 320);
  EXPECT_EQ(ls.settings.height, 200);
  EXPECT_EQ(ls.settings.samples, 3);
  EXPECT_EQ(ls.settings.max_depth, 4);
  EXPECT_EQ(ls.settings.min_contribution, 0.01f);
  EXPECT_EQ(ls.settings.seed, 42u);
  EXPECT_EQ(s.background, Vec3(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(s.ambient_light, Vec3(0.5f, 0.25f, 1.0f));

  // Materials: "default" plus the three named ones, looked up by name.
  ASSERT_EQ(s.materials.size(), 4u);
  EXPECT_EQ(s.materials[0].name, "default");
  auto mat = [&](const std::string& name) -> uint32_t {
    for (uint32_t i = 0; i < s.materials.size(); ++i)
      if (s.materials[i].name == name) return i;
    ADD_FAILURE() << "no material " << name;
    return 0;
  };
  const Material& red = s.materials[mat("red")];
  EXPECT_EQ(red.color, Vec3(0.9f, 0.1f, 0.1f));
  EXPECT_EQ(red.ambient, 0.2f);
  EXPECT_EQ(red.diffuse, 0.7f);
  EXPECT_EQ(red.specular, 0.3f);
  EXPECT_EQ(red.shininess, 64.0f);
  EXPECT_EQ(red.model, ShadingModel::Phong);
  const Material& glass = s.materials[mat("glass")];
  EXPECT_EQ(glass.transparency, 0.9f);
  EXPECT_EQ(glass.reflectivity, 0.05f);
  EXPECT_EQ(glass.ior, 1.33f);
  EXPECT_EQ(glass.model, ShadingModel::BlinnPhong);
  const Material& floor = s.materials[mat("floor")];
  EXPECT_TRUE(floor.checker);
  EXPECT_EQ(floor.checker_color, Vec3(0.0f));
  EXPECT_EQ(floor.checker_size, 0.5f);

  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].type, Light::Type::Point);
  EXPECT_EQ(s.lights[0].name, "key");
  EXPECT_EQ(s.lights[0].position, Vec3(0, 5, 0));
  EXPECT_EQ(s.lights[0].intensity, 2.0f);
  EXPECT_EQ(s.lights[0].attenuation, Vec3(1, 0.1f, 0));
  EXPECT_TRUE(s.lights[0].casts_shadows);
  EXPECT_EQ(s.lights[1].type, Light::Type::Directional);
  EXPECT_EQ(s.lights[1].direction, Vec3(0, -1, 0));
  EXPECT_EQ(s.lights[1].color, Vec3(1, 0.9f, 0.8f));
  EXPECT_FALSE(s.lights[1].casts_shadows);

  ASSERT_EQ(s.spheres.size(), 1u);
  EXPECT_EQ(s.spheres[0].name, "ball");
  EXPECT_EQ(s.spheres[0].center, Vec3(0, 1, 0));
  EXPECT_EQ(s.spheres[0].radius, 0.5f);
  EXPECT_EQ(s.spheres[0].material, mat("red"));
  ASSERT_EQ(s.planes.size(), 1u);
  EXPECT_EQ(s.planes[0].material, mat("floor"));

  ASSERT_EQ(s.meshes.size(), 3u);
  EXPECT_EQ(s.meshes[0].triangles.size(), 4u);
  EXPECT_EQ(s.meshes[0].material, mat("glass"));
  EXPECT_EQ(s.meshes[1].triangles.size(), 3u);
  EXPECT_EQ(s.meshes[1].name, "q");
  EXPECT_EQ(s.meshes[1].material, 0u);
  EXPECT_EQ(s.meshes[2].triangles.size(), 12u);
  // The transform scales by 2, then translates by (1, 0, 0): the tetrahedron's
  // corners (0,0,0), (1,0,0), (0,1,0), (0,0,1) become these.
  std::vector<Vec3> want = {{1, 0, 0}, {3, 0, 0}, {1, 2, 0}, {1, 0, 2}};
  for (const Vec3& w : want)
    EXPECT_NE(std::find(s.meshes[0].positions.begin(), s.meshes[0].positions.end(), w),
              s.meshes[0].positions.end())
        << "missing corner " << w.x << "," << w.y << "," << w.z;

  // The parsed scene is usable.
  LoadedScene copy = ls;
  EXPECT_NO_THROW(copy.scene.commit());
  EXPECT_EQ(copy.scene.summary().triangles, 4u + 3u + 12u);
  EXPECT_TRUE(copy.scene.summary().refractive);
}

TEST_F(SceneIo, TubesAndPointsParse) {
  // A polyline without segments (one through the positions in order), tubes
  // with segments, radii and colors, points with one radius; materials by
  // name; positions made scene-local like every position.
  const LoadedScene l = parse_scene(R"({
    "materials": {"red": {"color": [1, 0, 0]}},
    "objects": [
      {"type": "tubes", "name": "line", "positions": [[0, 0, 0], [1, 0, 0], [1, 1, 0]],
       "radius": 0.25, "material": "red"},
      {"type": "tubes", "positions": [[0, 0, 0], [0, 0, 1], [0, 0, 2]],
       "segments": [[0, 2], [2, 1]], "radii": [0.1, 0.2, 0.3],
       "colors": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]},
      {"type": "points", "name": "cloud", "positions": [[5, 5, 5], [6, 6, 6]], "radius": 0.5,
       "colors": [[0, 0, 1], [0, 1, 1]]}
    ]})",
                                    "inline", dir_, load_obj);
  const Scene& s = l.scene;
  ASSERT_EQ(s.tubes.size(), 2u);
  ASSERT_EQ(s.points.size(), 1u);
  EXPECT_EQ(s.tubes[0].name, "line");
  EXPECT_EQ(s.tubes[0].positions.size(), 3u);
  EXPECT_EQ(s.tubes[0].segments, (std::vector<glm::uvec2>{{0, 1}, {1, 2}}));
  EXPECT_EQ(s.tubes[0].radius, 0.25f);
  EXPECT_TRUE(s.tubes[0].radii.empty());
  EXPECT_EQ(s.materials[s.tubes[0].material].name, "red");
  EXPECT_EQ(s.tubes[1].name, "tubes1");
  EXPECT_EQ(s.tubes[1].segments, (std::vector<glm::uvec2>{{0, 2}, {2, 1}}));
  EXPECT_EQ(s.tubes[1].radii, (std::vector<float>{0.1f, 0.2f, 0.3f}));
  EXPECT_EQ(s.tubes[1].colors.size(), 3u);
  EXPECT_EQ(s.tubes[1].material, 0u);
  EXPECT_EQ(s.points[0].name, "cloud");
  EXPECT_EQ(s.points[0].positions[1], Vec3(6, 6, 6));
  EXPECT_EQ(s.points[0].radius, 0.5f);
  EXPECT_EQ(s.points[0].colors[1], Color(0, 1, 1));
  Scene committed = s;
  committed.commit();
  EXPECT_EQ(committed.summary().tube_segments, 4u);
  EXPECT_EQ(committed.summary().points, 2u);
}

TEST_F(SceneIo, EveryBadInputIsOneLineNamingFileAndProblem) {
  expect_error("malformed.json", R"({"camera": {"eye": [0, 1, 2]})", "malformed JSON");
  expect_error("trailing.json", R"({"background": [0, 0, 0],})", "malformed JSON");
  expect_error("unknown_key.json", R"({"colour": [1, 1, 1]})", "unknown key 'colour'");
  expect_error("unknown_material_key.json", R"({"materials": {"m": {"shine": 3}}})",
               "materials.m: unknown key 'shine'");
  expect_error("unknown_camera_key.json", R"({"camera": {"eyes": [0, 0, 5]}})",
               "camera: unknown key 'eyes'");
  expect_error("unknown_object_key.json",
               R"({"objects": [{"type": "sphere", "center": [0,0,0], "radius": 1, "r": 2}]})",
               "objects[0]: unknown key 'r'");
  expect_error("unknown_checker_key.json",
               R"({"materials": {"m": {"checker": {"colour": [0,0,0]}}}})",
               "materials.m.checker: unknown key 'colour'");
  expect_error("wrong_type.json",
               R"({"objects": [{"type": "sphere", "center": [0,0,0], "radius": "big"}]})",
               "objects[0].radius: expected a number");
  expect_error("wrong_type_int.json", R"({"render": {"width": 1.5}})",
               "render.width: expected an integer");
  expect_error("wrong_type_bool.json", R"({"lights": [{"position": [0,1,0], "shadows": "yes"}]})",
               "lights[0].shadows: expected true or false");
  expect_error("wrong_type_vec.json", R"({"camera": {"eye": [0, 1]}})",
               "camera.eye: expected an array of 3 numbers");
  expect_error("not_an_object.json", R"([1, 2, 3])", "expected an object");
  expect_error("huge.json",
               R"({"objects": [{"type": "sphere", "center": [0,0,0], "radius": 1e400}]})", "1e400");
  expect_error("huge_float.json",
               R"({"objects": [{"type": "sphere", "center": [0,0,1e39], "radius": 1}]})",
               "objects[0].center[2]: number is not finite");
  expect_error("negative_radius.json",
               R"({"objects": [{"type": "sphere", "center": [0,0,0], "radius": -1}]})",
               "objects[0].radius: value -1 is outside");
  expect_error("zero_radius.json",
               R"({"objects": [{"type": "sphere", "center": [0,0,0], "radius": 0}]})",
               "objects[0].radius");
  expect_error("unknown_material.json",
               R"({"objects": [{"type": "sphere", "center": [0,0,0], "radius": 1,
                   "material": "nope"}]})",
               "objects[0].material: unknown material 'nope'");
  // The loader's error, under the object's key (the command's loader's own
  // messages: tests/vtk/test_vtk_mesh_files.cpp).
  expect_error("missing_mesh.json", R"({"objects": [{"type": "mesh", "file": "nothere.obj"}]})",
               "objects[0].file: " + (dir_ / "nothere.obj").string() + ": cannot be opened");
  expect_error("too_reflective.json",
               R"({"materials": {"m": {"reflectivity": 0.6, "transparency": 0.5}}})",
               "materials.m: reflectivity + transparency must not exceed 1");
  // Ranges of render settings: the parser reports RenderSettings::validate()'s
  // message after "render: " (tests/cli/test_settings_ranges.cpp checks every
  // limit against the core and the command line).
  expect_error("zero_width.json", R"({"render": {"width": 0}})",
               "render: image size 0x480 is invalid: width and height must be at least 1");
  const std::string side = std::to_string(RenderSettings::kMaxImageSide);
  expect_error("huge_width.json", R"({"render": {"height": 100, "width": )" + side + "1}}",
               "render: image size " + side + "1x100 is too large");
  expect_error("too_many_pixels.json",
               R"({"render": {"width": )" + side + R"(, "height": )" + side + "}}",
               "render: image size " + side + "x" + side + " is too large");
  expect_error("zero_samples.json", R"({"render": {"samples": 0}})",
               "render: samples must be in 1..");
  expect_error("negative_cutoff.json", R"({"render": {"min_contribution": -0.5}})",
               "render: min_contribution must be in 0..1, got -0.5");
  expect_error("negative_seed.json", R"({"render": {"seed": -1}})",
               "render.seed: -1 is not a 32-bit unsigned integer");
  expect_error("huge_depth.json", R"({"render": {"max_depth": 1e3}})",
               "render.max_depth: expected an integer");
  expect_error("bad_object_type.json", R"({"objects": [{"type": "cube"}]})",
               "objects[0].type: expected \"sphere\", \"plane\", \"mesh\", \"tubes\" or "
               "\"points\", got \"cube\"");
  // Tubes and points.
  expect_error("tubes_no_positions.json", R"({"objects": [{"type": "tubes", "radius": 1}]})",
               "objects[0]: needs 'positions' (an array of [x, y, z])");
  expect_error("tubes_one_position.json",
               R"({"objects": [{"type": "tubes", "positions": [[0, 0, 0]]}]})",
               "objects[0]: tubes need at least one segment (two positions)");
  expect_error("tubes_bad_index.json",
               R"({"objects": [{"type": "tubes", "positions": [[0, 0, 0], [1, 0, 0]],
                                 "segments": [[0, 1], [1, 2]]}]})",
               "objects[0].segments[1]: index 2 is not below the 2 positions");
  expect_error("tubes_bad_segment.json",
               R"({"objects": [{"type": "tubes", "positions": [[0, 0, 0], [1, 0, 0]],
                                 "segments": [[0, 1, 1]]}]})",
               "objects[0].segments[0]: expected [i, j]");
  expect_error("tubes_zero_radius.json",
               R"({"objects": [{"type": "tubes", "positions": [[0, 0, 0], [1, 0, 0]],
                                 "radius": 0}]})",
               "objects[0].radius: value 0 is outside [1e-30, 1e+30]");
  expect_error("tubes_both_radii.json",
               R"({"objects": [{"type": "tubes", "positions": [[0, 0, 0], [1, 0, 0]],
                                 "radius": 1, "radii": [1, 1]}]})",
               "objects[0]: give either 'radius' or 'radii', not both");
  expect_error("points_radii_count.json",
               R"({"objects": [{"type": "points", "positions": [[0, 0, 0], [1, 0, 0]],
                                 "radii": [1]}]})",
               "objects[0].radii: expected an array of 2 (one per position)");
  expect_error("points_negative_radius.json",
               R"({"objects": [{"type": "points", "positions": [[0, 0, 0]], "radii": [-1]}]})",
               "objects[0].radii[0]: value -1 is outside [1e-30, 1e+30]");
  expect_error("points_bad_color.json",
               R"({"objects": [{"type": "points", "positions": [[0, 0, 0]],
                                 "colors": [[1, -1, 0]]}]})",
               "objects[0].colors[0]: color components must be >= 0");
  expect_error("points_nan.json",
               R"({"objects": [{"type": "points", "positions": [[0, 1e39, 0]]}]})",
               "objects[0].positions[0][1]: number is not finite");
  expect_error("points_unknown_key.json",
               R"({"objects": [{"type": "points", "positions": [[0, 0, 0]], "segments": []}]})",
               "objects[0]: unknown key 'segments'");
  expect_error("zero_normal.json", R"({"objects": [{"type": "plane", "normal": [0, 0, 0]}]})",
               "objects[0].normal: must be non-zero");
  expect_error("negative_color.json", R"({"background": [0, -1, 0]})",
               "background: color components must be >= 0");
}

TEST_F(SceneIo, MissingOrDirectoryScene) {
  for (const fs::path& p : {dir_ / "no_such_scene.json", dir_}) {
    try {
      load_scene(p, load_obj);
      ADD_FAILURE() << p << ": no error";
    } catch (const SceneError& e) {
      std::string msg = e.what();
      EXPECT_EQ(msg.rfind(p.string() + ": ", 0), 0u) << msg;
      EXPECT_TRUE(msg.find("file not found") != std::string::npos ||
                  msg.find("is a directory") != std::string::npos)
          << msg;
    }
  }
}

TEST_F(SceneIo, ANonObjectIsRefusedByItsFirstCharacter) {
  // A 1 GB file (sparse: no disk) starting with '[' is refused from its first
  // bytes: reading and parsing it all (a 200 MB array took 9.3 s and 937 MB)
  // would end in "malformed JSON" at the first NUL instead.
  const fs::path big = dir_ / "array.json";
  {
    std::ofstream f(big, std::ios::binary);
    f << "  \n\t[1, 2, 3, ";
  }
  fs::resize_file(big, std::uintmax_t(1) << 30);
  try {
    load_scene(big, load_obj);
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()),
              big.string() + ": expected an object ('{'), the file starts with '['");
  }
  // The same rule for text given directly, after a byte order mark; a byte
  // that is not text is quoted escaped.
  for (const auto& [text, first] : {std::pair<std::string, std::string>{"\xEF\xBB\xBF 42", "4"},
                                    {"\x01{}", "\\x01"},
                                    {"\"scene\"", "\""}}) {
    try {
      parse_scene(text, "inline", dir_, load_obj);
      ADD_FAILURE() << "no error for " << text;
    } catch (const SceneError& e) {
      EXPECT_EQ(std::string(e.what()),
                "inline: expected an object ('{'), the file starts with '" + first + "'");
    }
  }
  EXPECT_NO_THROW(parse_scene("\xEF\xBB\xBF\r\n {}", "bom", dir_, load_obj));
}

TEST_F(SceneIo, BytesFromTheFileAreQuotedPrintable) {
  try {
    parse_scene("{\"colo\\u001b[2Jr\": 1}", "inline", dir_, load_obj);
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "inline: unknown key 'colo\\x1B[2Jr'");
  }
  const std::string long_key(100000, 'k');
  try {
    parse_scene("{\"" + long_key + "\": 1}", "inline", dir_, load_obj);
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()),
              "inline: unknown key '" + std::string(kMaxQuotedBytes, 'k') + "... (100000 bytes)'");
  }
}

TEST_F(SceneIo, ParseSceneUsesTheGivenName) {
  try {
    parse_scene("{\"bogus\": 1}", "inline scene", dir_, load_obj);
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "inline scene: unknown key 'bogus'");
  }
  // Relative mesh paths resolve against base_dir.
  LoadedScene ls =
      parse_scene(R"({"objects": [{"type": "mesh", "file": "quad.obj"}]})", "x", dir_, load_obj);
  ASSERT_EQ(ls.scene.meshes.size(), 1u);
  EXPECT_EQ(ls.scene.meshes[0].triangles.size(), 3u);
  // Defaults when the file says nothing.
  LoadedScene empty = parse_scene("{}", "empty", dir_, load_obj);
  EXPECT_EQ(empty.settings.width, RenderSettings{}.width);
  EXPECT_EQ(empty.scene.materials.size(), 1u);
  EXPECT_TRUE(empty.scene.lights.empty());
}

}  // namespace

// A file of several datasets (a composite file) gives one mesh per dataset:
// each its own scene object, after the meshes before it and before those after
// it, named by the object and its place in the file, in the object's material;
// the loader's warnings come back naming the object.
TEST_F(SceneIo, OneMeshObjectCanGiveSeveralMeshes) {
  MeshLoader two_blocks = [](const MeshOptions& mo) {
    LoadedMeshFile f = load_obj(mo);
    if (mo.file.filename() == "quad.obj") {
      f.meshes.push_back(f.meshes[0]);
      f.meshes[0].name = "block 1";
      f.meshes[1].name = "block 2 (lid)";
      f.tubes.emplace_back();
      f.tubes[0].name = "block 4 lines";
      f.tubes[0].positions = {Vec3(0.0f), Vec3(1.0f)};
      f.tubes[0].segments = {{0, 1}};
      f.points.emplace_back();
      f.points[0].name = "block 5 vertices";
      f.points[0].positions = {Vec3(2.0f)};
      f.warnings.push_back(mo.file.string() +
                           ": block 3: no surface triangles, lines or vertices, left out");
    }
    return f;
  };
  LoadedScene ls = parse_scene(R"({"materials": {"red": {"color": [1, 0, 0]}},
      "objects": [{"type": "mesh", "file": "tetra.obj"},
                  {"type": "mesh", "name": "box", "file": "quad.obj", "material": "red"},
                  {"type": "mesh", "file": "hex.obj"}]})",
                               "x", dir_, two_blocks);
  ASSERT_EQ(ls.scene.meshes.size(), 4u);
  EXPECT_EQ(ls.scene.meshes[0].name, "mesh0");
  EXPECT_EQ(ls.scene.meshes[1].name, "box block 1");
  EXPECT_EQ(ls.scene.meshes[2].name, "box block 2 (lid)");
  EXPECT_EQ(ls.scene.meshes[3].name, "mesh2");
  EXPECT_EQ(ls.scene.meshes[1].material, ls.scene.meshes[2].material);
  EXPECT_NE(ls.scene.meshes[1].material, ls.scene.meshes[0].material);
  EXPECT_EQ(ls.scene.meshes[1].triangles.size(), 3u);
  EXPECT_EQ(ls.scene.meshes[2].triangles.size(), 3u);
  // Its lines and vertices: scene objects of the same name and material.
  ASSERT_EQ(ls.scene.tubes.size(), 1u);
  EXPECT_EQ(ls.scene.tubes[0].name, "box block 4 lines");
  EXPECT_EQ(ls.scene.tubes[0].material, ls.scene.meshes[1].material);
  ASSERT_EQ(ls.scene.points.size(), 1u);
  EXPECT_EQ(ls.scene.points[0].name, "box block 5 vertices");
  EXPECT_EQ(ls.scene.points[0].material, ls.scene.meshes[1].material);
  ASSERT_EQ(ls.warnings.size(), 1u);
  EXPECT_EQ(ls.warnings[0], "x: objects[1].file: " + (dir_ / "quad.obj").string() +
                                ": block 3: no surface triangles, lines or vertices, left out");
}
