// vtkRayScopePass and vtkRayScopeImageAlgorithm::CopyRenderer: a renderer made
// of ordinary VTK actors, lights and a camera, ray-traced by the render pass,
// shows in its window exactly the image the image algorithm produces for the
// same scene described by hand (datasets, materials, lights, camera);
// composite data drawn by a composite mapper is one scene. Needs
// an X display (run under xvfb-run).
#include <gtest/gtest.h>

#include "needs_display.h"

#include <cmath>
#include <string>
#include <vector>

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCompositeDataDisplayAttributes.h>
#include <vtkCompositePolyDataMapper2.h>
#include <vtkDataArray.h>
#include <vtkElevationFilter.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkLight.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartVolumeMapper.h>
#include <vtkSphereSource.h>
#include <vtkTransform.h>
#include <vtkTransformFilter.h>
#include <vtkUnsignedCharArray.h>
#include <vtkVolume.h>
#include <vtkWindowToImageFilter.h>

#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeMaterial.h"
#include "vtkRayScopeMeshConverter.h"
#include "vtkRayScopePass.h"
#include "vtk_test_util.h"

namespace {

constexpr int kWidth = 160, kHeight = 120;

// An elevation-colored sphere (point scalars through the mapper's lookup
// table), a reflective floor, and a glass sphere moved by its actor's
// position; a point light with attenuation and a directional light.
struct RendererScene {
  vtkNew<vtkSphereSource> ball, glass;
  vtkNew<vtkElevationFilter> elevation;
  vtkNew<vtkPlaneSource> floor;
  vtkNew<vtkPolyDataMapper> ball_mapper, floor_mapper, glass_mapper;
  vtkNew<vtkActor> ball_actor, floor_actor, glass_actor;
  vtkNew<vtkLight> point, sun;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;
  vtkNew<vtkRayScopePass> pass;

  RendererScene() {
    configure_sphere(ball, 0.0, 0.0, 0.0, 0.5, 48);
    elevation->SetInputConnection(ball->GetOutputPort());
    elevation->SetLowPoint(0, -0.5, 0);
    elevation->SetHighPoint(0, 0.5, 0);
    ball_mapper->SetInputConnection(elevation->GetOutputPort());
    ball_actor->SetMapper(ball_mapper);
    ball_actor->GetProperty()->SetSpecular(0.4);
    ball_actor->GetProperty()->SetSpecularPower(30);

    configure_floor(floor, -0.5, 3.0);
    floor_mapper->SetInputConnection(floor->GetOutputPort());
    floor_actor->SetMapper(floor_mapper);
    floor_actor->GetProperty()->SetColor(0.8, 0.7, 0.5);
    vtkRayScopeMaterial::SetPropertyReflectivity(floor_actor->GetProperty(), 0.4);

    configure_sphere(glass, 0.0, 0.0, 0.0, 0.3, 40);
    glass_mapper->SetInputConnection(glass->GetOutputPort());
    glass_actor->SetMapper(glass_mapper);
    glass_actor->SetPosition(0.75, -0.2, 0.6);
    glass_actor->GetProperty()->SetOpacity(0.1);
    vtkRayScopeMaterial::SetPropertyIndexOfRefraction(glass_actor->GetProperty(), 1.33);

    renderer->AddActor(ball_actor);
    renderer->AddActor(floor_actor);
    renderer->AddActor(glass_actor);

    point->SetLightTypeToSceneLight();
    point->SetPositional(true);
    point->SetPosition(2.0, 3.0, 2.5);
    point->SetConeAngle(90.0);
    point->SetAttenuationValues(1.0, 0.05, 0.0);
    point->SetDiffuseColor(1.0, 0.9, 0.8);
    point->SetIntensity(0.9);
    sun->SetLightTypeToSceneLight();
    sun->SetPosition(-1.0, 2.0, 1.0);
    sun->SetFocalPoint(0.0, 0.0, 0.0);
    sun->SetIntensity(0.5);
    renderer->AddLight(point);
    renderer->AddLight(sun);
    renderer->SetBackground(0.1, 0.2, 0.3);

    vtkCamera* c = renderer->GetActiveCamera();
    c->SetPosition(0.5, 1.2, 4.0);
    c->SetFocalPoint(0.1, -0.1, 0.0);
    c->SetViewUp(0.0, 1.0, 0.0);
    c->SetViewAngle(35.0);

    window->SetSize(kWidth, kHeight);
    window->SetOffScreenRendering(1);
    window->AddRenderer(renderer);
    renderer->SetPass(pass);
  }

