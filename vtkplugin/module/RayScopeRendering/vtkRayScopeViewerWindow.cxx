// vtkRayScopeViewer's window: its viewports, the scene and the camera drawn
// in 3D, the legend, and the interactor style that turns clicks and keys
// into the viewer's picks and keys.
#include "vtkRayScopeViewerInternals.h"

using namespace rayscope_vtk::viewer;

namespace {

vtkSmartPointer<vtkThreshold> make_threshold(vtkAlgorithmOutput* input, const char* array) {
  auto t = vtkSmartPointer<vtkThreshold>::New();
  t->SetInputConnection(input);
  t->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, array);
  t->SetThresholdFunction(vtkThreshold::THRESHOLD_BETWEEN);
  t->SetLowerThreshold(-VTK_DOUBLE_MAX);
  t->SetUpperThreshold(VTK_DOUBLE_MAX);
  return t;
}

vtkSmartPointer<vtkLookupTable> make_table(int n, const double (*colors)[3]) {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetNumberOfTableValues(n);
  lut->SetTableRange(0, n - 1);
  for (int i = 0; i < n; ++i) lut->SetTableValue(i, colors[i][0], colors[i][1], colors[i][2], 1.0);
  lut->Build();
  return lut;
}

// A short horizontal line: the symbol of a legend entry.
vtkSmartPointer<vtkPolyData> legend_symbol() {
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0, 0, 0);
  pts->InsertNextPoint(1, 0, 0);
  vtkNew<vtkCellArray> lines;
  vtkIdType ids[2] = {0, 1};
  lines->InsertNextCell(2, ids);
  pd->SetPoints(pts);
  pd->SetLines(lines);
  return pd;
}

void srgb(const rayscope::Color& linear, double out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = rayscope::linear_to_srgb(std::clamp(linear[k], 0.0f, 1.0f));
}

}  // namespace

// The window's interaction: clicks pick, keys go to the viewer, dragging in
// the 3D view orbits (vtkInteractorStyleTrackballCamera).
class vtkRayScopeViewerStyle : public vtkInteractorStyleTrackballCamera {
 public:
  static vtkRayScopeViewerStyle* New();
  vtkTypeMacro(vtkRayScopeViewerStyle, vtkInteractorStyleTrackballCamera);
  vtkRayScopeViewer* Viewer = nullptr;

  void OnLeftButtonDown() override {
    const int* p = this->Interactor->GetEventPosition();
    this->Press[0] = p[0];
    this->Press[1] = p[1];
    if (this->Viewer->GetImageRenderer()->IsInViewport(p[0], p[1])) {
      this->Viewer->PickAtDisplay(p[0], p[1]);
      return;
    }
    this->Superclass::OnLeftButtonDown();
  }
  void OnLeftButtonUp() override {
    this->Superclass::OnLeftButtonUp();
    const int* p = this->Interactor->GetEventPosition();
    if (std::abs(p[0] - this->Press[0]) <= kClickSlop &&
        std::abs(p[1] - this->Press[1]) <= kClickSlop &&
        this->Viewer->GetSceneRenderer()->IsInViewport(p[0], p[1]))
      this->Viewer->PickAtDisplay(p[0], p[1]);
  }
  void OnKeyPress() override {
    const char* key = this->Interactor->GetKeySym();
    if (key && this->Viewer->HandleKey(key)) return;
    this->Superclass::OnKeyPress();
  }
  // VTK's own character keys (wireframe, reset, stereo, fly, pick) would fight
  // the viewer's; only quitting is kept.
  void OnChar() override {
    const char c = this->Interactor->GetKeyCode();
    if (c == 'q' || c == 'e') this->Superclass::OnChar();
  }

 private:
  int Press[2] = {-1000, -1000};
};
vtkStandardNewMacro(vtkRayScopeViewerStyle);

// --- Building the window ------------------------------------------------------

