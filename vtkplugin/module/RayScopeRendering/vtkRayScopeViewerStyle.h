// vtkRayScopeViewer's interactor style: clicks pick, keys go to the viewer,
// dragging in the 3D view orbits (vtkInteractorStyleTrackballCamera).
// Private header.
#pragma once

#include "vtkInteractorStyleTrackballCamera.h"

class vtkRayScopeViewer;

class vtkRayScopeViewerStyle : public vtkInteractorStyleTrackballCamera {
 public:
  static vtkRayScopeViewerStyle* New();
  vtkTypeMacro(vtkRayScopeViewerStyle, vtkInteractorStyleTrackballCamera);
  /// The viewer the clicks and keys go to (not owned: it owns the style).
  vtkRayScopeViewer* Viewer = nullptr;

  /// A press in the image picks its pixel; elsewhere it starts an orbit.
  void OnLeftButtonDown() override;
  /// A release close to its press in the 3D view (a click, not a drag) picks
  /// the pixel that sees the surface there.
  void OnLeftButtonUp() override;
  /// The viewer's keys (HandleKey); any other key goes to the trackball.
  void OnKeyPress() override;
  /// VTK's own character keys (wireframe, reset, stereo, fly, pick) would
  /// fight the viewer's; only quitting (q, e) is kept.
  void OnChar() override;

 protected:
  vtkRayScopeViewerStyle() = default;
  ~vtkRayScopeViewerStyle() override = default;

 private:
  vtkRayScopeViewerStyle(const vtkRayScopeViewerStyle&) = delete;
  void operator=(const vtkRayScopeViewerStyle&) = delete;

  int Press[2] = {-1000, -1000};  // where the left button went down
};
