// vtkRayScopeRayTreeSource: the polydata of a pixel's ray tree holds exactly
// what rayscope::record_pixel records (compared through its JSON, as
// `rayscope inspect --format json` prints it).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>

#include "rayscope/raytree_format.h"
#include "rayscope/render.h"
#include "rayscope/replay.h"
#include "rayscope/scene.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeMaterial.h"
#include "vtkRayScopeRayTreeSource.h"
#include "vtk_test_util.h"

using json = nlohmann::json;

namespace {

// A reflective floor, a glass sphere and a mirror sphere under a point light
// and the headlight: every kind of ray, occluded shadow rays included.
struct TestScene {
  vtkNew<vtkPlaneSource> floor;
  vtkNew<vtkSphereSource> glass, mirror;
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  TestScene() {
    configure_floor(floor, -0.5, 3.0);
    configure_sphere(glass, -0.4, 0.0, 0.2, 0.5, 40);
    configure_sphere(mirror, 0.75, 0.0, -0.5, 0.45, 40);
    alg->AddInputConnection(floor->GetOutputPort());
    alg->AddInputConnection(glass->GetOutputPort());
    alg->AddInputConnection(mirror->GetOutputPort());
    vtkNew<vtkRayScopeMaterial> floor_m, glass_m, mirror_m;
    floor_m->SetColor(0.8, 0.7, 0.5);
    floor_m->SetReflectivity(0.3);
    glass_m->SetTransparency(0.9);
    glass_m->SetIndexOfRefraction(1.5);
    mirror_m->SetColor(0.9, 0.3, 0.2);
    mirror_m->SetReflectivity(0.6);
    mirror_m->SetSpecular(0.4);
    mirror_m->SetSpecularPower(30);
    alg->SetInputMaterial(0, floor_m);
    alg->SetInputMaterial(1, glass_m);
    alg->SetInputMaterial(2, mirror_m);
    alg->AddPointLight(2, 4, 3, 1, 1, 1, 0.8);
    alg->SetPosition(0, 1.0, 4.0);
    alg->SetFocalPoint(0, -0.1, 0);
    alg->SetBackground(0.2, 0.3, 0.5);
    alg->SetSize(64, 48);
    alg->SetSamples(2);
    alg->SetMaxDepth(4);
  }
};

double arr(vtkPolyData* pd, const char* name, vtkIdType cell, int comp = 0) {
  vtkDataArray* a = pd->GetCellData()->GetArray(name);
  EXPECT_NE(a, nullptr) << name;
  return a ? a->GetComponent(cell, comp) : 0.0;
}

void expect_vec(const double* got, const json& want, const std::string& what) {
  ASSERT_TRUE(want.is_array()) << what;
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(got[k], want[size_t(k)].get<double>()) << what << "[" << k << "]";
}

}  // namespace

// Every cell carries its kind's color (KindColor, bytes), the one palette
// GetKindColor gives the viewer and the examples: four different colors, and
// black for a value that is no kind.
TEST(VtkRayTree, EachRayCarriesItsKindsColor) {
  TestScene t;
  vtkNew<vtkRayScopeRayTreeSource> src;
  src->SetSceneSource(t.alg);
  for (int j = 2; j < 48; j += 5)
    for (int i = 3; i < 64; i += 5) src->AddPixel(i, j);
  src->Update();
  vtkPolyData* pd = src->GetOutput();
  auto* colors = vtkUnsignedCharArray::SafeDownCast(pd->GetCellData()->GetArray("KindColor"));
  ASSERT_NE(colors, nullptr);
  ASSERT_EQ(colors->GetNumberOfComponents(), 3);
  std::set<int> kinds;
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c) {
    const int kind = int(arr(pd, "Kind", c));
    kinds.insert(kind);
    double rgb[3];
    vtkRayScopeRayTreeSource::GetKindColor(kind, rgb);
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(colors->GetTypedComponent(c, k), std::lround(255.0 * rgb[k])) << c;
  }
  EXPECT_EQ(kinds.size(), 4u);  // the scene has a glass and a mirror
  std::set<std::array<double, 3>> palette;
  for (int kind = 0; kind < 4; ++kind) {
    std::array<double, 3> rgb;
    vtkRayScopeRayTreeSource::GetKindColor(kind, rgb.data());
    palette.insert(rgb);
  }
  EXPECT_EQ(palette.size(), 4u);
  double none[3] = {1, 1, 1};
  vtkRayScopeRayTreeSource::GetKindColor(4, none);
  EXPECT_EQ(none[0] + none[1] + none[2], 0.0);
}

