// Composite data (vtkMultiBlockDataSet, vtkPartitionedDataSet,
// vtkPartitionedDataSetCollection) is one scene: every leaf a scene object,
// traced together (blocks shadow each other), one image out of the image
// algorithm and one polydata out of the ray-tree, structure and range-query
// filters; and the headlight casts no shadow.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <vtkAppendPolyData.h>
#include <vtkCellData.h>
#include <vtkCompositeDataDisplayAttributes.h>
#include <vtkCubeSource.h>
#include <vtkDataObjectTreeIterator.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkMultiPieceDataSet.h>
#include <vtkNew.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkSphereSource.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>

#include "vtkRayScopeAccelSource.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeRangeQuery.h"
#include "vtkRayScopeRayTreeSource.h"
#include "vtk_test_util.h"

namespace {

constexpr int kWidth = 96, kHeight = 72;

// A floor with a sphere above it and a point light above the sphere, so the
// sphere's shadow falls on the floor in view.
struct Blocks {
  vtkSmartPointer<vtkPolyData> floor = vtkSmartPointer<vtkPolyData>::New();
  vtkSmartPointer<vtkPolyData> ball = vtkSmartPointer<vtkPolyData>::New();
  Blocks() {
    vtkNew<vtkPlaneSource> p;
    configure_floor(p, -0.5, 2.0);
    p->Update();
    floor->ShallowCopy(p->GetOutput());
    vtkNew<vtkSphereSource> s;
    configure_sphere(s, 0.0, 0.1, 0.0, 0.4, 32);
    s->Update();
    ball->ShallowCopy(s->GetOutput());
  }
  vtkSmartPointer<vtkMultiBlockDataSet> multiblock() const {
    auto mb = vtkSmartPointer<vtkMultiBlockDataSet>::New();
    mb->SetBlock(0, floor);
    mb->SetBlock(1, ball);
    return mb;
  }
};

void set_up(vtkRayScopeImageAlgorithm* alg) {
  alg->SetSize(kWidth, kHeight);
  alg->SetPosition(0.0, 1.5, 3.0);
  alg->SetFocalPoint(0.0, -0.2, 0.0);
  alg->SetViewUp(0.0, 1.0, 0.0);
  alg->SetViewAngle(40.0);
  alg->AddPointLight(0.2, 3.0, 0.2, 1.0, 1.0, 1.0, 1.0);
  alg->ComputeCostOff();
}

vtkUnsignedCharArray* colors(vtkImageData* img) {
  return vtkUnsignedCharArray::SafeDownCast(img->GetPointData()->GetArray("Color"));
}

int object_at(vtkImageData* img, vtkIdType pixel) {
  return vtkIntArray::SafeDownCast(img->GetPointData()->GetArray("ObjectId"))->GetValue(pixel);
}

std::vector<int> field_ints(vtkImageData* img, const char* name) {
  auto* a = vtkIntArray::SafeDownCast(img->GetFieldData()->GetAbstractArray(name));
  std::vector<int> out;
  for (vtkIdType i = 0; a && i < a->GetNumberOfTuples(); ++i) out.push_back(a->GetValue(i));
  return out;
}

// Whether two images have the same bytes in "Color" and the same ObjectId.
bool same_pixels(vtkImageData* a, vtkImageData* b) {
  vtkUnsignedCharArray *ca = colors(a), *cb = colors(b);
  if (!ca || !cb || ca->GetNumberOfValues() != cb->GetNumberOfValues()) return false;
  for (vtkIdType i = 0; i < ca->GetNumberOfValues(); ++i)
    if (ca->GetValue(i) != cb->GetValue(i)) return false;
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
    if (object_at(a, i) != object_at(b, i)) return false;
  return true;
}

}  // namespace

TEST(VtkComposite, MultiBlockIsOneSceneAsItsBlocksAsInputs) {
  Blocks blocks;
  vtkNew<vtkRayScopeImageAlgorithm> composite;
  set_up(composite);
  composite->SetInputData(blocks.multiblock());
  ASSERT_EQ(update(composite), 1);
  vtkImageData* img = composite->GetOutput();
  ASSERT_NE(img, nullptr) << "the output is one image, not a multiblock of images";
  EXPECT_EQ(img->GetNumberOfPoints(), vtkIdType(kWidth * kHeight));
  EXPECT_GT(count_object(img, 0), 100);
  EXPECT_GT(count_object(img, 1), 100);
  EXPECT_EQ(field_ints(img, "ObjectInput"), (std::vector<int>{0, 0}));
  EXPECT_EQ(field_ints(img, "ObjectFlatIndex"), (std::vector<int>{1, 2}));
  auto* names = vtkStringArray::SafeDownCast(img->GetFieldData()->GetAbstractArray("ObjectName"));
  ASSERT_NE(names, nullptr);
  EXPECT_EQ(names->GetValue(1), "input 0 block 2");

  // The same two datasets as two inputs are the same scene, pixel for pixel.
  vtkNew<vtkRayScopeImageAlgorithm> separate;
  set_up(separate);
  separate->AddInputData(blocks.floor);
  separate->AddInputData(blocks.ball);
  ASSERT_EQ(update(separate), 1);
  EXPECT_TRUE(same_pixels(img, separate->GetOutput()));
  EXPECT_EQ(field_ints(separate->GetOutput(), "ObjectFlatIndex"), (std::vector<int>{-1, -1}));
}