  // Renders through the pass and reads back what the window shows.
  vtkSmartPointer<vtkImageData> render_and_read() {
    window->Render();
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(window);
    grab->ReadFrontBufferOff();
    grab->ShouldRerenderOff();
    grab->Update();
    vtkSmartPointer<vtkImageData> out = vtkSmartPointer<vtkImageData>::New();
    out->DeepCopy(grab->GetOutput());
    return out;
  }
};

// The same scene, described to the image algorithm by hand.
struct HandScene {
  vtkNew<vtkTransformFilter> moved_glass;
  vtkNew<vtkTransform> translation;
  vtkNew<vtkRayScopeMaterial> ball_material, floor_material, glass_material;
  vtkNew<vtkRayScopeImageAlgorithm> alg;

  explicit HandScene(RendererScene& r) {
    translation->Translate(0.75, -0.2, 0.6);
    moved_glass->SetTransform(translation);
    moved_glass->SetInputConnection(r.glass->GetOutputPort());
    alg->AddInputConnection(r.elevation->GetOutputPort());
    alg->AddInputConnection(r.floor->GetOutputPort());
    alg->AddInputConnection(moved_glass->GetOutputPort());
    // vtkProperty defaults: white, ambient 0, diffuse 1, specular color white.
    ball_material->SetSpecular(0.4);
    ball_material->SetSpecularPower(30);
    floor_material->SetColor(0.8, 0.7, 0.5);
    floor_material->SetReflectivity(0.4);
    glass_material->SetTransparency(1.0 - 0.1);
    glass_material->SetIndexOfRefraction(1.33);
    alg->SetInputMaterial(0, ball_material);
    alg->SetInputMaterial(1, floor_material);
    alg->SetInputMaterial(2, glass_material);
    alg->SetHeadlight(0);
    int p = alg->AddPointLight(2.0, 3.0, 2.5, 1.0, 0.9, 0.8, 0.9);
    alg->SetLightAttenuation(p, 1.0, 0.05, 0.0);
    alg->AddDirectionalLight(1.0, -2.0, -1.0, 1.0, 1.0, 1.0, 0.5);
    alg->SetBackground(0.1, 0.2, 0.3);
    alg->SetSize(kWidth, kHeight);
    alg->SetPosition(0.5, 1.2, 4.0);
    alg->SetFocalPoint(0.1, -0.1, 0.0);
    alg->SetViewUp(0.0, 1.0, 0.0);
    alg->SetViewAngle(35.0);
    alg->ComputeCostOff();
  }
};

// Largest difference of any RGB byte between the window and a traced image.
int max_byte_difference(vtkImageData* shown, vtkImageData* traced) {
  int ds[3], dt[3];
  shown->GetDimensions(ds);
  traced->GetDimensions(dt);
  if (ds[0] != dt[0] || ds[1] != dt[1]) return 1000;
  auto* a = vtkUnsignedCharArray::SafeDownCast(shown->GetPointData()->GetScalars());
  auto* b = vtkUnsignedCharArray::SafeDownCast(traced->GetPointData()->GetScalars());
  if (!a || !b) return 1000;
  int m = 0;
  for (vtkIdType i = 0; i < b->GetNumberOfTuples(); ++i)
    for (int k = 0; k < 3; ++k)
      m = std::max(m, std::abs(int(a->GetTypedComponent(i, k)) - int(b->GetTypedComponent(i, k))));
  return m;
}

}  // namespace

