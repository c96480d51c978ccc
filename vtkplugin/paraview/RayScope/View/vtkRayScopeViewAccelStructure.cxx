#include "vtkRayScopeViewAccelStructure.h"

#include "vtkObjectFactory.h"
#include "vtkRayScopeRenderView.h"

vtkStandardNewMacro(vtkRayScopeViewAccelStructure);

void vtkRayScopeViewAccelStructure::SetView(vtkView* view) {
  this->SetSceneSource(vtkRayScopeRenderView::SceneOf(view, this->ViewIsRayScope));
}

int vtkRayScopeViewAccelStructure::RequestData(vtkInformation* request,
                                               vtkInformationVector** inputVector,
                                               vtkInformationVector* outputVector) {
  if (!this->ViewIsRayScope) {
    vtkErrorMacro(<< vtkRayScopeRenderView::NotRayScopeError());
    return 0;
  }
  return this->Superclass::RequestData(request, inputVector, outputVector);
}