TEST(VtkRayTree, MatchesRecordPixelJson) {
  TestScene t;
  t.alg->Update();
  vtkImageData* img = t.alg->GetOutput();
  vtkNew<vtkRayScopeRayTreeSource> src;
  src->SetSceneSource(t.alg);
  std::vector<std::pair<int, int>> pixels;
  for (int j = 2; j < 48; j += 7)
    for (int i = 3; i < 64; i += 6) pixels.emplace_back(i, j);
  for (auto [i, j] : pixels) src->AddPixel(i, j);
  src->Update();
  vtkPolyData* pd = src->GetOutput();

  rayscope::Scene* scene = t.alg->GetCoreScene();
  ASSERT_NE(scene, nullptr);
  const rayscope::RenderSettings settings = t.alg->GetRenderSettings();

  // Cells of each pixel: vertex cells (hit points) first, then one line per ray.
  const vtkIdType nverts = pd->GetNumberOfVerts();
  std::map<int, std::vector<vtkIdType>> lines_of, verts_of;
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c) {
    const int p = int(arr(pd, "PixelIndex", c));
    const bool is_vertex = arr(pd, "IsHitPoint", c) != 0.0;
    EXPECT_EQ(is_vertex, c < nverts);
    EXPECT_EQ(pd->GetCellType(c), is_vertex ? VTK_VERTEX : VTK_LINE);
    (is_vertex ? verts_of : lines_of)[p].push_back(c);
  }

  std::map<std::string, int> kinds_seen;
  int occluded_seen = 0, skipped_seen = 0;
  vtkNew<vtkIdList> ids;
  auto* kind_names = vtkStringArray::SafeDownCast(pd->GetCellData()->GetAbstractArray("KindName"));
  ASSERT_NE(kind_names, nullptr);
  vtkDataArray* normals = pd->GetPointData()->GetNormals();
  ASSERT_NE(normals, nullptr);
  for (size_t p = 0; p < pixels.size(); ++p) {
    const auto [i, j] = pixels[p];
    const int y = settings.height - 1 - j;  // core rows count from the top
    const json rec =
        json::parse(rayscope::format_json(rayscope::record_pixel(*scene, settings, i, y), *scene));
    const json& rays = rec["rays"];
    const std::vector<vtkIdType>& lines = lines_of[int(p)];
    ASSERT_EQ(lines.size(), rays.size()) << "pixel " << i << "," << j;

    // The pixel's color: the JSON's, and the rendered image's, bit for bit.
    const double* pc = pd->GetFieldData()->GetArray("PixelColor")->GetTuple3(vtkIdType(p));
    expect_vec(pc, rec["color"], "pixel color");
    const double* ic = img->GetPointData()->GetArray("LinearColor")->GetTuple3(j * 64 + i);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(ic[k], pc[k]);

    size_t hits = 0;
    for (size_t r = 0; r < rays.size(); ++r) {
      const json& ray = rays[r];
      const vtkIdType c = lines[r];
      const std::string what =
          "pixel " + std::to_string(i) + "," + std::to_string(j) + " ray " + std::to_string(r);
      EXPECT_EQ(arr(pd, "RayId", c), ray["id"].get<int>()) << what;
      EXPECT_EQ(arr(pd, "ParentId", c), ray["parent"].get<int>()) << what;
      EXPECT_EQ(kind_names->GetValue(c), ray["kind"].get<std::string>()) << what;
      EXPECT_EQ(arr(pd, "Depth", c), ray["depth"].get<int>()) << what;
      EXPECT_EQ(arr(pd, "Sample", c), ray["sample"].get<int>()) << what;
      EXPECT_EQ(arr(pd, "Pixel", c, 0), i);
      EXPECT_EQ(arr(pd, "Pixel", c, 1), j);
      EXPECT_EQ(arr(pd, "BoxesTested", c), ray["bvh"]["boxes_tested"].get<double>()) << what;
      EXPECT_EQ(arr(pd, "PrimitivesTested", c), ray["bvh"]["primitives_tested"].get<double>());
      EXPECT_EQ(arr(pd, "NodesVisited", c), double(ray["bvh"]["nodes"].size())) << what;
      EXPECT_EQ(arr(pd, "NodesCulled", c), ray["bvh"]["culled"].get<double>()) << what;
      double v[3];
      for (int k = 0; k < 3; ++k) v[k] = arr(pd, "Weight", c, k);
      expect_vec(v, ray["weight"], what + " weight");
      for (int k = 0; k < 3; ++k) v[k] = arr(pd, "Color", c, k);
      expect_vec(v, ray["color"], what + " color");

      pd->GetCellPoints(c, ids);
      ASSERT_EQ(ids->GetNumberOfIds(), 2);
      double start[3], end[3];
      pd->GetPoint(ids->GetId(0), start);
      pd->GetPoint(ids->GetId(1), end);
      expect_vec(start, ray["origin"], what + " origin");
      kinds_seen[ray["kind"].get<std::string>()]++;

      if (ray["kind"] == "shadow") {
        const bool occluded = ray["occluded"].get<bool>();
        EXPECT_EQ(arr(pd, "Occluded", c), occluded) << what;
        EXPECT_EQ(arr(pd, "Skipped", c), ray["skipped"].get<bool>() ? 1 : 0) << what;
        EXPECT_EQ(arr(pd, "LightId", c), ray["light"].get<int>()) << what;
        if (occluded) {
          ++occluded_seen;
          EXPECT_EQ(arr(pd, "ObjectId", c), ray["occluder"].get<int>()) << what;
          // The line ends on an occluding surface before the light.
          EXPECT_EQ(arr(pd, "EndKind", c), 3) << what;
          EXPECT_GE(arr(pd, "EndObjectId", c), 0) << what;
          const double tt = arr(pd, "T", c);
          EXPECT_GT(tt, 0.0);
          if (ray["tmax"].is_number()) {
            EXPECT_LT(tt, ray["tmax"].get<double>());
          }
          for (int k = 0; k < 3; ++k) {
            const double o = ray["origin"][size_t(k)].get<double>();
            const double d = ray["direction"][size_t(k)].get<double>();
            EXPECT_NEAR(end[k], o + tt * d, 1e-4 * (1.0 + std::abs(end[k]))) << what;
          }
        } else {
          EXPECT_EQ(arr(pd, "EndKind", c), 2) << what;
          if (ray["tmax"].is_number()) {  // point light: the line ends at the light
            for (int k = 0; k < 3; ++k)
              EXPECT_NEAR(end[k],
                          ray["origin"][size_t(k)].get<double>() +
                              ray["tmax"].get<double>() * ray["direction"][size_t(k)].get<double>(),
                          1e-5);
          }
        }
        continue;
      }
      const bool hit = ray["hit"].get<bool>();
      EXPECT_EQ(arr(pd, "Hit", c), hit) << what;
      if (ray["skipped"].get<bool>()) {  // not traced: a stub along its direction
        ++skipped_seen;
        EXPECT_FALSE(hit) << what;
        EXPECT_EQ(arr(pd, "EndKind", c), 4) << what;
        EXPECT_EQ(arr(pd, "Skipped", c), ray["skip_reason"] == "depth limit"           ? 2
                                         : ray["skip_reason"] == "contribution cutoff" ? 3
                                                                                       : -1)
            << what;
        continue;
      }
      EXPECT_EQ(arr(pd, "Skipped", c), 0) << what;
      if (!hit) {
        EXPECT_EQ(arr(pd, "EndKind", c), 0) << what;
        EXPECT_EQ(arr(pd, "ObjectId", c), -1) << what;
        continue;
      }
      ++hits;
      EXPECT_EQ(arr(pd, "EndKind", c), 1) << what;
      EXPECT_EQ(arr(pd, "ObjectId", c), ray["object"].get<int>()) << what;
      EXPECT_EQ(arr(pd, "EndObjectId", c), ray["object"].get<int>()) << what;
      EXPECT_EQ(arr(pd, "T", c), ray["t"].get<double>()) << what;
      expect_vec(end, ray["point"], what + " hit point");
      expect_vec(normals->GetTuple3(ids->GetId(1)), ray["shading_normal"], what + " normal");
      expect_vec(pd->GetPointData()->GetArray("GeometricNormals")->GetTuple3(ids->GetId(1)),
                 ray["geometric_normal"], what + " geometric normal");
    }
    // One vertex per hit, at the hit point, carrying its ray's id.
    const std::vector<vtkIdType>& verts = verts_of[int(p)];
    ASSERT_EQ(verts.size(), hits) << "pixel " << i << "," << j;
    for (vtkIdType c : verts) {
      const json& ray = rays[size_t(arr(pd, "RayId", c))];
      ASSERT_TRUE(ray.value("hit", false));
      pd->GetCellPoints(c, ids);
      expect_vec(pd->GetPoint(ids->GetId(0)), ray["point"], "vertex");
    }
  }
  // The chosen pixels cover every kind of ray and occluded shadow rays.
  for (const char* k : {"primary", "shadow", "reflection", "refraction"})
    EXPECT_GT(kinds_seen[k], 0) << k;
  EXPECT_GT(occluded_seen, 0);
  EXPECT_GT(skipped_seen, 0);
}

