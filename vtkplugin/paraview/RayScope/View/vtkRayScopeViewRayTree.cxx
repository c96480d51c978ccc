#include "vtkRayScopeViewRayTree.h"

#include "vtkObjectFactory.h"
#include "vtkRayScopeRenderView.h"

vtkStandardNewMacro(vtkRayScopeViewRayTree);

void vtkRayScopeViewRayTree::SetView(vtkView* view) {
  auto* rayscope = vtkRayScopeRenderView::SafeDownCast(view);
  this->ViewIsRayScope = view == nullptr || rayscope != nullptr;
  this->SetSceneSource(rayscope ? rayscope->GetImageAlgorithm() : nullptr);
}

int vtkRayScopeViewRayTree::RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                                        vtkInformationVector* outputVector) {
  if (!this->ViewIsRayScope) {
    vtkErrorMacro(<< "View: not a RayScope view (create one with CreateView('RayScopeView'))");
    return 0;
  }
  return this->Superclass::RequestData(request, inputVector, outputVector);
}
