// vtkRayScopeImageAlgorithm: image layout, projection, progress, validation,
// thread invariance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkLookupTable.h>
#include <vtkMath.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkSphereSource.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWeakPointer.h>

#include "rayscope/aggregate.h"
#include "rayscope/image.h"
#include "rayscope/render_settings.h"
#include "rayscope/scene.h"
#include "vtkRayScopeAccelSource.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeMaterial.h"
#include "vtkRayScopeRangeQuery.h"
#include "vtkRayScopeRayTreeSource.h"
#include "vtkRayScopeSceneSettings.h"
#include "vtk_test_util.h"

namespace {

int object_at(vtkImageData* img, int i, int j) {
  int* dims = img->GetDimensions();
  return vtkIntArray::SafeDownCast(img->GetPointData()->GetArray("ObjectId"))
      ->GetValue(vtkIdType(j) * dims[0] + i);
}

// Both images have the same linear colors, bit for bit.
void expect_same_colors(vtkImageData* a, vtkImageData* b) {
  vtkDataArray* ca = a->GetPointData()->GetArray("LinearColor");
  vtkDataArray* cb = b->GetPointData()->GetArray("LinearColor");
  ASSERT_NE(ca, nullptr);
  ASSERT_NE(cb, nullptr);
  ASSERT_EQ(ca->GetNumberOfTuples(), cb->GetNumberOfTuples());
  for (vtkIdType k = 0; k < ca->GetNumberOfTuples(); ++k)
    for (int j = 0; j < 3; ++j) ASSERT_EQ(ca->GetComponent(k, j), cb->GetComponent(k, j)) << k;
}

}  // namespace

// A sphere in front of a perspective camera: hit in the middle, background in
// the corners, the silhouette as large as the analytic projection of the
// sphere, the second (smaller, higher) sphere in the upper rows: VTK images
// have row 0 at the bottom.
TEST(VtkImage, SphereLayout) {
  vtkNew<vtkSphereSource> big, small;
  configure_sphere(big, 0, 0, 0, 0.5, 96);
  configure_sphere(small, 0, 0.65, 0, 0.1, 32);
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  alg->AddInputConnection(big->GetOutputPort());
  alg->AddInputConnection(small->GetOutputPort());
  alg->SetSize(96, 96);
  alg->SetPosition(0, 0, 3);
  alg->Update();
  vtkImageData* img = alg->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  ASSERT_EQ(dims[0], 96);
  ASSERT_EQ(dims[1], 96);
  ASSERT_EQ(dims[2], 1);
  for (const char* name : {"Color", "LinearColor", "Depth", "Normal", "ObjectId", "Cost"})
    ASSERT_NE(img->GetPointData()->GetAbstractArray(name), nullptr) << name;

  EXPECT_EQ(object_at(img, 48, 48), 0);
  EXPECT_EQ(object_at(img, 0, 0), -1);
  EXPECT_EQ(object_at(img, 95, 0), -1);
  EXPECT_EQ(object_at(img, 0, 95), -1);
  EXPECT_EQ(object_at(img, 95, 95), -1);

  // Silhouette radius of a sphere of radius r seen from distance d with a
  // vertical view angle a: tan(asin(r / d)) / tan(a / 2) half-heights.
  const double r_px =
      std::tan(std::asin(0.5 / 3.0)) / std::tan(vtkMath::RadiansFromDegrees(15.0)) * 48.0;
  const double expected = vtkMath::Pi() * r_px * r_px;
  // The small sphere hides a sliver of the big one's silhouette; the polygonal
  // sphere (96 x 48 facets) is ~0.1% smaller in area than the true one.
  EXPECT_NEAR(count_object(img, 0), expected, 0.03 * expected);

  // The small sphere sits above: in the upper rows (VTK row 0 is the bottom),
  // centered in columns.
  auto* ids = vtkIntArray::SafeDownCast(img->GetPointData()->GetArray("ObjectId"));
  double sum_i = 0, sum_j = 0;
  int n = 0;
  for (int j = 0; j < 96; ++j)
    for (int i = 0; i < 96; ++i)
      if (ids->GetValue(j * 96 + i) == 1) {
        sum_i += i + 0.5;
        sum_j += j + 0.5;
        ++n;
      }
  ASSERT_GT(n, 10);
  EXPECT_NEAR(sum_i / n, 48.0, 1.0);
  // Its silhouette is an ellipse centered halfway between the projections of
  // the two tangent rays in the vertical plane.
  const double a = std::atan(0.65 / 3.0), h = std::asin(0.1 / std::hypot(0.65, 3.0));
  const double y_px = 48.0 + 0.5 * (std::tan(a + h) + std::tan(a - h)) /
                                 std::tan(vtkMath::RadiansFromDegrees(15.0)) * 48.0;
  EXPECT_NEAR(sum_j / n, y_px, 1.0);

  // Depth along the primary ray, unit normals facing the camera, NaN depth on
  // the background; the center is white (white material, headlight at 0 deg).
  auto* depth = vtkFloatArray::SafeDownCast(img->GetPointData()->GetArray("Depth"));
  auto* normal = vtkFloatArray::SafeDownCast(img->GetPointData()->GetArray("Normal"));
  auto* color = vtkUnsignedCharArray::SafeDownCast(img->GetPointData()->GetArray("Color"));
  const vtkIdType c = 48 * 96 + 48;
  EXPECT_NEAR(depth->GetValue(c), 2.5, 0.01);
  EXPECT_GT(normal->GetTypedComponent(c, 2), 0.99);
  EXPECT_TRUE(std::isnan(depth->GetValue(0)));
  EXPECT_GE(color->GetTypedComponent(c, 0), 250);
  EXPECT_EQ(color->GetTypedComponent(0, 0), 0);
  EXPECT_GT(img->GetPointData()->GetArray("Cost")->GetTuple1(c), 0.0);
  EXPECT_NE(img->GetFieldData()->GetArray("RayCounts"), nullptr);
}

