// vtkRayScopeViewer's window: its viewports, the image viewport (the image,
// the picked pixel's marker, the color scale) and the scene drawn in 3D (the
// objects the tracer intersects, the lights, the camera with its image plane
// and pixel grid); the other parts are built into it from their own files.
#include "vtkRayScopeViewerInternals.h"
#include "vtkRayScopeViewerStyle.h"

using namespace rayscope_vtkmodule::viewer;

namespace {

void srgb(const rayscope::Color& linear, double out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = rayscope::linear_to_srgb(std::clamp(linear[k], 0.0f, 1.0f));
}

}  // namespace

// Builds the window, its renderers and every part drawn in them.
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

  // The overlay: the picked pixel's rays and the structure's boxes.
  this->BuildOverlay();

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

  // The text: help and message lines, the inspect panel, the legend.
  this->BuildTextPanel();
  this->BuildTreeDiagram();

  this->Picker->PickFromListOn();
  this->Picker->SetTolerance(0.0005);
  this->BuildSceneGeometry();
  this->Initialized = true;
}

// The core scene's objects, drawn by VTK: meshes, spheres, tubes, points,
// planes (sized to the rest of the scene) and point lights, in their material colors, half
// transparent so that rays inside them stay visible.
void vtkRayScopeViewer::Internals::BuildSceneGeometry() {
  for (vtkActor* a : this->GeometryActors) this->SceneRen->RemoveActor(a);
  this->GeometryActors.clear();
  this->Picker->InitializePickList();
  const rayscope::Scene& s = *this->scene();
  rayscope::Bounds3 b = s.bounds();
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
  // Tube sets around their traced segments (VTK's tube filter, capped; the
  // radius per point when the set has radii) and point sets as a sphere at
  // each traced point, of its radius.
  for (const rayscope::TubeSet& t : s.tubes) {
    vtkNew<vtkPolyData> pd;
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    vtkNew<vtkFloatArray> radius;
    vtkNew<vtkCellArray> lines;
    for (size_t k = 0; k < t.segments.size(); ++k) {
      if (!t.traced(k)) continue;
      vtkIdType ids[2];
      for (int e = 0; e < 2; ++e) {
        const uint32_t i = t.segments[k][e];
        const rayscope::DVec3 w = s.to_world(t.positions[i]);
        ids[e] = pts->InsertNextPoint(w.x, w.y, w.z);
        radius->InsertNextValue(t.radii.empty() ? t.radius : t.radii[i]);
      }
      lines->InsertNextCell(2, ids);
    }
    pd->SetPoints(pts);
    pd->SetLines(lines);
    pd->GetPointData()->SetScalars(radius);
    vtkNew<vtkTubeFilter> tube;
    tube->SetInputData(pd);
    tube->SetVaryRadiusToVaryRadiusByAbsoluteScalar();
    tube->SetNumberOfSides(16);
    tube->CappingOn();
    tube->Update();
    add(tube->GetOutput(), nullptr, t.material, true);
  }
  for (const rayscope::PointSet& ps : s.points) {
    vtkNew<vtkPolyData> pd;
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    vtkNew<vtkFloatArray> radius;
    for (size_t i = 0; i < ps.positions.size(); ++i) {
      if (!ps.traced(i)) continue;
      const rayscope::DVec3 w = s.to_world(ps.positions[i]);
      pts->InsertNextPoint(w.x, w.y, w.z);
      radius->InsertNextValue(ps.point_radius(i));
    }
    pd->SetPoints(pts);
    pd->GetPointData()->SetScalars(radius);
    vtkNew<vtkSphereSource> ball;  // radius 1, scaled by each point's radius
    ball->SetRadius(1.0);
    ball->SetThetaResolution(16);
    ball->SetPhiResolution(12);
    vtkNew<vtkGlyph3D> glyphs;
    glyphs->SetInputData(pd);
    glyphs->SetSourceConnection(ball->GetOutputPort());
    glyphs->SetScaleModeToScaleByScalar();
    glyphs->SetScaleFactor(1.0);
    glyphs->OrientOff();
    glyphs->Update();
    add(glyphs->GetOutput(), nullptr, ps.material, true);
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

void vtkRayScopeViewer::Internals::AimSceneCamera(const double bounds[6], double zoom) {
  vtkCamera* cam = this->SceneRen->GetActiveCamera();
  cam->SetViewAngle(kSceneViewAngle);
  this->SceneRen->ResetCamera(bounds);
  cam->Zoom(zoom);
  this->Changed |= kSceneView;
}

void vtkRayScopeViewer::Internals::FrameScene() {
  rayscope::Bounds3 b = this->scene()->bounds();
  b.extend(this->scene()->camera.eye);
  b.extend(this->scene()->camera.look_at);
  const rayscope::DVec3 lo = this->scene()->to_world(b.lo), hi = this->scene()->to_world(b.hi);
  const double bounds[6] = {lo.x, hi.x, lo.y, hi.y, lo.z, hi.z};
  this->AimSceneCamera(bounds, kSceneZoom);
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

// The picked pixel's marker in the image: its square and a cross hair.
void vtkRayScopeViewer::Internals::UpdateMarker() {
  const int i = this->Self->PickedPixel[0], j = this->Self->PickedPixel[1];
  vtkNew<vtkPoints> pts;
  const double x = i, y = j, r = 0.5, arm = 6.0;
  for (auto [px, py] : {std::pair{x - r, y - r},
                        {x + r, y - r},
                        {x + r, y + r},
                        {x - r, y + r},
                        {x - arm, y},
                        {x - r, y},
                        {x + r, y},
                        {x + arm, y},
                        {x, y - arm},
                        {x, y - r},
                        {x, y + r},
                        {x, y + arm}})
    pts->InsertNextPoint(px, py, 0.5);
  vtkNew<vtkCellArray> lines;
  const vtkIdType square[5] = {0, 1, 2, 3, 0};
  lines->InsertNextCell(5, square);
  for (vtkIdType k = 4; k < 12; k += 2) {
    const vtkIdType seg[2] = {k, k + 1};
    lines->InsertNextCell(2, seg);
  }
  if (this->Self->ShowPacket) {
    // The packet's block of pixels (its rows counted from the top).
    const rayscope::TileRect& b = this->Packet.block;
    const double x0 = b.x0 - r, x1 = b.x1 - 1 + r;
    const double y0 = this->Settings.height - b.y1 - r, y1 = this->Settings.height - 1 - b.y0 + r;
    const vtkIdType first = pts->GetNumberOfPoints();
    for (auto [px, py] : {std::pair{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}})
      pts->InsertNextPoint(px, py, 0.5);
    const vtkIdType block[5] = {first, first + 1, first + 2, first + 3, first};
    lines->InsertNextCell(5, block);
  }
  this->Marker->Initialize();
  this->Marker->SetPoints(pts);
  this->Marker->SetLines(lines);
  this->MarkerActor->VisibilityOn();
}

// Draws the viewports that changed (Changed), and only those: the others
// keep their pixels (VTK draws into a framebuffer of its own, and a
// renderer whose Draw is off leaves its viewport as it was). Under
// software OpenGL a click then costs the window what the click changed, a
// render's progress the header and the image. Renders of the window by
// anyone else (orbiting, resizing, a screenshot) draw every viewport.
void vtkRayScopeViewer::Internals::Redraw() {
  if (!this->Initialized || this->Changed == 0) return;
  const std::pair<vtkRenderer*, unsigned> views[4] = {{this->HeaderRen, kHeaderView},
                                                      {this->ImageRen, kImageView},
                                                      {this->SceneRen, kSceneView},
                                                      {this->PanelRen, kPanelView}};
  for (auto [ren, view] : views) ren->SetDraw((this->Changed & view) != 0);
  this->Changed = 0;
  this->Window->Render();
  for (auto [ren, view] : views) ren->SetDraw(1);
}