void vtkRayScopeViewer::Internals::Build() {
  vtkRayScopeViewer* self = this->Self;
  this->Window->SetSize(self->WindowSize);
  this->Window->SetWindowName("rayscope view");
  this->Window->SetMultiSamples(0);
  this->HeaderRen->SetViewport(0.0, kHeaderBottom, 1.0, 1.0);
  this->ImageRen->SetViewport(0.0, kPanelTop, 0.5, kHeaderBottom);
  this->SceneRen->SetViewport(0.5, kPanelTop, 1.0, kHeaderBottom);
  this->PanelRen->SetViewport(0.0, 0.0, 1.0, kPanelTop);
  this->ImageRen->SetBackground(0.08, 0.08, 0.08);
  this->SceneRen->SetBackground(0.15, 0.16, 0.2);
  // The 3D view blends its half-transparent surfaces in the order they are
  // drawn (vtkRenderStepsPass: VTK's plain opaque, translucent and overlay
  // steps). Without a pass, VTK 9.1 draws translucent geometry with
  // order-independent transparency (vtkOrderIndependentTranslucentPass: float
  // render targets and a full-viewport blend): under software OpenGL (Mesa's
  // llvmpipe) the window then took 72 ms to draw on the bunny scene instead
  // of 35, for a 3D view that differs from this one by 0.3 of 255 on average
  // (docs/performance.md, bench_viewer).
  this->SceneRen->SetPass(vtkSmartPointer<vtkRenderStepsPass>::New());
  this->PanelRen->SetBackground(0.05, 0.05, 0.05);
  this->HeaderRen->SetBackground(0.0, 0.0, 0.0);
  for (vtkRenderer* r :
       {this->HeaderRen.Get(), this->ImageRen.Get(), this->SceneRen.Get(), this->PanelRen.Get()})
    this->Window->AddRenderer(r);
  this->Interactor->SetRenderWindow(this->Window);
  this->Style = vtkSmartPointer<vtkRayScopeViewerStyle>::New();
  this->Style->Viewer = self;
  this->Style->SetDefaultRenderer(this->SceneRen);
  this->Interactor->SetInteractorStyle(this->Style);

  // Image viewport.
  this->ImageActor->GetMapper()->SetInputData(this->Display);
  this->ImageActor->InterpolateOff();
  this->ImageRen->AddActor(this->ImageActor);
  vtkNew<vtkPolyDataMapper> marker_mapper;
  marker_mapper->SetInputData(this->Marker);
  this->MarkerActor->SetMapper(marker_mapper);
  this->MarkerActor->GetProperty()->SetColor(kPickColor[0], kPickColor[1], kPickColor[2]);
  this->MarkerActor->GetProperty()->SetLineWidth(2.0);
  this->MarkerActor->VisibilityOff();
  this->ImageRen->AddActor(this->MarkerActor);
  this->ImageRen->GetActiveCamera()->ParallelProjectionOn();
  this->ScaleBar->SetLookupTable(this->ScaleTable);
  this->ScaleBar->SetOrientationToHorizontal();
  this->ScaleBar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->ScaleBar->GetPositionCoordinate()->SetValue(0.1, 0.01);
  this->ScaleBar->SetWidth(0.8);
  this->ScaleBar->SetHeight(0.12);
  this->ScaleBar->SetNumberOfLabels(5);
  this->ScaleBar->VisibilityOff();
  this->ImageRen->AddActor2D(this->ScaleBar);

  // Ray tree: filtered by depth, ray and kind; traced rays in their kind's
  // color with hit points and normals, skipped rays gray.
  this->Tree->SetSceneSource(this->Algorithm);
  // KindName (strings) is left out: VTK 9.1's threshold and geometry filters
  // drop its values, and Kind says the same.
  this->NoStrings->SetInputConnection(this->Tree->GetOutputPort());
  this->NoStrings->RemoveArraysOn();
  this->NoStrings->AddCellDataArray("KindName");
  this->ByDepth = make_threshold(this->NoStrings->GetOutputPort(), "Depth");
  this->ByRay = make_threshold(this->ByDepth->GetOutputPort(), "RayId");
  this->ByKind = make_threshold(this->ByRay->GetOutputPort(), "Kind");
  this->Shown->SetInputConnection(this->ByKind->GetOutputPort());
  this->Traced = make_threshold(this->Shown->GetOutputPort(), "Skipped");
  this->Traced->SetLowerThreshold(0);
  this->Traced->SetUpperThreshold(0);
  this->Skipped = make_threshold(this->Shown->GetOutputPort(), "Skipped");
  this->Skipped->SetLowerThreshold(1);
  vtkNew<vtkDataSetMapper> traced_mapper;
  traced_mapper->SetInputConnection(this->Traced->GetOutputPort());
  traced_mapper->SetLookupTable(make_table(4, kKindColors));
  traced_mapper->SetScalarModeToUseCellFieldData();
  traced_mapper->SelectColorArray("Kind");
  traced_mapper->SetScalarRange(0, 3);
  this->TracedActor->SetMapper(traced_mapper);
  this->TracedActor->GetProperty()->SetLineWidth(2.5);
  this->TracedActor->GetProperty()->SetPointSize(9.0);
  this->TracedActor->GetProperty()->RenderPointsAsSpheresOn();
  // Unlit: the tree's point normals are those of hit points, 0 at other ends.
  this->TracedActor->GetProperty()->LightingOff();
  vtkNew<vtkDataSetMapper> skipped_mapper;
  skipped_mapper->SetInputConnection(this->Skipped->GetOutputPort());
  skipped_mapper->ScalarVisibilityOff();
  this->SkippedActor->SetMapper(skipped_mapper);
  this->SkippedActor->GetProperty()->SetColor(kSkippedColor[0], kSkippedColor[1], kSkippedColor[2]);
  this->SkippedActor->GetProperty()->SetLineWidth(1.5);
  this->SkippedActor->GetProperty()->LightingOff();
  this->Normals->SetInputConnection(this->Traced->GetOutputPort());
  this->Normals->SetVectorModeToUseNormal();
  vtkNew<vtkPolyDataMapper> normal_mapper;
  normal_mapper->SetInputConnection(this->Normals->GetOutputPort());
  normal_mapper->ScalarVisibilityOff();
  this->NormalActor->SetMapper(normal_mapper);
  this->NormalActor->GetProperty()->SetColor(kNormalColor[0], kNormalColor[1], kNormalColor[2]);
  this->NormalActor->GetProperty()->SetLineWidth(2.0);
  this->NormalActor->GetProperty()->LightingOff();
  // The selected ray, drawn over the others.
  this->Selected = make_threshold(this->Shown->GetOutputPort(), "RayId");
  vtkNew<vtkDataSetMapper> selected_mapper;
  selected_mapper->SetInputConnection(this->Selected->GetOutputPort());
  selected_mapper->ScalarVisibilityOff();
  this->SelectedActor->SetMapper(selected_mapper);
  this->SelectedActor->GetProperty()->SetColor(kSelectedColor[0], kSelectedColor[1],
                                               kSelectedColor[2]);
  this->SelectedActor->GetProperty()->SetLineWidth(6.0);
  this->SelectedActor->GetProperty()->SetPointSize(12.0);
  this->SelectedActor->GetProperty()->RenderPointsAsSpheresOn();
  this->SelectedActor->GetProperty()->LightingOff();
  for (vtkActor* a : {this->TracedActor.Get(), this->SkippedActor.Get(), this->NormalActor.Get(),
                      this->SelectedActor.Get()}) {
    a->VisibilityOff();
    a->PickableOff();
    this->SceneRen->AddActor(a);
  }
  // Occluders of shadow rays.
  vtkNew<vtkPolyDataMapper> occluder_mapper;
  occluder_mapper->SetInputData(this->Occluders);
  occluder_mapper->ScalarVisibilityOff();
  this->OccluderActor->SetMapper(occluder_mapper);
  this->OccluderActor->GetProperty()->SetColor(kOccluderColor[0], kOccluderColor[1],
                                               kOccluderColor[2]);
  this->OccluderActor->GetProperty()->SetPointSize(13.0);
  this->OccluderActor->GetProperty()->RenderPointsAsSpheresOn();
  this->OccluderActor->GetProperty()->LightingOff();
  this->OccluderActor->PickableOff();
  this->OccluderActor->VisibilityOff();
  this->SceneRen->AddActor(this->OccluderActor);
  // Labels on demand: "#id dDEPTH wWEIGHT" at the middle of each shown ray
  // (the mapper's "field data" mode reads the named point-data array).
  vtkNew<vtkLabeledDataMapper> label_mapper;
  label_mapper->SetInputData(this->Labels);
  label_mapper->SetLabelModeToLabelFieldData();
  label_mapper->SetFieldDataName("Label");
  label_mapper->GetLabelTextProperty()->SetFontSize(12);
  label_mapper->GetLabelTextProperty()->SetColor(1.0, 1.0, 1.0);
  label_mapper->GetLabelTextProperty()->ShadowOn();
  this->LabelActor->SetMapper(label_mapper);
  this->LabelActor->VisibilityOff();
  this->SceneRen->AddActor2D(this->LabelActor);

  // BVH boxes: by level, or a played walk by state.
  this->BVH->SetSceneSource(this->Algorithm);
  this->LevelTable = vtkSmartPointer<vtkLookupTable>::New();
  this->LevelTable->SetHueRange(0.66, 0.0);
  this->LevelTable->Build();
  this->WalkTable = make_table(6, kWalkColors);
  this->BVHMapper->SetInputData(this->NoBoxes);
  this->BVHMapper->SetScalarModeToUseCellFieldData();
  this->BVHActor->SetMapper(this->BVHMapper);
  this->BVHActor->GetProperty()->SetLineWidth(1.5);
  this->BVHActor->GetProperty()->LightingOff();
  this->BVHActor->PickableOff();
  this->SceneRen->AddActor(this->BVHActor);

  // The camera, its image plane, the pixel grid and the picked pixel.
  vtkNew<vtkPolyDataMapper> camera_mapper;
  camera_mapper->SetInputData(this->CameraGeometry);
  this->CameraActor->SetMapper(camera_mapper);
  this->CameraActor->GetProperty()->SetColor(0.85, 0.85, 0.85);
  this->CameraActor->GetProperty()->LightingOff();
  this->CameraActor->PickableOff();
  this->SceneRen->AddActor(this->CameraActor);
  vtkNew<vtkPolyDataMapper> cell_mapper;
  cell_mapper->SetInputData(this->PickedCell);
  this->PickedCellActor->SetMapper(cell_mapper);
  this->PickedCellActor->GetProperty()->SetColor(kPickColor[0], kPickColor[1], kPickColor[2]);
  this->PickedCellActor->PickableOff();
  this->SceneRen->AddActor(this->PickedCellActor);

  // Text: help and message lines on top, the inspect text below.
  this->HelpActor->SetInput(kHelp);
  this->HelpActor->GetTextProperty()->SetFontSize(13);
  this->HelpActor->GetTextProperty()->SetColor(0.8, 0.8, 0.8);
  this->HelpActor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->HelpActor->GetPositionCoordinate()->SetValue(0.005, 0.52);
  this->HeaderRen->AddActor2D(this->HelpActor);
  this->MessageActor->GetTextProperty()->SetFontSize(13);
  this->MessageActor->GetTextProperty()->SetColor(1.0, 0.85, 0.3);
  this->MessageActor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->MessageActor->GetPositionCoordinate()->SetValue(0.005, 0.06);
  this->HeaderRen->AddActor2D(this->MessageActor);
  // The panel: a text actor per line, from the top left corner down, a line
  // height apart (FreeType's own spacing of the lines of one text: drawn
  // so, the panel is pixel for pixel the text drawn by one actor).
  vtkNew<vtkTextProperty> panel_text;
  panel_text->SetFontFamilyToCourier();
  panel_text->SetFontSize(12);
  panel_text->SetVerticalJustificationToTop();
  int one[4], two[4];
  vtkTextRenderer* text = vtkTextRenderer::GetInstance();
  this->PanelLineHeight =
      text && text->GetBoundingBox(panel_text, vtkStdString("Xg"), one, this->Window->GetDPI()) &&
              text->GetBoundingBox(panel_text, vtkStdString("Xg\nXg"), two, this->Window->GetDPI())
          ? (two[3] - two[2]) - (one[3] - one[2])
          : 14;
  vtkNew<vtkCoordinate> panel_corner;
  panel_corner->SetCoordinateSystemToNormalizedViewport();
  panel_corner->SetValue(0.005, 0.98);
  for (int k = 0; k < kPanelLines; ++k) {
    auto line = vtkSmartPointer<vtkTextActor>::New();
    line->GetTextProperty()->ShallowCopy(panel_text);
    line->GetPositionCoordinate()->SetCoordinateSystemToViewport();
    line->GetPositionCoordinate()->SetReferenceCoordinate(panel_corner);
    this->PanelRen->AddActor2D(line);
    this->PanelLines.push_back(line);
  }
  this->PanelLineText.assign(size_t(kPanelLines), std::string());
  this->ShowPanelLines({"click a pixel of the image (left) or a surface (right)"});
  this->Legend->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->Legend->GetPositionCoordinate()->SetValue(0.0, 0.0);
  this->Legend->GetPosition2Coordinate()->SetValue(0.2, 0.3);
  this->Legend->UseBackgroundOn();
  this->Legend->SetBackgroundColor(0.0, 0.0, 0.0);
  this->SceneRen->AddActor2D(this->Legend);
  this->UpdateLegend();

  this->Picker->PickFromListOn();
  this->Picker->SetTolerance(0.0005);
  this->BuildSceneGeometry();
  this->Initialized = true;
}