// One sample only; the ray tree of a single pixel through SetPixel.
TEST(VtkRayTree, SingleSample) {
  TestScene t;
  vtkNew<vtkRayScopeRayTreeSource> src;
  src->SetSceneSource(t.alg);
  src->SetPixel(20, 20);
  src->SetSample(3);
  src->Update();
  vtkPolyData* pd = src->GetOutput();
  ASSERT_GT(pd->GetNumberOfLines(), 0);
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c) EXPECT_EQ(arr(pd, "Sample", c), 3);
  const rayscope::PixelRecord rec = rayscope::record_pixel(
      *t.alg->GetCoreScene(), t.alg->GetRenderSettings(), 20, 48 - 1 - 20, 3);
  EXPECT_EQ(pd->GetNumberOfLines(), vtkIdType(rec.rays.size()));
}

// Bad pixel, bad sample, no scene: one clear error each, no output.
TEST(VtkRayTree, RejectsBadParameters) {
  TestScene t;
  struct Case {
    const char* expect;
    int i, j, sample;
    bool scene;
  };
  for (const Case& c :
       {Case{"pixel (64, 0) is outside the 64x48 image", 64, 0, -1, true},
        Case{"pixel (0, -1) is outside", 0, -1, -1, true},
        Case{"Sample 4 is outside -1..3", 0, 0, 4, true}, Case{"no scene", 0, 0, -1, false}}) {
    vtkNew<vtkRayScopeRayTreeSource> src;
    if (c.scene) src->SetSceneSource(t.alg);
    src->SetPixel(c.i, c.j);
    src->SetSample(c.sample);
    vtkNew<ErrorCatcher> errors, pipeline_errors;
    src->AddObserver(vtkCommand::ErrorEvent, errors);
    src->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline_errors);
    EXPECT_EQ(update(src), 0);
    EXPECT_EQ(errors->count, 1) << c.expect;
    EXPECT_NE(errors->last.find(c.expect), std::string::npos) << errors->last;
  }
}