// Skipped without an X display (needs_display.h).
class VtkPass : public rayscope_test::DisplayTest {};

// The window shows, byte for byte, what the image algorithm renders for the
// hand-made description of the renderer's scene.
TEST_F(VtkPass, WindowEqualsImageAlgorithm) {
  RendererScene r;
  vtkSmartPointer<vtkImageData> shown = r.render_and_read();
  EXPECT_EQ(r.pass->GetNumberOfRenderedProps(), 3);

  HandScene h(r);
  ASSERT_EQ(update(h.alg), 1);
  vtkImageData* traced = h.alg->GetOutput();
  EXPECT_EQ(max_byte_difference(shown, traced), 0);
  // Every object is visible, and the image is not background only.
  for (int id = 0; id < 3; ++id) EXPECT_GT(count_object(traced, id), 50) << "object " << id;
  // The last image of the pass is the same image.
  ASSERT_NE(r.pass->GetLastImage(), nullptr);
  EXPECT_EQ(max_byte_difference(r.pass->GetLastImage(), traced), 0);
}

// An image reduction of 3 traces one pixel per 3 x 3 block: the traced image
// is a third of the viewport on each side (rounded up), and each of its pixels
// fills its block of the window; back to 1, every pixel again.
TEST_F(VtkPass, ImageReductionTracesOnePixelPerBlock) {
  RendererScene r;
  r.pass->SetImageReduction(3);
  vtkSmartPointer<vtkImageData> shown = r.render_and_read();
  vtkImageData* traced = r.pass->GetLastImage();
  ASSERT_NE(traced, nullptr);
  int dims[3];
  traced->GetDimensions(dims);
  EXPECT_EQ(dims[0], (kWidth + 2) / 3);
  EXPECT_EQ(dims[1], (kHeight + 2) / 3);
  auto* window = vtkUnsignedCharArray::SafeDownCast(shown->GetPointData()->GetScalars());
  auto* color = vtkUnsignedCharArray::SafeDownCast(traced->GetPointData()->GetScalars());
  ASSERT_NE(window, nullptr);
  ASSERT_NE(color, nullptr);
  const int wc = window->GetNumberOfComponents();
  int mismatches = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c)
        mismatches += window->GetValue((vtkIdType(y) * kWidth + x) * wc + c) !=
                      color->GetValue((vtkIdType(y / 3) * dims[0] + x / 3) * 3 + c);
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(count_object(traced, 0), 5);
  r.pass->SetImageReduction(1);
  r.render_and_read();
  r.pass->GetLastImage()->GetDimensions(dims);
  EXPECT_EQ(dims[0], kWidth);
  EXPECT_EQ(dims[1], kHeight);
}

// The bytes of an image's LinearColor array (the float colors).
std::string linear_bytes(vtkImageData* image) {
  vtkDataArray* a = image ? image->GetPointData()->GetArray("LinearColor") : nullptr;
  if (!a) return {};
  const auto* p = static_cast<const char*>(a->GetVoidPointer(0));
  return std::string(p, p + a->GetNumberOfValues() * a->GetDataTypeSize());
}

