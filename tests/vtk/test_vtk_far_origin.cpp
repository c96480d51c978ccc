// Data far from the world's origin through the VTK module: the image
// algorithm traces around the center of its inputs' bounds (Scene::origin),
// with points of double-precision data moved there before they are rounded to
// float, so geospatial data (1e5..1e7: UTM, ECEF) renders as it would at the
// origin; the BVH and ray-tree sources output world coordinates.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkTransform.h>
#include <vtkTransformFilter.h>
#include <vtkUnsignedCharArray.h>

#include "vtkRayScopeAccelSource.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeMaterial.h"
#include "vtkRayScopeRayTreeSource.h"
#include "vtk_test_util.h"

namespace {

const char* const kBunny = "/usr/share/glmark2/models/bunny.obj";

// PSNR in dB of two 8-bit sRGB "Color" arrays.
double psnr8(vtkImageData* a, vtkImageData* b) {
  auto* ca = vtkUnsignedCharArray::SafeDownCast(a->GetPointData()->GetArray("Color"));
  auto* cb = vtkUnsignedCharArray::SafeDownCast(b->GetPointData()->GetArray("Color"));
  double se = 0.0;
  vtkIdType n = 0;
  for (vtkIdType i = 0; i < ca->GetNumberOfTuples(); ++i)
    for (int k = 0; k < 3; ++k, ++n) {
      const double d = (double(ca->GetTypedComponent(i, k)) - cb->GetTypedComponent(i, k)) / 255.0;
      se += d * d;
    }
  const double mse = se / double(n);
  return mse == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(1.0 / mse);
}

// The bunny on a floor, lit by a point light and the headlight, everything
// moved by (d, d, d): the data through vtkTransformFilter with double output
// points (as geospatial data arrives), the camera and the light by hand.
struct MovedScene {
  vtkNew<vtkOBJReader> reader;
  vtkNew<vtkPlaneSource> floor;
  vtkNew<vtkTransform> move;
  vtkNew<vtkTransformFilter> bunny_moved, floor_moved;
  vtkNew<vtkRayScopeMaterial> floor_material;
  vtkNew<vtkRayScopeImageAlgorithm> alg;

  explicit MovedScene(double d) {
    reader->SetFileName(kBunny);
    floor->SetOrigin(-0.3, 0.033, -0.3);
    floor->SetPoint1(0.3, 0.033, -0.3);
    floor->SetPoint2(-0.3, 0.033, 0.3);
    move->Translate(d, d, d);
    bunny_moved->SetInputConnection(reader->GetOutputPort());
    floor_moved->SetInputConnection(floor->GetOutputPort());
    for (vtkTransformFilter* f : {bunny_moved.Get(), floor_moved.Get()}) {
      f->SetTransform(move);
      f->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
      alg->AddInputConnection(f->GetOutputPort());
    }
    floor_material->SetReflectivity(0.3);
    alg->SetInputMaterial(1, floor_material);
    alg->SetSize(160, 120);
    alg->SetSamples(2);
    alg->SetPosition(0.1 + d, 0.2 + d, 0.45 + d);
    alg->SetFocalPoint(-0.02 + d, 0.1 + d, d);
    alg->AddPointLight(0.5 + d, 1.0 + d, 0.6 + d, 1, 1, 1, 0.8);
    alg->Update();
  }
};

}  // namespace

// Measured (160x120, 2x2 samples): identical images at 1e5, 1e6 and 1e7 (the
// local origin moves with the data, so the tracer sees the same numbers up
// to the rounding of double sums). Before the local origin, vertices rounded
// to float at 1e6 (spacing 0.0625, a third of the bunny) left a few blobs.
// Required: the 40 dB.
TEST(VtkFarFromOrigin, MovedDataRendersTheSameImage) {
  ASSERT_TRUE(std::filesystem::exists(kBunny)) << kBunny << " is missing (scripts/setup)";
  MovedScene ref(0.0);
  ASSERT_GT(count_object(ref.alg->GetOutput(), 0), 2000);  // the bunny fills part of the view
  for (double d : {1e5, 1e6, 1e7}) {
    MovedScene far(d);
    const double p = psnr8(ref.alg->GetOutput(), far.alg->GetOutput());
    std::printf("offset %g: PSNR %.2f dB\n", d, p);
    EXPECT_GE(p, 40.0) << "offset " << d;
  }
}

// The BVH source's boxes and the ray-tree source's rays are in world
// coordinates: the root box is the data's bounds, the primary ray starts at
// the camera.
TEST(VtkFarFromOrigin, SourcesOutputWorldCoordinates) {
  ASSERT_TRUE(std::filesystem::exists(kBunny)) << kBunny << " is missing (scripts/setup)";
  const double d = 1e6;
  MovedScene far(d);
  vtkNew<vtkRayScopeAccelSource> bvh;
  bvh->SetSceneSource(far.alg);
  bvh->SetLevelRange(0, 0);  // the root's box
  bvh->Update();
  vtkPolyData* boxes = bvh->GetOutput();
  ASSERT_EQ(boxes->GetPoints()->GetDataType(), VTK_DOUBLE);
  double got[6], want[6];
  boxes->GetBounds(got);
  far.bunny_moved->GetOutput()->GetBounds(want);
  double floor_b[6];
  far.floor_moved->GetOutput()->GetBounds(floor_b);
  for (int k = 0; k < 3; ++k) {
    want[2 * k] = std::min(want[2 * k], floor_b[2 * k]);
    want[2 * k + 1] = std::max(want[2 * k + 1], floor_b[2 * k + 1]);
  }
  // The boxes are the float bounds of local coordinates of size ~0.3: within
  // a few float ulps (1e-7) of the data's, not float's spacing at 1e6 (0.06).
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(got[k], want[k], 1e-6) << "bound " << k;

  vtkNew<vtkRayScopeRayTreeSource> tree;
  tree->SetSceneSource(far.alg);
  tree->SetPixel(80, 60);
  tree->Update();
  vtkPolyData* rays = tree->GetOutput();
  ASSERT_GT(rays->GetNumberOfPoints(), 1);
  double origin[3];
  rays->GetPoint(0, origin);  // the first ray's start: the camera
  const double* eye = far.alg->GetPosition();
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(origin[k], eye[k], 1e-6) << "axis " << k;
}