// Parallel projection: ParallelScale is half the image height in world units.
TEST(VtkImage, ParallelProjectionScale) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 0, 0, 0, 0.5, 128);
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  alg->AddInputConnection(s->GetOutputPort());
  alg->SetSize(100, 100);
  alg->SetPosition(0, 0, 10);
  alg->ParallelProjectionOn();
  alg->SetParallelScale(1.0);
  alg->Update();
  const double expected = vtkMath::Pi() * 25.0 * 25.0;
  EXPECT_NEAR(count_object(alg->GetOutput(), 0), expected, 0.02 * expected);
}

// A vtkCamera's parameters give the same image as setting them by hand.
TEST(VtkImage, CopyCameraAndResetCamera) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 2, 1, -3, 0.7);
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  alg->AddInputConnection(s->GetOutputPort());
  alg->SetSize(40, 30);
  ASSERT_EQ(alg->ResetCamera(), 1);
  alg->Update();
  // The bounding sphere fills the view: the object is centered and visible.
  EXPECT_EQ(object_at(alg->GetOutput(), 20, 15), 0);
  EXPECT_EQ(object_at(alg->GetOutput(), 0, 0), -1);

  vtkNew<vtkCamera> cam;
  cam->SetPosition(alg->GetPosition());
  cam->SetFocalPoint(alg->GetFocalPoint());
  cam->SetViewUp(alg->GetViewUp());
  cam->SetViewAngle(alg->GetViewAngle());
  vtkNew<vtkRayScopeImageAlgorithm> alg2;
  alg2->AddInputConnection(s->GetOutputPort());
  alg2->SetSize(40, 30);
  alg2->CopyCamera(cam);
  alg2->Update();
  expect_same_colors(alg->GetOutput(), alg2->GetOutput());
}

// ProgressEvent: non-decreasing, from 0 to 1, several steps for a many-tile image.
TEST(VtkImage, ProgressEvents) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 0, 0, 0, 0.5);
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  alg->AddInputConnection(s->GetOutputPort());
  alg->SetSize(256, 256);
  alg->SetPosition(0, 0, 3);
  alg->SetSamples(2);
  std::vector<double> progress;
  vtkNew<vtkCallbackCommand> cb;
  cb->SetClientData(&progress);
  cb->SetCallback([](vtkObject* o, unsigned long, void* cd, void*) {
    static_cast<std::vector<double>*>(cd)->push_back(vtkAlgorithm::SafeDownCast(o)->GetProgress());
  });
  alg->AddObserver(vtkCommand::ProgressEvent, cb);
  alg->Update();
  ASSERT_GE(progress.size(), 2u);
  EXPECT_EQ(progress.front(), 0.0);
  EXPECT_EQ(progress.back(), 1.0);
  for (size_t i = 1; i < progress.size(); ++i) EXPECT_GE(progress[i], progress[i - 1]);
}

// The image does not depend on the number of threads (bit for bit).
TEST(VtkImage, ThreadInvariance) {
  vtkNew<vtkSphereSource> a, b;
  configure_sphere(a, 0, 0, 0, 0.5);
  configure_sphere(b, 0.6, 0.3, 0.4, 0.3);
  auto render = [&](int threads) {
    vtkNew<vtkRayScopeImageAlgorithm> alg;
    alg->AddInputConnection(a->GetOutputPort());
    alg->AddInputConnection(b->GetOutputPort());
    alg->SetSize(64, 48);
    alg->SetSamples(2);
    alg->SetPosition(0, 0.5, 3);
    alg->AddPointLight(2, 3, 2, 1, 1, 1, 1);
    vtkNew<vtkRayScopeMaterial> mirror;
    mirror->SetReflectivity(0.5);
    alg->SetInputMaterial(0, mirror);
    alg->SetThreads(threads);
    alg->Update();
    vtkSmartPointer<vtkDataArray> c = alg->GetOutput()->GetPointData()->GetArray("LinearColor");
    return c;
  };
  auto c1 = render(1), c2 = render(2);
  ASSERT_EQ(c1->GetNumberOfTuples(), c2->GetNumberOfTuples());
  auto* f1 = vtkFloatArray::SafeDownCast(c1);
  auto* f2 = vtkFloatArray::SafeDownCast(c2);
  EXPECT_EQ(std::memcmp(f1->GetPointer(0), f2->GetPointer(0), size_t(f1->GetDataSize()) * 4), 0);
}