// Progressive rendering in a plain VTK window: each render adds a pass of one
// sample per pixel while nothing changes, and after Samples x Samples passes
// the image is the one-render image, bit for bit (its float colors); the
// window shows each pass. A change starts again; FinishProgressive traces all
// the passes an image lacks in one render.
TEST_F(VtkPass, ProgressiveRefinesIntoTheOneRenderImage) {
  RendererScene r;
  vtkRayScopeImageAlgorithm* alg = r.pass->GetImageAlgorithm();
  alg->SetSamples(2);
  r.render_and_read();
  const std::string whole = linear_bytes(r.pass->GetLastImage());
  ASSERT_FALSE(whole.empty());
  EXPECT_EQ(alg->GetImagePasses(), 1);
  EXPECT_EQ(alg->GetImageTotalPasses(), 1);

  alg->ProgressiveOn();
  std::vector<int> passes;
  std::string first;
  for (int i = 0; i < 5; ++i) {
    vtkSmartPointer<vtkImageData> shown = r.render_and_read();
    passes.push_back(alg->GetImagePasses());
    EXPECT_EQ(max_byte_difference(shown, r.pass->GetLastImage()), 0) << "render " << i;
    if (i == 0) first = linear_bytes(r.pass->GetLastImage());
  }
  EXPECT_EQ(passes, (std::vector<int>{1, 2, 3, 4, 4}));
  EXPECT_EQ(alg->GetImageTotalPasses(), 4);
  EXPECT_NE(first, whole);
  EXPECT_EQ(linear_bytes(r.pass->GetLastImage()), whole);
  vtkDataArray* field = r.pass->GetLastImage()->GetFieldData()->GetArray("ProgressivePasses");
  ASSERT_NE(field, nullptr);
  EXPECT_EQ(field->GetComponent(0, 0), 4);
  EXPECT_EQ(field->GetComponent(0, 1), 4);

  // A property changed: the next render starts again.
  r.floor_actor->GetProperty()->SetColor(0.3, 0.6, 0.9);
  r.render_and_read();
  EXPECT_EQ(alg->GetImagePasses(), 1);
  // The camera moved, and FinishProgressive: all four passes in one render,
  // the one-render image of the new camera.
  r.renderer->GetActiveCamera()->Azimuth(20.0);
  r.pass->FinishProgressiveOn();
  r.render_and_read();
  EXPECT_EQ(alg->GetImagePasses(), 4);
  const std::string finished = linear_bytes(r.pass->GetLastImage());
  alg->ProgressiveOff();
  r.render_and_read();
  EXPECT_EQ(linear_bytes(r.pass->GetLastImage()), finished);
  EXPECT_NE(finished, whole);
}

// Moving the camera, changing a property and hiding an actor between renders
// give the image of the changed scene (the pass keeps its scene between renders
// and must notice every change).
TEST_F(VtkPass, FollowsChanges) {
  RendererScene r;
  r.render_and_read();
  HandScene h(r);

  r.renderer->GetActiveCamera()->Azimuth(25.0);
  r.renderer->GetActiveCamera()->OrthogonalizeViewUp();
  r.floor_actor->GetProperty()->SetColor(0.3, 0.6, 0.9);
  vtkSmartPointer<vtkImageData> shown = r.render_and_read();
  h.alg->CopyCamera(r.renderer->GetActiveCamera());
  h.floor_material->SetColor(0.3, 0.6, 0.9);
  ASSERT_EQ(update(h.alg), 1);
  EXPECT_EQ(max_byte_difference(shown, h.alg->GetOutput()), 0);

  r.glass_actor->VisibilityOff();
  shown = r.render_and_read();
  EXPECT_EQ(r.pass->GetNumberOfRenderedProps(), 2);
  h.alg->RemoveInputConnection(0, 2);
  ASSERT_EQ(update(h.alg), 1);
  EXPECT_EQ(count_object(h.alg->GetOutput(), 2), 0);
  EXPECT_EQ(max_byte_difference(shown, h.alg->GetOutput()), 0);
}