// The scene's datasets through input port 0: the same tree as the scene
// source's own inputs give. Without a scene source, a default scene with the
// camera fitted to the data is used (the tree of an image algorithm with
// AutoCamera on and the same inputs).
TEST(VtkRayTree, InputPortGivesTheSceneSourceItsInputs) {
  TestScene t;
  vtkNew<vtkRayScopeRayTreeSource> own;
  own->SetSceneSource(t.alg);
  own->SetPixel(30, 20);
  ASSERT_EQ(update(own), 1);

  TestScene settings;  // the same settings, its inputs replaced by the tree's
  settings.alg->RemoveAllInputConnections(0);
  vtkNew<vtkRayScopeRayTreeSource> ported;
  ported->SetSceneSource(settings.alg);
  ported->AddInputConnection(t.floor->GetOutputPort());
  ported->AddInputConnection(t.glass->GetOutputPort());
  ported->AddInputConnection(t.mirror->GetOutputPort());
  ported->SetPixel(30, 20);
  ASSERT_EQ(update(ported), 1);
  vtkPolyData* a = own->GetOutput();
  vtkPolyData* b = ported->GetOutput();
  ASSERT_GT(a->GetNumberOfLines(), 3);
  ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells());
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  for (vtkIdType p = 0; p < a->GetNumberOfPoints(); ++p)
    for (int k = 0; k < 3; ++k) ASSERT_EQ(a->GetPoint(p)[k], b->GetPoint(p)[k]) << p;
  // An unchanged input builds no new scene.
  const vtkIdType commits = settings.alg->GetNumberOfSceneCommits();
  ported->SetPixel(10, 10);
  ASSERT_EQ(update(ported), 1);
  EXPECT_EQ(settings.alg->GetNumberOfSceneCommits(), commits);

  vtkNew<vtkRayScopeRayTreeSource> bare;  // no scene source
  bare->AddInputConnection(t.glass->GetOutputPort());
  bare->SetPixel(150, 150);  // the middle of the default 300 x 300 image
  ASSERT_EQ(update(bare), 1);
  vtkNew<vtkRayScopeImageAlgorithm> fitted;
  fitted->AddInputConnection(t.glass->GetOutputPort());
  fitted->AutoCameraOn();
  vtkNew<vtkRayScopeRayTreeSource> reference;
  reference->SetSceneSource(fitted);
  reference->SetPixel(150, 150);
  ASSERT_EQ(update(reference), 1);
  EXPECT_GE(bare->GetOutput()->GetNumberOfVerts(), 1);  // the primary ray hits the sphere
  ASSERT_EQ(bare->GetOutput()->GetNumberOfPoints(), reference->GetOutput()->GetNumberOfPoints());
  for (vtkIdType p = 0; p < bare->GetOutput()->GetNumberOfPoints(); ++p)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(bare->GetOutput()->GetPoint(p)[k], reference->GetOutput()->GetPoint(p)[k]);
}