// LooseFactor, KdSplit and GridResolution (the CLI's --loose-factor,
// --kd-split and --grid-resolution) reach the
// structure: a change rebuilds it with the new settings (fewer references per
// primitive with median splits and smallest-cell storage than every-cell),
// and the image stays the BVH's, bit for bit.
TEST(VtkImage, LooseFactorAndKdSplitReachTheStructure) {
  vtkNew<vtkSphereSource> a, b;
  configure_sphere(a, 0, 0, 0, 0.5);
  configure_sphere(b, 0.6, 0.3, 0.4, 0.3);
  vtkNew<vtkRayScopeImageAlgorithm> bvh, alg;
  for (vtkRayScopeImageAlgorithm* x : {bvh.Get(), alg.Get()}) {
    x->AddInputConnection(a->GetOutputPort());
    x->AddInputConnection(b->GetOutputPort());
    x->SetSize(48, 36);
    x->SetPosition(0, 0.5, 3);
  }
  ASSERT_EQ(update(bvh), 1);
  EXPECT_DOUBLE_EQ(alg->GetLooseFactor(), double(rayscope::kDefaultLooseFactor));
  EXPECT_EQ(alg->GetKdSplit(), vtkRayScopeImageAlgorithm::KD_SPLIT_SAH);
  alg->SetAccelToKdTree();
  ASSERT_EQ(update(alg), 1);
  const double every_cell_refs = alg->GetCoreScene()->accel().figures().refs_per_prim;
  EXPECT_GT(every_cell_refs, 1.0);
  expect_same_colors(bvh->GetOutput(), alg->GetOutput());

  alg->SetStorageToSmallestCell();
  alg->SetLooseFactor(0.3);
  alg->SetKdSplitToMedian();
  ASSERT_EQ(update(alg), 1);
  const rayscope::Aggregate& accel = alg->GetCoreScene()->accel();
  EXPECT_EQ(accel.kind(), rayscope::AccelKind::KdTree);
  EXPECT_EQ(accel.storage(), rayscope::PrimStorage::SmallestCell);
  EXPECT_EQ(accel.config().loose_factor, 0.3f);
  EXPECT_EQ(accel.config().kdtree.rule, rayscope::KdSplitRule::Median);
  EXPECT_DOUBLE_EQ(accel.figures().refs_per_prim, 1.0);
  expect_same_colors(bvh->GetOutput(), alg->GetOutput());

  // The lecture's rule, and the image still the BVH's.
  alg->SetStorageToEveryCell();
  alg->SetKdSplitToAlternatingMedian();
  ASSERT_EQ(update(alg), 1);
  EXPECT_EQ(alg->GetCoreScene()->accel().config().kdtree.rule,
            rayscope::KdSplitRule::AlternatingMedian);
  EXPECT_EQ(alg->GetCoreScene()->accel().structure_as<rayscope::KdTree>().nodes[0].axis(), 0);
  expect_same_colors(bvh->GetOutput(), alg->GetOutput());

  // GridResolution gives the grid's cells per axis; 0 on an axis: automatic.
  alg->SetAccelToGrid();
  alg->SetStorageToEveryCell();
  alg->SetGridResolution(7, 5, 3);
  ASSERT_EQ(update(alg), 1);
  EXPECT_EQ(alg->GetCoreScene()->accel().structure_as<rayscope::UniformGrid>().resolution(),
            glm::uvec3(7, 5, 3));
  expect_same_colors(bvh->GetOutput(), alg->GetOutput());
  alg->SetGridResolution(0, 0, 0);
  alg->SetStorageToSmallestCell();

  // The grid and the octree take the same loose factor.
  for (int kind :
       {int(vtkRayScopeImageAlgorithm::ACCEL_GRID), int(vtkRayScopeImageAlgorithm::ACCEL_OCTREE)}) {
    alg->SetAccel(kind);
    ASSERT_EQ(update(alg), 1);
    EXPECT_EQ(alg->GetCoreScene()->accel().config().loose_factor, 0.3f);
    EXPECT_DOUBLE_EQ(alg->GetCoreScene()->accel().figures().refs_per_prim, 1.0);
    expect_same_colors(bvh->GetOutput(), alg->GetOutput());
  }
}