// The core scene's objects, drawn by VTK: meshes, spheres, planes (sized to
// the rest of the scene) and point lights, in their material colors, half
// transparent so that rays inside them stay visible.
void vtkRayScopeViewer::Internals::BuildSceneGeometry() {
  for (vtkActor* a : this->GeometryActors) this->SceneRen->RemoveActor(a);
  this->GeometryActors.clear();
  this->Picker->InitializePickList();
  const rayscope::Scene& s = *this->scene();
  rayscope::Bounds3 b = s.bvh().bounds();
  b.extend(s.camera.look_at);
  const double size = std::max(1e-3, double(glm::length(b.extent())));
  auto add = [&](vtkPolyData* pd, vtkAlgorithmOutput* port, uint32_t material, bool pickable) {
    vtkNew<vtkPolyDataMapper> mapper;
    if (pd)
      mapper->SetInputData(pd);
    else
      mapper->SetInputConnection(port);
    mapper->ScalarVisibilityOff();
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    double c[3] = {1.0, 0.9, 0.4};
    if (material < s.materials.size()) srgb(s.materials[material].color, c);
    actor->GetProperty()->SetColor(c);
    actor->GetProperty()->SetOpacity(pickable ? 0.45 : 1.0);
    this->SceneRen->AddActor(actor);
    if (pickable) this->Picker->AddPickList(actor);
    this->GeometryActors.push_back(actor);
  };
  for (const rayscope::TriangleMesh& m : s.meshes) {
    vtkNew<vtkPolyData> pd;
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    for (const rayscope::Vec3& p : m.positions) {
      const rayscope::DVec3 w = s.to_world(p);
      pts->InsertNextPoint(w.x, w.y, w.z);
    }
    vtkNew<vtkCellArray> tris;
    for (const glm::uvec3& t : m.triangles) {
      const vtkIdType ids[3] = {vtkIdType(t.x), vtkIdType(t.y), vtkIdType(t.z)};
      tris->InsertNextCell(3, ids);
    }
    pd->SetPoints(pts);
    pd->SetPolys(tris);
    add(pd, nullptr, m.material, true);
  }
  for (const rayscope::Sphere& sp : s.spheres) {
    vtkNew<vtkSphereSource> src;
    const rayscope::DVec3 c = s.to_world(sp.center);
    src->SetCenter(c.x, c.y, c.z);
    src->SetRadius(sp.radius);
    src->SetThetaResolution(48);
    src->SetPhiResolution(32);
    src->Update();
    add(src->GetOutput(), nullptr, sp.material, true);
  }
  for (const rayscope::Plane& pl : s.planes) {
    // A square of the scene's size around the point of the plane nearest to
    // the scene's center.
    const rayscope::Vec3 n = glm::normalize(pl.normal);
    const rayscope::Vec3 c = b.center() - glm::dot(b.center() - pl.point, n) * n;
    const rayscope::Vec3 t0 = glm::normalize(
        glm::cross(n, std::abs(n.x) < 0.9f ? rayscope::Vec3(1, 0, 0) : rayscope::Vec3(0, 1, 0)));
    const rayscope::Vec3 t1 = glm::cross(n, t0);
    const float h = float(size);
    vtkNew<vtkPlaneSource> src;
    const rayscope::DVec3 o = s.to_world(c - h * t0 - h * t1), p1 = s.to_world(c + h * t0 - h * t1),
                          p2 = s.to_world(c - h * t0 + h * t1);
    src->SetOrigin(o.x, o.y, o.z);
    src->SetPoint1(p1.x, p1.y, p1.z);
    src->SetPoint2(p2.x, p2.y, p2.z);
    src->SetResolution(16, 16);
    src->Update();
    add(src->GetOutput(), nullptr, pl.material, true);
  }
  for (const rayscope::Light& l : s.lights) {
    vtkNew<vtkSphereSource> src;
    src->SetRadius(kLightFraction * size);
    if (l.type == rayscope::Light::Type::Point) {
      const rayscope::DVec3 c = s.to_world(l.position);
      src->SetCenter(c.x, c.y, c.z);
      src->Update();
      add(src->GetOutput(), nullptr, ~0u, false);
      continue;
    }
    // A directional light: a sphere outside the scene where its light comes
    // from, and a line along the way it travels.
    const rayscope::Vec3 d = glm::normalize(l.direction);
    const rayscope::DVec3 from = s.to_world(b.center() - float(size) * d),
                          to = s.to_world(b.center() - float(0.6 * size) * d);
    src->SetCenter(from.x, from.y, from.z);
    src->Update();
    add(src->GetOutput(), nullptr, ~0u, false);
    vtkNew<vtkPolyData> ray;
    vtkNew<vtkPoints> pts;
    pts->InsertNextPoint(from.x, from.y, from.z);
    pts->InsertNextPoint(to.x, to.y, to.z);
    vtkNew<vtkCellArray> line;
    const vtkIdType ids[2] = {0, 1};
    line->InsertNextCell(2, ids);
    ray->SetPoints(pts);
    ray->SetLines(line);
    add(ray, nullptr, ~0u, false);
  }
  this->Normals->SetScaleFactor(kNormalFraction * size);
  this->Changed |= kSceneView;
}