// A parallel camera, the renderer's automatic headlight and a camera light.
TEST_F(VtkPass, ParallelCameraHeadlightAndCameraLight) {
  RendererScene r;
  r.renderer->RemoveAllLights();
  vtkNew<vtkLight> head, cam;
  head->SetLightTypeToHeadlight();
  head->SetIntensity(0.7);
  cam->SetLightTypeToCameraLight();
  cam->SetPosition(1.0, 1.0, 1.0);  // camera coordinates: up-right of the camera
  cam->SetFocalPoint(0.0, 0.0, 0.0);
  cam->SetIntensity(0.4);
  r.renderer->AddLight(head);
  r.renderer->AddLight(cam);
  vtkCamera* c = r.renderer->GetActiveCamera();
  c->ParallelProjectionOn();
  c->SetParallelScale(1.3);
  vtkSmartPointer<vtkImageData> shown = r.render_and_read();

  HandScene h(r);
  h.alg->RemoveAllLights();
  h.alg->CopyCamera(c);
  // The renderer's headlight is the algorithm's: along the view, no shadow.
  h.alg->SetHeadlight(1);
  h.alg->SetHeadlightIntensity(0.7);
  // The camera light, in world coordinates: where vtkLight puts it.
  double p[3], f[3];
  cam->GetTransformedPosition(p);
  cam->GetTransformedFocalPoint(f);
  h.alg->AddDirectionalLight(f[0] - p[0], f[1] - p[1], f[2] - p[2], 1, 1, 1, 0.4);
  ASSERT_EQ(update(h.alg), 1);
  EXPECT_EQ(max_byte_difference(shown, h.alg->GetOutput()), 0);

  // Without any light, the renderer gets VTK's automatic headlight.
  vtkNew<vtkRenderer> bare;
  bare->AddActor(r.ball_actor);
  bare->SetActiveCamera(c);
  vtkNew<vtkRayScopeImageAlgorithm> copy;
  EXPECT_EQ(copy->CopyRenderer(bare), 1);
  EXPECT_EQ(copy->GetNumberOfLights(), 1);
  EXPECT_FALSE(copy->GetHeadlight());
}

// Statistics and the cost display: the traced image carries the cost arrays,
// the window shows the heat map instead of the colors.
TEST_F(VtkPass, StatisticsAndCostDisplay) {
  RendererScene r;
  r.pass->GetImageAlgorithm()->ComputeCostOn();
  vtkSmartPointer<vtkImageData> colors = r.render_and_read();
  vtkImageData* last = r.pass->GetLastImage();
  ASSERT_NE(last, nullptr);
  ASSERT_NE(last->GetPointData()->GetArray("Cost"), nullptr);
  ASSERT_NE(last->GetFieldData()->GetArray("RayCounts"), nullptr);
  EXPECT_GT(last->GetFieldData()->GetArray("NodesVisited")->GetComponent(0, 0), 0.0);
  EXPECT_EQ(max_byte_difference(colors, last), 0);

  r.pass->SetDisplayModeToCost();
  vtkSmartPointer<vtkImageData> heat = r.render_and_read();
  EXPECT_GT(max_byte_difference(heat, r.pass->GetLastImage()), 50);
}

// The pass has no render settings of its own: it renders with its image
// algorithm's, which CopyRenderer() leaves alone. Cost starts off; the cost
// display switches it on.
TEST_F(VtkPass, RendersWithTheImageAlgorithmSettings) {
  RendererScene r;
  vtkRayScopeImageAlgorithm* alg = r.pass->GetImageAlgorithm();
  EXPECT_FALSE(alg->GetComputeCost());
  alg->SetSamples(2);
  alg->SetMaxDepth(1);
  alg->SetMinContribution(0.5);
  alg->ShadowsOff();
  alg->SetThreads(2);
  vtkSmartPointer<vtkImageData> shown = r.render_and_read();
  EXPECT_EQ(alg->GetSamples(), 2);
  EXPECT_EQ(alg->GetMaxDepth(), 1);
  EXPECT_EQ(alg->GetMinContribution(), 0.5);
  EXPECT_FALSE(alg->GetShadows());
  EXPECT_EQ(r.pass->GetLastImage()->GetPointData()->GetArray("Cost"), nullptr);

  HandScene h(r);
  h.alg->SetSamples(2);
  h.alg->SetMaxDepth(1);
  h.alg->SetMinContribution(0.5);
  h.alg->ShadowsOff();
  ASSERT_EQ(update(h.alg), 1);
  EXPECT_EQ(max_byte_difference(shown, h.alg->GetOutput()), 0);
  HandScene defaults(r);
  ASSERT_EQ(update(defaults.alg), 1);
  EXPECT_GT(max_byte_difference(shown, defaults.alg->GetOutput()), 10);

  r.pass->SetDisplayModeToCost();
  EXPECT_TRUE(alg->GetComputeCost());
  r.render_and_read();
  EXPECT_NE(r.pass->GetLastImage()->GetPointData()->GetArray("Cost"), nullptr);
}