// Each bad parameter gives one clear error naming it, and Update fails.
TEST(VtkImage, RejectsBadParameters) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 0, 0, 0, 0.5, 16);
  struct Case {
    const char* expect;
    std::function<void(vtkRayScopeImageAlgorithm*)> breakit;
  };
  std::vector<Case> cases = {
      // The render settings: RenderSettings::validate()'s messages and limits.
      {"image size 0x20", [](auto* a) { a->SetWidth(0); }},
      {"image size 40x40000", [](auto* a) { a->SetHeight(40000); }},
      {"image size 20000x20000 is too large",
       [](auto* a) { a->SetSize(20000, 20000); }},  // more than kMaxPixels
      {"samples must be in 1..64", [](auto* a) { a->SetSamples(0); }},
      {"samples must be in 1..64", [](auto* a) { a->SetSamples(65); }},
      {"max_depth must be in 0..64", [](auto* a) { a->SetMaxDepth(-1); }},
      {"min_contribution must be in 0..1, got", [](auto* a) { a->SetMinContribution(-1.0); }},
      {"min_contribution must be in 0..1, got", [](auto* a) { a->SetMinContribution(1.5); }},
      {"threads must be in 0..1024", [](auto* a) { a->SetThreads(1025); }},
      {"max_samples must be 0 (no adaptive sampling) or a multiple of samples (1) in 1..64, got 65",
       [](auto* a) { a->SetMaxSamples(65); }},
      {"max_samples must be 0 (no adaptive sampling) or a multiple of samples (2) in 2..64, got 3",
       [](auto* a) {
         a->SetSamples(2);
         a->SetMaxSamples(3);
       }},
      {"target_error must be in 0..1, got -0.5",
       [](auto* a) {
         a->SetMaxSamples(4);
         a->SetTargetError(-0.5);
       }},
      {"target_error 0.01 needs adaptive sampling", [](auto* a) { a->SetTargetError(0.01); }},
      // The checks only VTK has.
      {"Position and FocalPoint coincide", [](auto* a) { a->SetPosition(0, 0, 0); }},
      {"ViewUp is zero or parallel", [](auto* a) { a->SetViewUp(0, 0, 1); }},
      {"ViewAngle must be in (0, 180)", [](auto* a) { a->SetViewAngle(180.0); }},
      {"ParallelScale",
       [](auto* a) {
         a->ParallelProjectionOn();
         a->SetParallelScale(0.0);
       }},
      {"Background components", [](auto* a) { a->SetBackground(2, 0, 0); }},
      {"light 0: intensity", [](auto* a) { a->AddPointLight(0, 1, 1, 1, 1, 1, -1); }},
      {"light 0: direction must be non-zero",
       [](auto* a) { a->AddDirectionalLight(0, 0, 0, 1, 1, 1, 1); }},
      {"default material: Reflectivity + Transparency must be <= 1",
       [](auto* a) {
         a->GetMaterial()->SetReflectivity(0.7);
         a->GetMaterial()->SetTransparency(0.5);
       }},
      {"material of input 0: IndexOfRefraction",
       [](auto* a) {
         vtkNew<vtkRayScopeMaterial> m;
         m->SetIndexOfRefraction(-1.0);
         a->SetInputMaterial(0, m);
       }},
      // Structure and storage: the core's one check (accel_storage_error),
      // as the CLI's --storage.
      {"storage split is not available for kdtree",
       [](auto* a) {
         a->SetAccelToKdTree();
         a->SetStorageToSplit();
       }},
      {"storage smallest-cell is not available for bvh",
       [](auto* a) { a->SetStorageToSmallestCell(); }},
      {"storage split is not available for grid",
       [](auto* a) {
         a->SetAccelToGrid();
         a->SetStorageToSplit();
       }},
      {"LooseFactor: loose factor must be a number from 0 to 0.5",
       [](auto* a) {
         a->SetAccelToGrid();
         a->SetStorageToSmallestCell();
         a->SetLooseFactor(0.7);
       }},
      {"GridResolution: resolution 5000 x 1 x 1 exceeds 4096 cells per axis",
       [](auto* a) {
         a->SetAccelToGrid();
         a->SetGridResolution(5000, 1, 1);
       }},
      {"GridResolution: cells per axis must be >= 0",
       [](auto* a) { a->SetGridResolution(4, -1, 4); }},
      {"storage smallest-cell is not available for spheres",
       [](auto* a) {
         a->SetAccelToSpheres();
         a->SetStorageToSmallestCell();
       }},
  };
  for (const Case& c : cases) {
    vtkNew<vtkRayScopeImageAlgorithm> alg;
    alg->AddInputConnection(s->GetOutputPort());
    alg->SetSize(40, 20);
    ASSERT_EQ(update(alg), 1);
    c.breakit(alg);
    vtkNew<ErrorCatcher> errors, pipeline_errors;
    alg->AddObserver(vtkCommand::ErrorEvent, errors);
    alg->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline_errors);
    EXPECT_EQ(update(alg), 0) << c.expect;
    // One error per update (the parameters are checked once), and the output
    // of the earlier good update is gone.
    EXPECT_EQ(errors->count, 1) << c.expect;
    EXPECT_NE(errors->last.find(c.expect), std::string::npos)
        << "expected '" << c.expect << "' in: " << errors->last;
    EXPECT_EQ(alg->GetOutput()->GetNumberOfPoints(), 0) << c.expect;
  }
  // No input at all.
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  vtkNew<ErrorCatcher> errors, pipeline_errors;
  alg->AddObserver(vtkCommand::ErrorEvent, errors);
  alg->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline_errors);
  alg->Update();
  EXPECT_GE(errors->count + pipeline_errors->count, 1);
}

// MinContribution is a weight within a sample: 0..1, both ends included.
TEST(VtkImage, MinContributionRange) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 0, 0, 0, 0.5, 16);
  for (double m : {0.0, 1e-3, 1.0}) {
    vtkNew<vtkRayScopeImageAlgorithm> alg;
    alg->AddInputConnection(s->GetOutputPort());
    alg->SetSize(20, 20);
    alg->GetMaterial()->SetReflectivity(0.5);
    alg->SetMinContribution(m);
    EXPECT_EQ(update(alg), 1) << m;
    EXPECT_EQ(alg->GetRenderSettings().min_contribution, float(m));
  }
}