// The camera as the lecture draws it: frustum edges from the eye to the image
// plane (put at a fraction of the way to look_at so that it is in view), the
// plane's outline, the pixel grid around the picked pixel and that pixel.
void vtkRayScopeViewer::Internals::UpdateCameraGeometry() {
  const rayscope::Scene& s = *this->scene();
  const rayscope::Camera& cam = s.camera;
  const rayscope::RenderSettings& rs = this->Settings;
  const float plane = float(kImagePlaneFraction) * glm::length(cam.look_at - cam.eye);
  auto on_plane = [&](float px, float py) {
    const rayscope::Ray r = cam.generate_ray(px, py);
    const float t =
        (plane - glm::dot(r.origin - cam.eye, cam.forward())) / glm::dot(r.dir, cam.forward());
    return r.origin + t * r.dir;
  };
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  auto point = [&](const rayscope::Vec3& p) {
    const rayscope::DVec3 w = s.to_world(p);
    return pts->InsertNextPoint(w.x, w.y, w.z);
  };
  auto line = [&](const rayscope::Vec3& a, const rayscope::Vec3& b) {
    const vtkIdType ids[2] = {point(a), point(b)};
    lines->InsertNextCell(2, ids);
  };
  const float w = float(rs.width), h = float(rs.height);
  const std::array<std::array<float, 2>, 4> corners = {
      {{0.0f, 0.0f}, {w, 0.0f}, {w, h}, {0.0f, h}}};
  for (size_t k = 0; k < 4; ++k) {
    const auto [px, py] = corners[k];
    line(cam.generate_ray(px, py).origin, on_plane(px, py));
    line(on_plane(px, py), on_plane(corners[(k + 1) % 4][0], corners[(k + 1) % 4][1]));
  }
  vtkNew<vtkCellArray> quad;
  if (this->Self->PickedPixel[0] >= 0) {
    const int x = this->Self->PickedPixel[0], y = rs.height - 1 - this->Self->PickedPixel[1];
    const int x0 = std::max(0, x - kGridRadius), x1 = std::min(rs.width, x + kGridRadius + 1);
    const int y0 = std::max(0, y - kGridRadius), y1 = std::min(rs.height, y + kGridRadius + 1);
    for (int gx = x0; gx <= x1; ++gx)
      line(on_plane(float(gx), float(y0)), on_plane(float(gx), float(y1)));
    for (int gy = y0; gy <= y1; ++gy)
      line(on_plane(float(x0), float(gy)), on_plane(float(x1), float(gy)));
    const vtkIdType ids[4] = {
        point(on_plane(float(x), float(y))), point(on_plane(float(x + 1), float(y))),
        point(on_plane(float(x + 1), float(y + 1))), point(on_plane(float(x), float(y + 1)))};
    quad->InsertNextCell(4, ids);
  }
  // Unchanged (a re-render with the same camera and size, the same pixel):
  // the 3D view need not be drawn again.
  vtkPoints* shown = this->CameraGeometry->GetPoints();
  if (shown && shown->GetNumberOfPoints() == pts->GetNumberOfPoints() &&
      shown->GetDataType() == VTK_DOUBLE &&
      std::equal(static_cast<const double*>(pts->GetVoidPointer(0)),
                 static_cast<const double*>(pts->GetVoidPointer(0)) + 3 * pts->GetNumberOfPoints(),
                 static_cast<const double*>(shown->GetVoidPointer(0))))
    return;
  this->Changed |= kSceneView;
  this->CameraGeometry->Initialize();
  this->CameraGeometry->SetPoints(pts);
  this->CameraGeometry->SetLines(lines);
  this->PickedCell->Initialize();
  this->PickedCell->SetPoints(pts);
  this->PickedCell->SetPolys(quad);
}