// Bad settings: one error from the algorithm, no crash, the background shows.
TEST_F(VtkPass, BadSettingsReportAnError) {
  RendererScene r;
  vtkNew<ErrorCatcher> errors;
  r.pass->GetImageAlgorithm()->AddObserver(vtkCommand::ErrorEvent, errors);
  r.pass->AddObserver(vtkCommand::ErrorEvent, errors);
  r.pass->GetImageAlgorithm()->SetSamples(0);
  vtkSmartPointer<vtkImageData> shown = r.render_and_read();
  EXPECT_GE(errors->count, 1);
  EXPECT_NE(errors->last.find("ray tracing failed"), std::string::npos) << errors->last;
  EXPECT_EQ(r.pass->GetLastImage(), nullptr);
  auto* px = vtkUnsignedCharArray::SafeDownCast(shown->GetPointData()->GetScalars());
  // Background 0.1, 0.2, 0.3 -> bytes 26, 51, 77 (VTK clears in display values).
  EXPECT_NEAR(px->GetTypedComponent(0, 0), 26, 1);
  EXPECT_NEAR(px->GetTypedComponent(0, 2), 77, 1);
}

// The pass draws into its own viewport only: an OpenGL renderer beside it in
// the same window keeps its image, and the pass's half is the traced image.
TEST_F(VtkPass, DrawsIntoItsViewportOnly) {
  RendererScene r;
  r.window->SetSize(2 * kWidth, kHeight);
  r.renderer->SetViewport(0.5, 0.0, 1.0, 1.0);
  vtkNew<vtkRenderer> opengl;
  opengl->SetViewport(0.0, 0.0, 0.5, 1.0);
  opengl->AddActor(r.ball_actor);
  opengl->SetActiveCamera(r.renderer->GetActiveCamera());
  opengl->SetBackground(0.0, 0.0, 0.0);
  // OpenGL first, so that a pass clearing more than its viewport would erase it.
  r.window->RemoveRenderer(r.renderer);
  r.window->AddRenderer(opengl);
  r.window->AddRenderer(r.renderer);
  r.window->Render();  // the second frame starts with the first one's GL state
  vtkSmartPointer<vtkImageData> shown = r.render_and_read();

  HandScene h(r);
  ASSERT_EQ(update(h.alg), 1);
  auto* px = vtkUnsignedCharArray::SafeDownCast(shown->GetPointData()->GetScalars());
  auto* traced =
      vtkUnsignedCharArray::SafeDownCast(h.alg->GetOutput()->GetPointData()->GetScalars());
  int max_diff = 0, left_lit = 0, left_cleared = 0;
  for (int j = 0; j < kHeight; ++j)
    for (int i = 0; i < kWidth; ++i) {
      const vtkIdType left = vtkIdType(j) * 2 * kWidth + i, right = left + kWidth;
      for (int k = 0; k < 3; ++k)
        max_diff = std::max(max_diff,
                            std::abs(int(px->GetTypedComponent(right, k)) -
                                     int(traced->GetTypedComponent(vtkIdType(j) * kWidth + i, k))));
      const int r0 = px->GetTypedComponent(left, 0), g0 = px->GetTypedComponent(left, 1),
                b0 = px->GetTypedComponent(left, 2);
      left_lit += r0 + g0 + b0 > 0;
      // The pass's background (0.1, 0.2, 0.3) must not show on the left.
      left_cleared += std::abs(r0 - 26) <= 1 && std::abs(g0 - 51) <= 1 && std::abs(b0 - 77) <= 1;
    }
  EXPECT_EQ(max_diff, 0);
  // The OpenGL ball covers a few thousand pixels of the black left half.
  EXPECT_GT(left_lit, 1000);
  EXPECT_EQ(left_cleared, 0);
}