// Adaptive sampling and the texture filter are properties: they reach the
// core's settings, and adaptive sampling with a target of 0 is the fixed
// render of its largest grid.
TEST(VtkImage, AdaptiveSamplingAndTextureFilter) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 0, 0, 0, 0.5, 16);
  vtkNew<vtkRayScopeImageAlgorithm> fixed, adaptive;
  for (vtkRayScopeImageAlgorithm* a : {fixed.Get(), adaptive.Get()}) {
    a->AddInputConnection(s->GetOutputPort());
    a->SetSize(24, 20);
    a->TextureFilterOn();
  }
  fixed->SetSamples(4);
  adaptive->SetSamples(2);
  adaptive->SetMaxSamples(4);
  ASSERT_EQ(update(fixed), 1);
  ASSERT_EQ(update(adaptive), 1);
  expect_same_colors(fixed->GetOutput(), adaptive->GetOutput());
  // "Samples": what each pixel took, only with adaptive sampling (all 16 at
  // a target of 0; flat pixels stop after two batches of 4 at 0.02).
  EXPECT_EQ(fixed->GetOutput()->GetPointData()->GetAbstractArray("Samples"), nullptr);
  auto samples = [&] {
    return vtkIntArray::SafeDownCast(
        adaptive->GetOutput()->GetPointData()->GetAbstractArray("Samples"));
  };
  ASSERT_NE(samples(), nullptr);
  ASSERT_EQ(samples()->GetNumberOfTuples(), 24 * 20);
  for (vtkIdType i = 0; i < samples()->GetNumberOfTuples(); ++i)
    ASSERT_EQ(samples()->GetValue(i), 16);
  adaptive->SetTargetError(0.02);
  ASSERT_EQ(update(adaptive), 1);
  ASSERT_NE(samples(), nullptr);
  int fewer = 0;
  for (vtkIdType i = 0; i < samples()->GetNumberOfTuples(); ++i) {
    const int n = samples()->GetValue(i);
    ASSERT_TRUE(n == 8 || n == 12 || n == 16) << n;
    fewer += n < 16;
  }
  EXPECT_GT(fewer, 24 * 20 / 2);  // the background, at least
  const rayscope::RenderSettings rs = adaptive->GetRenderSettings();
  EXPECT_EQ(rs.target_error, 0.02f);
  EXPECT_EQ(rs.max_samples, 4);
  EXPECT_TRUE(rs.texture_filter);
}

// A point with NaN coordinates: its triangles are left out with one warning
// naming the input and the problem; the image is still made, without NaN.
TEST(VtkImage, NonFinitePointsAreSkippedWithAWarning) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 0, 0, 0, 0.5, 16);
  s->Update();
  vtkNew<vtkPolyData> pd;
  pd->DeepCopy(s->GetOutput());
  pd->GetPoints()->SetPoint(3, std::nan(""), 0.0, 0.0);
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  alg->AddInputData(pd);
  alg->SetSize(32, 32);
  alg->SetPosition(0, 0, 3);
  vtkNew<ErrorCatcher> warnings, errors;
  alg->AddObserver(vtkCommand::WarningEvent, warnings);
  alg->AddObserver(vtkCommand::ErrorEvent, errors);
  ASSERT_EQ(update(alg), 1);
  EXPECT_EQ(errors->count, 0);
  ASSERT_EQ(warnings->count, 1);
  EXPECT_NE(warnings->last.find("triangles with non-finite vertex coordinates skipped"),
            std::string::npos)
      << warnings->last;
  vtkDataArray* color = alg->GetOutput()->GetPointData()->GetArray("Color");
  ASSERT_NE(color, nullptr);
  for (vtkIdType i = 0; i < color->GetNumberOfTuples(); ++i)
    for (int c = 0; c < color->GetNumberOfComponents(); ++c)
      ASSERT_TRUE(std::isfinite(color->GetComponent(i, c))) << "pixel " << i;
  EXPECT_GT(count_object(alg->GetOutput(), 0), 100);  // the rest of the sphere is there
}

// Changing only the camera re-renders without converting the geometry again;
// changing the input re-converts it.
TEST(VtkImage, FollowsPipelineChanges) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 0, 0, 0, 0.5);
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  alg->AddInputConnection(s->GetOutputPort());
  alg->SetSize(32, 32);
  alg->SetPosition(0, 0, 3);
  alg->Update();
  EXPECT_EQ(alg->GetNumberOfGeometryConversions(), 1);
  EXPECT_EQ(alg->GetNumberOfSceneCommits(), 1);
  const int before = count_object(alg->GetOutput(), 0);
  alg->SetPosition(0, 0, 6);  // farther: smaller
  alg->Update();
  const int farther = count_object(alg->GetOutput(), 0);
  EXPECT_LT(farther, before / 2);
  EXPECT_EQ(alg->GetNumberOfGeometryConversions(), 1);  // the camera only: nothing rebuilt
  EXPECT_EQ(alg->GetNumberOfSceneCommits(), 1);
  s->SetRadius(1.0);  // upstream change
  alg->Update();
  EXPECT_GT(count_object(alg->GetOutput(), 0), 3 * farther);
  EXPECT_EQ(alg->GetNumberOfGeometryConversions(), 2);
  EXPECT_EQ(alg->GetNumberOfSceneCommits(), 2);
}