TEST(VtkComposite, BlocksShadowEachOther) {
  Blocks blocks;
  vtkNew<vtkRayScopeImageAlgorithm> both, floor_only;
  set_up(both);
  set_up(floor_only);
  both->SetInputData(blocks.multiblock());
  auto floor_mb = vtkSmartPointer<vtkMultiBlockDataSet>::New();
  floor_mb->SetBlock(0, blocks.floor);
  floor_only->SetInputData(floor_mb);
  ASSERT_EQ(update(both), 1);
  ASSERT_EQ(update(floor_only), 1);
  // Floor pixels in view in both images that the sphere darkens: its shadow.
  vtkImageData *a = both->GetOutput(), *b = floor_only->GetOutput();
  int shadowed = 0;
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
    if (object_at(a, i) == 0 && object_at(b, i) == 0)
      shadowed += colors(a)->GetValue(3 * i) + 30 < colors(b)->GetValue(3 * i);
  EXPECT_GT(shadowed, 50);
}

TEST(VtkComposite, FlatIndicesNamesAndPartitionedCollections) {
  Blocks blocks;
  // Nested: block 0 a multiblock holding an empty block and the floor (named),
  // block 1 a multi-piece dataset (a vtkPartitionedDataSet) of the sphere.
  auto inner = vtkSmartPointer<vtkMultiBlockDataSet>::New();
  inner->SetNumberOfBlocks(2);
  inner->SetBlock(1, blocks.floor);
  inner->GetMetaData(1u)->Set(vtkCompositeDataSet::NAME(), "floor");
  auto parts = vtkSmartPointer<vtkMultiPieceDataSet>::New();
  parts->SetPartition(0, blocks.ball);
  auto outer = vtkSmartPointer<vtkMultiBlockDataSet>::New();
  outer->SetBlock(0, inner);
  outer->SetBlock(1, parts);

  // The flat indices VTK's own iterator gives the leaves.
  std::vector<int> expected;
  vtkNew<vtkDataObjectTreeIterator> it;
  it->SetDataSet(outer);
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    expected.push_back(int(it->GetCurrentFlatIndex()));
  ASSERT_EQ(expected.size(), 2u);

  vtkNew<vtkRayScopeImageAlgorithm> alg;
  set_up(alg);
  alg->SetInputData(outer);
  ASSERT_EQ(update(alg), 1);
  EXPECT_EQ(field_ints(alg->GetOutput(), "ObjectFlatIndex"), expected);
  EXPECT_EQ(alg->GetObjectName(0), "input 0 block " + std::to_string(expected[0]) + " 'floor'");

  // A partitioned dataset collection of the same two datasets: the same image.
  auto collection = vtkSmartPointer<vtkPartitionedDataSetCollection>::New();
  collection->SetPartition(0, 0, blocks.floor);
  collection->SetPartition(1, 0, blocks.ball);
  vtkNew<vtkRayScopeImageAlgorithm> pdc;
  set_up(pdc);
  pdc->SetInputData(collection);
  ASSERT_EQ(update(pdc), 1);
  ASSERT_NE(pdc->GetOutput(), nullptr);
  EXPECT_TRUE(same_pixels(alg->GetOutput(), pdc->GetOutput()));
}

TEST(VtkComposite, BlockVisibilityColorAndOpacity) {
  Blocks blocks;
  auto mb = blocks.multiblock();
  vtkNew<vtkCompositeDataDisplayAttributes> attributes;
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  set_up(alg);
  alg->SetInputData(mb);
  alg->SetInputBlockAttributes(0, attributes);
  ASSERT_EQ(update(alg), 1);
  const int ball_pixels = count_object(alg->GetOutput(), 1);
  ASSERT_GT(ball_pixels, 100);

  // A red floor block: its pixels turn red.
  const double red[3] = {1.0, 0.0, 0.0};
  attributes->SetBlockColor(blocks.floor, red);
  ASSERT_EQ(update(alg), 1);
  vtkImageData* img = alg->GetOutput();
  int red_pixels = 0, floor_pixels = 0;
  for (vtkIdType i = 0; i < img->GetNumberOfPoints(); ++i)
    if (object_at(img, i) == 0) {
      ++floor_pixels;
      red_pixels += colors(img)->GetValue(3 * i) > 0 && colors(img)->GetValue(3 * i + 1) == 0 &&
                    colors(img)->GetValue(3 * i + 2) == 0;
    }
  EXPECT_GT(red_pixels, floor_pixels / 2);

  // Hiding the multiblock hides both blocks, unless a block shows itself.
  attributes->SetBlockVisibility(mb, false);
  attributes->SetBlockVisibility(blocks.floor, true);
  ASSERT_EQ(update(alg), 1);
  EXPECT_EQ(count_object(alg->GetOutput(), 1), 0) << "one object left: the floor";
  EXPECT_EQ(field_ints(alg->GetOutput(), "ObjectFlatIndex"), (std::vector<int>{1}));

  // Nothing visible is an error and an empty image, not a crash.
  attributes->SetBlockVisibility(blocks.floor, false);
  vtkNew<ErrorCatcher> errors;
  alg->AddObserver(vtkCommand::ErrorEvent, errors);
  EXPECT_EQ(update(alg), 0);
  EXPECT_NE(errors->last.find("the composite inputs hold no dataset"), std::string::npos)
      << errors->last;
  EXPECT_EQ(alg->GetOutput()->GetNumberOfPoints(), 0);
}

