#include "vtkRayScopeViewRayTree.h"

#include "vtkObjectFactory.h"
#include "vtkRayScopeRenderView.h"

vtkStandardNewMacro(vtkRayScopeViewRayTree);

void vtkRayScopeViewRayTree::SetView(vtkView* view) {
  this->SetSceneSource(vtkRayScopeRenderView::SceneOf(view, this->ViewIsRayScope));
}

int vtkRayScopeViewRayTree::RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                                        vtkInformationVector* outputVector) {
  if (!this->ViewIsRayScope) {
    vtkErrorMacro(<< vtkRayScopeRenderView::NotRayScopeError());
    return 0;
  }
  return this->Superclass::RequestData(request, inputVector, outputVector);
}