// Updating a scene in place (camera with its headlight, material values,
// light values: no BVH rebuild) gives the very image of a fresh algorithm.
TEST(VtkImage, InPlaceUpdatesMatchFreshRender) {
  vtkNew<vtkSphereSource> a, b;
  configure_sphere(a, 0, 0, 0, 0.5);
  configure_sphere(b, 0.7, 0.2, -0.3, 0.3);
  auto setup = [&](vtkRayScopeImageAlgorithm* alg, double x, double color, double light_y) {
    alg->RemoveAllInputConnections(0);
    alg->AddInputConnection(a->GetOutputPort());
    alg->AddInputConnection(b->GetOutputPort());
    alg->SetSize(40, 30);
    alg->SetPosition(x, 0.5, 3);
    alg->GetMaterial()->SetColor(color, 0.5, 0.25);
    alg->GetMaterial()->SetReflectivity(0.3);
    alg->RemoveAllLights();
    alg->AddPointLight(1, light_y, 2, 1, 1, 1, 0.7);
  };
  auto colors = [](vtkRayScopeImageAlgorithm* alg) {
    vtkFloatArray* c =
        vtkFloatArray::SafeDownCast(alg->GetOutput()->GetPointData()->GetArray("LinearColor"));
    return std::vector<float>(c->GetPointer(0), c->GetPointer(0) + c->GetNumberOfValues());
  };
  vtkNew<vtkRayScopeImageAlgorithm> reused;
  setup(reused, 0.0, 1.0, 3.0);
  reused->Update();
  ASSERT_EQ(reused->GetNumberOfGeometryConversions(), 1);
  ASSERT_EQ(reused->GetNumberOfSceneCommits(), 1);
  for (auto [x, color, light_y] :
       {std::tuple{0.4, 1.0, 3.0}, std::tuple{0.4, 0.2, 3.0}, std::tuple{-0.3, 0.6, 1.5}}) {
    setup(reused, x, color, light_y);
    reused->Update();
    vtkNew<vtkRayScopeImageAlgorithm> fresh;
    setup(fresh, x, color, light_y);
    fresh->Update();
    EXPECT_EQ(colors(reused), colors(fresh)) << x << " " << color << " " << light_y;
    // Updated in place: the geometry is not converted again, the BVH not rebuilt.
    EXPECT_EQ(reused->GetNumberOfGeometryConversions(), 1);
    EXPECT_EQ(reused->GetNumberOfSceneCommits(), 1);
  }
}

// An algorithm renders frame after frame into the framebuffer it keeps: each
// output is a fresh algorithm's, array for array and bit for bit, when the
// size changes and when the Cost arrays come and go between frames.
TEST(VtkImage, FrameAfterFrameEqualsAFreshRender) {
  vtkNew<vtkSphereSource> a;
  configure_sphere(a, 0, 0, 0, 0.5);
  auto setup = [&](vtkRayScopeImageAlgorithm* alg, int w, int h, bool cost) {
    alg->RemoveAllInputConnections(0);
    alg->AddInputConnection(a->GetOutputPort());
    alg->SetSize(w, h);
    alg->SetPosition(0, 0.5, 3);
    alg->SetComputeCost(cost);
  };
  vtkNew<vtkRayScopeImageAlgorithm> reused;
  for (auto [w, h, cost] : {std::tuple{40, 30, true}, std::tuple{40, 30, false},
                            std::tuple{24, 20, true}, std::tuple{40, 30, false}}) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + (cost ? " cost" : ""));
    setup(reused, w, h, cost);
    reused->Update();
    vtkNew<vtkRayScopeImageAlgorithm> fresh;
    setup(fresh, w, h, cost);
    fresh->Update();
    vtkPointData* got = reused->GetOutput()->GetPointData();
    vtkPointData* want = fresh->GetOutput()->GetPointData();
    ASSERT_EQ(got->GetNumberOfArrays(), want->GetNumberOfArrays());
    EXPECT_EQ(got->GetArray("Cost") != nullptr, cost);
    for (int i = 0; i < want->GetNumberOfArrays(); ++i) {
      vtkDataArray* wa = want->GetArray(i);
      vtkDataArray* ga = got->GetArray(wa->GetName());
      ASSERT_NE(ga, nullptr) << wa->GetName();
      ASSERT_EQ(ga->GetDataSize(), wa->GetDataSize()) << wa->GetName();
      EXPECT_EQ(std::memcmp(ga->GetVoidPointer(0), wa->GetVoidPointer(0),
                            size_t(wa->GetDataSize()) * size_t(wa->GetDataTypeSize())),
                0)
          << wa->GetName();
    }
  }
}

// Frame after frame the output's arrays are filled again in place, unless
// someone kept them (a reference, a downstream shallow copy): those keep the
// frame they showed, and the next output gets new arrays.
TEST(VtkImage, OutputArraysAreFilledAgainUnlessKept) {
  vtkNew<vtkSphereSource> a;
  configure_sphere(a, 0, 0, 0, 0.5);
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  alg->AddInputConnection(a->GetOutputPort());
  alg->SetSize(40, 30);
  auto frame_from = [&](double x) {
    alg->SetPosition(x, 0.5, 3);
    alg->Update();
    return alg->GetOutput()->GetPointData();
  };
  auto values = [](vtkDataArray* d) {
    auto* f = vtkFloatArray::SafeDownCast(d);
    return std::vector<float>(f->GetPointer(0), f->GetPointer(0) + f->GetNumberOfValues());
  };
  vtkWeakPointer<vtkDataArray> first = frame_from(0.0)->GetArray("LinearColor");
  const std::vector<float> first_values = values(first);
  vtkDataArray* second = frame_from(0.6)->GetArray("LinearColor");
  ASSERT_NE(first.Get(), nullptr);  // not deleted: filled again
  EXPECT_EQ(second, first.Get());
  EXPECT_NE(values(second), first_values);

  vtkSmartPointer<vtkDataArray> kept = second;
  const std::vector<float> kept_values = values(kept);
  vtkNew<vtkImageData> downstream;
  downstream->ShallowCopy(alg->GetOutput());
  vtkDataArray* third = frame_from(-0.6)->GetArray("LinearColor");
  EXPECT_NE(third, kept.Get());
  EXPECT_EQ(values(kept), kept_values);
  EXPECT_EQ(values(downstream->GetPointData()->GetArray("LinearColor")), kept_values);
  EXPECT_NE(values(third), kept_values);
  // Every array of the new output is new, not only the one referenced.
  EXPECT_NE(alg->GetOutput()->GetPointData()->GetArray("Depth"),
            downstream->GetPointData()->GetArray("Depth"));
}