TEST(VtkComposite, SceneFiltersTakeCompositeDataWhole) {
  Blocks blocks;
  auto mb = blocks.multiblock();
  vtkNew<vtkRayScopeRayTreeSource> tree;
  tree->SetInputData(mb);
  tree->GetSettings()->SetSize(kWidth, kHeight);
  tree->SetPixel(kWidth / 2, kHeight / 2);
  ASSERT_EQ(update(tree), 1);
  auto* rays = vtkPolyData::SafeDownCast(tree->GetOutputDataObject(0));
  ASSERT_NE(rays, nullptr) << "one polydata, not one per block";
  auto* ids = vtkIntArray::SafeDownCast(rays->GetCellData()->GetArray("ObjectId"));
  ASSERT_NE(ids, nullptr);
  bool hits_ball = false;
  for (vtkIdType c = 0; c < ids->GetNumberOfTuples(); ++c) hits_ball |= ids->GetValue(c) == 1;
  EXPECT_TRUE(hits_ball) << "the auto camera looks at the middle of both blocks: the sphere";

  vtkNew<vtkRayScopeAccelSource> accel;
  accel->SetInputData(mb);
  ASSERT_EQ(update(accel), 1);
  EXPECT_NE(vtkPolyData::SafeDownCast(accel->GetOutputDataObject(0)), nullptr);

  vtkNew<vtkRayScopeRangeQuery> query;
  query->SetInputData(mb);
  ASSERT_EQ(update(query), 1);
  EXPECT_NE(vtkPolyData::SafeDownCast(query->GetOutputDataObject(0)), nullptr);
}

TEST(VtkComposite, HeadlightCastsNoShadow) {
  // A block with a step (a box on a wider box), seen from above and the side.
  // A light along the view casting shadows, as the headlight once was,
  // darkens the faces behind the step's edges; the headlight, a light at the
  // eye, casts no shadow the eye can see: the image is the same with and
  // without shadow rays, though they are traced.
  vtkNew<vtkCubeSource> base, step;
  base->SetBounds(-1.0, 1.0, -0.3, 0.0, -1.0, 1.0);
  step->SetBounds(-1.0, 0.0, 0.0, 0.4, -1.0, 0.2);
  vtkNew<vtkAppendPolyData> part;
  part->AddInputConnection(base->GetOutputPort());
  part->AddInputConnection(step->GetOutputPort());
  auto render = [&](bool headlight, bool shadows) {
    auto alg = vtkSmartPointer<vtkRayScopeImageAlgorithm>::New();
    alg->SetInputConnection(part->GetOutputPort());
    alg->SetSize(kWidth, kHeight);
    alg->SetPosition(2.0, 2.5, 3.5);
    alg->SetFocalPoint(0.0, 0.0, 0.0);
    alg->SetViewAngle(35.0);
    alg->SetHeadlight(headlight);
    // Without the headlight: a shadow-casting light along the same view.
    if (!headlight) alg->AddDirectionalLight(-2.0, -2.5, -3.5, 1.0, 1.0, 1.0, 1.0);
    alg->SetShadows(shadows);
    alg->ComputeCostOff();
    EXPECT_EQ(update(alg), 1);
    auto out = vtkSmartPointer<vtkImageData>::New();
    out->DeepCopy(alg->GetOutput());
    return out;
  };
  auto darker = [](vtkImageData* a, vtkImageData* b) {  // pixels of a darker than in b
    int n = 0;
    for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
      n += colors(a)->GetValue(3 * i) + 8 < colors(b)->GetValue(3 * i);
    return n;
  };
  auto lit = render(true, true), unshadowed = render(true, false);
  EXPECT_EQ(darker(lit, unshadowed), 0);
  EXPECT_TRUE(same_pixels(lit, unshadowed));
  vtkDataArray* rays = lit->GetFieldData()->GetArray("RayCounts");
  vtkDataArray* occluded = lit->GetFieldData()->GetArray("ShadowRaysOccluded");
  ASSERT_NE(rays, nullptr);
  ASSERT_NE(occluded, nullptr);
  EXPECT_GT(rays->GetComponent(0, 1), 0.0) << "shadow rays toward the headlight are traced";
  EXPECT_EQ(occluded->GetComponent(0, 0), 0.0) << "and none is blocked";
  // The scene does show the bands with a shadow-casting light along the view
  // (perspective makes shadow rays leave the eye's rays): the check can fail.
  EXPECT_GT(darker(render(false, true), render(false, false)), 0);
}