// A multiblock drawn by vtkCompositePolyDataMapper2 (what VTK and ParaView use
// for composite data): one image of both blocks, the sphere's shadow on the
// floor, the same pixels as the image algorithm given the multiblock, and the
// mapper's block visibility and colors.
TEST_F(VtkPass, CompositeMapperBlocksAreOneScene) {
  RendererScene r;
  r.renderer->RemoveAllViewProps();
  r.floor->Update();
  r.ball->Update();
  vtkNew<vtkMultiBlockDataSet> blocks;
  blocks->SetBlock(0, r.floor->GetOutput());
  blocks->SetBlock(1, r.ball->GetOutput());
  vtkNew<vtkCompositePolyDataMapper2> mapper;
  mapper->SetInputDataObject(blocks);
  vtkNew<vtkCompositeDataDisplayAttributes> attributes;
  mapper->SetCompositeDataDisplayAttributes(attributes);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  r.renderer->AddActor(actor);

  vtkSmartPointer<vtkImageData> shown = r.render_and_read();
  EXPECT_EQ(r.pass->GetNumberOfRenderedProps(), 1);
  vtkImageData* last = r.pass->GetLastImage();
  ASSERT_NE(last, nullptr);
  EXPECT_GT(count_object(last, 0), 50);
  EXPECT_GT(count_object(last, 1), 50);

  HandScene h(r);
  h.alg->RemoveAllInputConnections(0);
  h.alg->SetInputData(blocks);
  h.alg->SetInputMaterial(0, nullptr);
  h.alg->SetInputMaterial(1, nullptr);
  h.alg->SetInputMaterial(2, nullptr);
  ASSERT_EQ(update(h.alg), 1);
  EXPECT_EQ(max_byte_difference(shown, h.alg->GetOutput()), 0);

  // The sphere's block hidden, the floor's block red.
  attributes->SetBlockVisibility(r.ball->GetOutput(), false);
  const double red[3] = {1.0, 0.0, 0.0};
  attributes->SetBlockColor(r.floor->GetOutput(), red);
  mapper->Modified();
  r.render_and_read();
  last = r.pass->GetLastImage();
  ASSERT_NE(last, nullptr);
  EXPECT_EQ(count_object(last, 1), 0);
  auto* color = vtkUnsignedCharArray::SafeDownCast(last->GetPointData()->GetArray("Color"));
  auto* ids = vtkIntArray::SafeDownCast(last->GetPointData()->GetArray("ObjectId"));
  int floor = 0, red_floor = 0;
  for (vtkIdType i = 0; i < ids->GetNumberOfTuples(); ++i)
    if (ids->GetValue(i) == 0) {
      ++floor;
      red_floor += color->GetTypedComponent(i, 0) > 0 && color->GetTypedComponent(i, 1) == 0;
    }
  EXPECT_GT(red_floor, floor / 2);
}

// A volume in the renderer is not drawn, and says so once.
TEST_F(VtkPass, VolumeGivesOneWarning) {
  RendererScene r;
  vtkNew<vtkImageData> grid;
  grid->SetDimensions(4, 4, 4);
  grid->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  vtkNew<vtkSmartVolumeMapper> vmapper;
  vmapper->SetInputData(grid);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(vmapper);
  r.renderer->AddVolume(volume);
  vtkNew<ErrorCatcher> warnings;
  r.pass->GetImageAlgorithm()->AddObserver(vtkCommand::WarningEvent, warnings);
  r.render_and_read();
  r.render_and_read();
  EXPECT_EQ(warnings->count, 1);
  EXPECT_NE(warnings->last.find("vtkVolume"), std::string::npos) << warnings->last;
  EXPECT_EQ(r.pass->GetNumberOfRenderedProps(), 3);
}