// AutoCamera: the image equals ResetCamera()'s, while the camera settings stay
// as they were (only their direction counts), and it follows the data.
TEST(VtkImage, AutoCameraFitsLikeResetCamera) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 2, 1, -3, 0.7);
  vtkNew<vtkRayScopeImageAlgorithm> reset, autocam;
  for (vtkRayScopeImageAlgorithm* a : {reset.Get(), autocam.Get()}) {
    a->AddInputConnection(s->GetOutputPort());
    a->SetSize(40, 30);
    a->SetPosition(1, 2, 5);  // view direction (1, 2, 5) - focal point (0, 0, 0)
  }
  ASSERT_EQ(reset->ResetCamera(), 1);
  autocam->AutoCameraOn();
  ASSERT_EQ(update(reset), 1);
  ASSERT_EQ(update(autocam), 1);
  expect_same_colors(reset->GetOutput(), autocam->GetOutput());
  EXPECT_EQ(autocam->GetPosition()[0], 1.0);  // the settings are not rewritten
  EXPECT_EQ(autocam->GetFocalPoint()[2], 0.0);
  EXPECT_EQ(object_at(autocam->GetOutput(), 20, 15), 0);

  s->SetCenter(-40, 3, 7);  // moved far away: still centered in the picture
  ASSERT_EQ(update(autocam), 1);
  EXPECT_EQ(object_at(autocam->GetOutput(), 20, 15), 0);
  EXPECT_EQ(object_at(autocam->GetOutput(), 0, 0), -1);
}

// One settings object shared by the image algorithm and the ray-tree,
// structure and range-query filters: a change made once (camera, structure)
// re-executes every filter, each on its own inputs, from the new values; a
// filter given other settings keeps its own.
TEST(VtkImage, SettingsSharedByEveryFilter) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 0, 0, 0, 0.5);
  vtkNew<vtkRayScopeSceneSettings> settings;
  settings->SetSize(40, 30);
  vtkNew<vtkRayScopeImageAlgorithm> image;
  vtkNew<vtkRayScopeRayTreeSource> tree;
  vtkNew<vtkRayScopeAccelSource> structure;
  vtkNew<vtkRayScopeRangeQuery> query;
  image->SetSettings(settings);
  EXPECT_EQ(image->GetSettings(), settings.Get());
  tree->SetSettings(image->GetSettings());
  structure->SetSettings(settings);
  query->SetSettings(settings);
  for (vtkAlgorithm* a : std::initializer_list<vtkAlgorithm*>{image, tree, structure, query})
    a->AddInputConnection(s->GetOutputPort());
  tree->SetPixel(20, 15);
  query->SetQueryTypeToNearest();
  query->SetCenter(0, 0, 2);
  for (double z : {4.0, 6.0}) {
    settings->SetPosition(0, 0, z);  // one change, through the shared object
    EXPECT_EQ(image->GetPosition()[2], z);
    ASSERT_EQ(update(image), 1);
    const double depth =
        image->GetOutput()->GetPointData()->GetArray("Depth")->GetTuple1(15 * 40 + 20);
    EXPECT_NEAR(depth, z - 0.5, 0.02);
    ASSERT_EQ(update(tree), 1);
    vtkPolyData* rays = tree->GetOutput();
    double gap = 1e30;  // the primary ray starts at the eye
    for (vtkIdType p = 0; p < rays->GetNumberOfPoints(); ++p) {
      const double* x = rays->GetPoint(p);
      gap = std::min(gap, std::abs(x[0]) + std::abs(x[1]) + std::abs(x[2] - z));
    }
    EXPECT_LT(gap, 1e-6) << z;
  }
  auto structure_of = [](vtkPolyDataAlgorithm* a) {
    EXPECT_EQ(update(a), 1);
    auto* names =
        vtkStringArray::SafeDownCast(a->GetOutput()->GetFieldData()->GetAbstractArray("Structure"));
    return names ? names->GetValue(0) : std::string("none");
  };
  EXPECT_EQ(structure_of(structure), "bvh");
  settings->SetAccelToKdTree();
  EXPECT_EQ(structure_of(structure), "kdtree");
  EXPECT_EQ(structure_of(query), "kdtree");
  // Other settings for one filter: the shared object no longer reaches it.
  vtkNew<vtkRayScopeSceneSettings> own;
  query->SetSettings(own);
  settings->SetAccelToOctree();
  EXPECT_EQ(structure_of(structure), "octree");
  EXPECT_EQ(structure_of(query), "bvh");
  query->SetSettings(nullptr);  // back to new defaults of its own
  EXPECT_NE(query->GetSettings(), own.Get());
  EXPECT_EQ(query->GetSettings()->GetAutoCamera(), 1);
}