void vtkRayScopeViewer::Internals::UpdateLegend() {
  // The entries for what is shown: the ray kinds and markers, then the
  // played walk's states or the BVH's level ramp (root to deepest level).
  std::vector<std::pair<std::string, std::array<double, 3>>> entries;
  auto add = [&](std::string label, const double(&c)[3]) {
    entries.push_back({std::move(label), {c[0], c[1], c[2]}});
  };
  for (int k = 0; k < 4; ++k) add(std::string(kKindNames[k]) + " ray", kKindColors[k]);
  add("skipped (not traced)", kSkippedColor);
  add("shading normal", kNormalColor);
  add("shadow ray blocked here", kOccluderColor);
  if (this->Self->TraversalSteps >= 0) {
    const std::string name = this->StructureLabel();
    for (int k = 1; k < 6; ++k) add(name + ": " + kWalkNames[k], kWalkColors[k]);
  } else if (this->Self->ShowBVH) {
    vtkDataArray* depth = this->BVH->GetOutput()->GetFieldData()->GetArray("TreeDepth");
    const int deepest = depth ? std::max(0, int(depth->GetTuple1(0)) - 1) : 0;
    const vtkIdType n = this->LevelTable->GetNumberOfTableValues();
    double root[4], leaves[4];
    this->LevelTable->GetTableValue(0, root);
    this->LevelTable->GetTableValue(n - 1, leaves);
    const std::string name = this->StructureLabel();
    add(name + ": level 0 (root)", {root[0], root[1], root[2]});
    add(name + ": level " + std::to_string(deepest) + " (deepest)",
        {leaves[0], leaves[1], leaves[2]});
  }
  // Rebuilt only when its entries change: each entry is text to rasterize.
  if (entries == this->LegendEntries) return;
  this->LegendEntries = entries;
  this->Changed |= kSceneView;
  this->Legend->SetNumberOfEntries(int(entries.size()));
  vtkSmartPointer<vtkPolyData> symbol = legend_symbol();
  for (size_t e = 0; e < entries.size(); ++e)
    this->Legend->SetEntry(int(e), symbol, entries[e].first.c_str(), entries[e].second.data());
}
