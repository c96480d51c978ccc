// vtkRayScopeViewer's interactor style (vtkRayScopeViewerStyle.h).
#include "vtkRayScopeViewerStyle.h"

#include <cstdlib>

#include "vtkObjectFactory.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"

#include "vtkRayScopeViewer.h"

namespace {
constexpr int kClickSlop = 3;  // a press and release this close is a click, not a drag
}  // namespace

vtkStandardNewMacro(vtkRayScopeViewerStyle);

void vtkRayScopeViewerStyle::OnLeftButtonDown() {
  const int* p = this->Interactor->GetEventPosition();
  this->Press[0] = p[0];
  this->Press[1] = p[1];
  if (this->Viewer->GetImageRenderer()->IsInViewport(p[0], p[1])) {
    this->Viewer->PickAtDisplay(p[0], p[1]);
    return;
  }
  this->Superclass::OnLeftButtonDown();
}

void vtkRayScopeViewerStyle::OnLeftButtonUp() {
  this->Superclass::OnLeftButtonUp();
  const int* p = this->Interactor->GetEventPosition();
  if (std::abs(p[0] - this->Press[0]) <= kClickSlop &&
      std::abs(p[1] - this->Press[1]) <= kClickSlop &&
      this->Viewer->GetSceneRenderer()->IsInViewport(p[0], p[1]))
    this->Viewer->PickAtDisplay(p[0], p[1]);
}

void vtkRayScopeViewerStyle::OnKeyPress() {
  const char* key = this->Interactor->GetKeySym();
  if (key && this->Viewer->HandleKey(key)) return;
  this->Superclass::OnKeyPress();
}

void vtkRayScopeViewerStyle::OnChar() {
  const char c = this->Interactor->GetKeyCode();
  if (c == 'q' || c == 'e') this->Superclass::OnChar();
}