// SetMaterial replaces the default material; AddLight adds either kind and
// rejects other types.
TEST(VtkImage, SetMaterialAndAddLight) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 0, 0, 0, 0.5);
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  alg->AddInputConnection(s->GetOutputPort());
  alg->SetSize(20, 20);
  alg->AutoCameraOn();
  vtkNew<vtkRayScopeMaterial> red;
  red->SetColor(1, 0, 0);
  alg->SetMaterial(red);
  EXPECT_EQ(alg->GetMaterial(), red.Get());
  ASSERT_EQ(update(alg), 1);
  const double* c =
      alg->GetOutput()->GetPointData()->GetArray("LinearColor")->GetTuple3(10 * 20 + 10);
  EXPECT_GT(c[0], 0.1);
  EXPECT_EQ(c[1], 0.0);
  EXPECT_EQ(c[2], 0.0);
  alg->SetMaterial(nullptr);  // back to a default (white) material
  EXPECT_NE(alg->GetMaterial(), red.Get());
  EXPECT_EQ(alg->GetMaterial()->GetColor()[1], 1.0);

  EXPECT_EQ(alg->AddLight(vtkRayScopeImageAlgorithm::LIGHT_POINT, 1, 2, 3, 1, 1, 1, 1), 0);
  EXPECT_EQ(alg->AddLight(vtkRayScopeImageAlgorithm::LIGHT_DIRECTIONAL, 0, -1, 0, 1, 1, 1, 1), 1);
  vtkNew<ErrorCatcher> errors;  // the lights are the settings': they report it
  alg->GetSettings()->AddObserver(vtkCommand::ErrorEvent, errors);
  EXPECT_EQ(alg->AddLight(2, 0, 0, 0, 1, 1, 1, 1), -1);
  EXPECT_EQ(errors->count, 1);
  EXPECT_NE(errors->last.find("AddLight: type 2"), std::string::npos) << errors->last;
  EXPECT_EQ(alg->GetNumberOfLights(), 2);
}

// ScalarColoring: solid ignores scalars; by array maps the chosen point array
// through the given table (over the table's range) or over the array's range.
TEST(VtkImage, ScalarColoringModes) {
  vtkNew<vtkPlaneSource> plane;  // in z = 0, facing +z, x and y in [-0.5, 0.5]
  plane->SetResolution(8, 8);
  plane->Update();
  vtkNew<vtkPolyData> pd;
  pd->DeepCopy(plane->GetOutput());
  vtkNew<vtkFloatArray> x;
  x->SetName("X");
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
    x->InsertNextValue(float(pd->GetPoint(i)[0] + 0.5));
  pd->GetPointData()->AddArray(x);
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  alg->AddInputData(pd);
  alg->SetSize(32, 32);
  alg->AutoCameraOn();
  alg->HeadlightOff();
  alg->GetMaterial()->SetAmbient(1.0);  // color = the surface color exactly
  alg->GetMaterial()->SetDiffuse(0.0);
  auto color_at = [&](int i) {
    const double* c =
        alg->GetOutput()->GetPointData()->GetArray("LinearColor")->GetTuple3(16 * 32 + i);
    return std::vector<double>(c, c + 3);
  };
  alg->SetScalarColoring(vtkRayScopeImageAlgorithm::COLOR_SOLID);
  ASSERT_EQ(update(alg), 1);
  EXPECT_EQ(color_at(7), (std::vector<double>{1.0, 1.0, 1.0}));

  vtkNew<ErrorCatcher> errors;
  alg->AddObserver(vtkCommand::ErrorEvent, errors);
  alg->SetScalarColoring(vtkRayScopeImageAlgorithm::COLOR_BY_ARRAY);
  EXPECT_EQ(update(alg), 0);  // no array chosen
  EXPECT_NE(errors->last.find("no array is chosen"), std::string::npos) << errors->last;

  alg->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "X");
  ASSERT_EQ(update(alg), 1);
  // VTK's default table (red at 0 to blue at 1) over X's range [0, 1]: red on
  // the left, blue on the right.
  std::vector<double> left = color_at(7), right = color_at(24);  // X ~ 0.12, 0.88
  EXPECT_GT(left[0], left[2]);
  EXPECT_GT(right[2], right[0]);

  vtkNew<vtkLookupTable> grey;  // black to white over [0, 2]: the left half is dark
  grey->SetHueRange(0, 0);
  grey->SetSaturationRange(0, 0);
  grey->SetValueRange(0, 1);
  grey->SetTableRange(0, 2);
  grey->Build();
  alg->SetLookupTable(grey);
  ASSERT_EQ(update(alg), 1);
  std::vector<double> g = color_at(24);
  EXPECT_EQ(g[0], g[1]);
  EXPECT_EQ(g[1], g[2]);
  EXPECT_LT(g[0], 0.35);  // X ~ 0.88 of a [0, 2] table: a value of ~0.44, ~0.16 linear
  EXPECT_GT(g[0], 0.1);
}
