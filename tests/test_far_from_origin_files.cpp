// Scene and mesh files far from the world's origin, through the front end the
// rayscope command uses (scene files, the bunny and .vtp files read by VTK
// through rayscope_vtkio): coordinates stay in double until they are made
// relative to the scene's local origin (Scene::origin), so a scene moved by
// 1e5..1e7 (geospatial data: UTM, ECEF) renders the image it renders at the
// origin. The VTK module's side is in tests/vtk (test_vtk_far_origin); the
// core's, with the default scene built in C++, in test_far_from_origin.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataWriter.h>
#include <nlohmann/json.hpp>

#include "image_compare.h"
#include "rayscope/raytree_format.h"
#include "rayscope/render.h"
#include "rayscope/replay.h"
#include "rayscope/scene_io.h"
#include "rayscope_vtkio/mesh_files.h"
#include "test_util.h"

namespace {

using json = nlohmann::json;
using namespace rayscope;

const std::filesystem::path kScenes = std::filesystem::path(RAYSCOPE_SOURCE_DIR) / "data/scenes";
const char* const kBunny = "/usr/share/glmark2/models/bunny.obj";

class FarFromOrigin : public ::testing::Test {
 protected:
  void SetUp() override {
    // setup installs glmark2-data: a missing bunny is a broken machine, not a skip.
    ASSERT_TRUE(std::filesystem::exists(kBunny)) << kBunny << " is missing (scripts/setup)";
    dir_ = std::filesystem::temp_directory_path() /
           ("rayscope_far_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

// The scene file moved by (d, d, d): camera, point lights, spheres, planes and
// mesh transforms (their translation is applied last, so adding to it moves
// the mesh). Mesh paths are made absolute, as the copy lives elsewhere.
json moved(json s, double d, const std::filesystem::path& base_dir) {
  auto add = [d](json& v) {
    for (auto& x : v) x = x.get<double>() + d;
  };
  add(s["camera"]["eye"]);
  add(s["camera"]["look_at"]);
  for (json& l : s["lights"])
    if (l.contains("position")) add(l["position"]);
  for (json& o : s["objects"]) {
    const std::string type = o["type"];
    if (type == "sphere") add(o["center"]);
    if (type == "plane") add(o["point"]);
    if (type == "mesh") {
      std::filesystem::path f = o["file"].get<std::string>();
      if (f.is_relative()) o["file"] = (base_dir / f).string();
      if (!o["transform"].contains("translate")) o["transform"]["translate"] = {0.0, 0.0, 0.0};
      add(o["transform"]["translate"]);
    }
  }
  return s;
}

Framebuffer render_text(const json& scene, const std::filesystem::path& base_dir) {
  LoadedScene ls = parse_scene(scene.dump(), "scene", base_dir, rayscope_vtkio::load_meshes);
  ls.scene.commit();
  return render(ls.scene, rstest::small_render(160, 120, 2));
}

json read_json(const std::filesystem::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

}  // namespace

// The bunny-and-glass scene (the bunny read from its OBJ file by VTK, a glass
// sphere touching a checkered floor, a point and a directional light) moved by
// 1e5, 1e6 and 1e7. Before scenes had a local origin this measured 26.6 dB at
// 1e5: the bunny staircased by its vertices' float spacing (0.0078), the glass
// highlight speckled, and a dark crescent where the sphere touches the floor
// (the sphere's center and the floor rounded by different amounts, so the
// sphere dipped through the floor). Now the moved scene is traced around
// its look_at, the unmoved one around the world's origin (it is near it), so
// they differ by one rounding of coordinates of size ~1..10. Measured: 55.2 dB
// at all three offsets (36 of 19200 pixels off by more than 1/255, at
// silhouettes and checker edges). Required: the 40 dB.
TEST_F(FarFromOrigin, SceneFileMovedUpTo1e7RendersTheSameImage) {
  const json base = read_json(kScenes / "bunny_glass.json");
  const Framebuffer ref = render_text(base, kScenes);
  for (double d : {1e5, 1e6, 1e7}) {
    const Framebuffer fb = render_text(moved(base, d, kScenes), kScenes);
    const double p = rstest::psnr(ref, fb);
    std::printf("offset %g: PSNR %.2f dB, %zu pixels > 1/255\n", d, p,
                rstest::pixels_differing(ref, fb));
    EXPECT_GE(p, 40.0) << "offset " << d;
  }
}

// A mesh file whose points are stored in double at 1e6 keeps its detail: the
// points are moved to the scene's origin before they are rounded to float.
// The file's bunny is compared with the same bunny written at the origin.
// Rounding the points to float at 1e6 (spacing 0.0625, a fifth of the
// bunny's 0.15 size) would leave a few blobs; required, as above, 40 dB.
TEST_F(FarFromOrigin, MeshFileWithDoublePointsFarAwayKeepsItsPrecision) {
  vtkNew<vtkOBJReader> reader;
  reader->SetFileName(kBunny);
  reader->Update();
  const double d = 1e6;
  auto write = [&](double offset, const std::string& name) {
    vtkNew<vtkPolyData> pd;
    pd->ShallowCopy(reader->GetOutput());
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    vtkPoints* in = reader->GetOutput()->GetPoints();
    pts->SetNumberOfPoints(in->GetNumberOfPoints());
    for (vtkIdType i = 0; i < in->GetNumberOfPoints(); ++i) {
      double p[3];
      in->GetPoint(i, p);
      pts->SetPoint(i, p[0] + offset, p[1] + offset, p[2] + offset);
    }
    pd->SetPoints(pts);
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetInputData(pd);
    w->SetFileName((dir_ / name).string().c_str());
    ASSERT_EQ(w->Write(), 1);
  };
  write(0.0, "near.vtp");
  write(d, "far.vtp");
  json scene = {{"camera", {{"eye", {0.0, 0.12, 0.45}}, {"look_at", {-0.02, 0.1, 0.0}}}},
                {"lights", {{{"type", "point"}, {"position", {1.0, 2.0, 2.0}}}}},
                {"objects", {{{"type", "mesh"}, {"file", "near.vtp"}}}}};
  const Framebuffer ref = render_text(scene, dir_);
  json far = scene;
  for (const char* k : {"eye", "look_at"})
    for (auto& x : far["camera"][k]) x = x.get<double>() + d;
  for (auto& x : far["lights"][0]["position"]) x = x.get<double>() + d;
  far["objects"][0]["file"] = "far.vtp";
  const Framebuffer fb = render_text(far, dir_);
  const double p = rstest::psnr(ref, fb);
  std::printf("mesh file at 1e6: PSNR %.2f dB, %zu pixels > 1/255\n", p,
              rstest::pixels_differing(ref, fb));
  EXPECT_GE(p, 40.0);
}

// Ray trees report world coordinates: the local origin is added back to ray
// origins and hit points, in double.
TEST_F(FarFromOrigin, RayTreesReportWorldCoordinates) {
  const double d = 1e7;
  const json base = read_json(kScenes / "bunny_glass.json");
  LoadedScene near = parse_scene(base.dump(), "near", kScenes, rayscope_vtkio::load_meshes);
  LoadedScene far =
      parse_scene(moved(base, d, kScenes).dump(), "far", kScenes, rayscope_vtkio::load_meshes);
  near.scene.commit();
  far.scene.commit();
  // Near the world's origin the scene keeps it; far away the origin is the
  // (moved) look_at, 0.85 above the floor.
  EXPECT_EQ(near.scene.origin, DVec3(0.0));
  EXPECT_EQ(far.scene.origin, DVec3(d, d + 0.85, d));
  const RenderSettings rs = rstest::small_render(160, 120, 1);
  const json a = json::parse(format_json(record_pixel(near.scene, rs, 60, 70), near.scene));
  const json b = json::parse(format_json(record_pixel(far.scene, rs, 60, 70), far.scene));
  ASSERT_EQ(a["rays"].size(), b["rays"].size());
  ASSERT_TRUE(a["rays"][0]["hit"].get<bool>());
  int points = 0;
  for (size_t i = 0; i < a["rays"].size(); ++i)
    for (const char* key : {"origin", "point"}) {
      if (!a["rays"][i].contains(key)) continue;
      ++points;
      for (int k = 0; k < 3; ++k)
        // The far tree's world coordinates, less d, are the near tree's up
        // to float's rounding of the two scenes' coordinates relative to
        // their origins (0 and look_at; ~1e-6 for coordinates up to 10) and
        // its effect on hit points: 1e-4, a hundred-thousandth of the scene.
        // Without the origin added back they would be off by d.
        EXPECT_NEAR(b["rays"][i][key][k].get<double>() - d, a["rays"][i][key][k].get<double>(),
                    1e-4)
            << "ray " << i << " " << key;
    }
  EXPECT_GE(points, 2);
}
