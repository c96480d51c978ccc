#include "vtkRayScopeRenderView.h"

#include "vtkObjectFactory.h"
#include "vtkPVSynchronizedRenderer.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopePass.h"

vtkStandardNewMacro(vtkRayScopeRenderView);

vtkRayScopeRenderView::vtkRayScopeRenderView() : Pass(vtkRayScopePass::New()) {
  // The synchronized renderer puts the pass on the view's renderer (on every
  // rank that renders).
  this->SynchronizedRenderers->SetRenderPass(this->Pass);
}

vtkRayScopeRenderView::~vtkRayScopeRenderView() {
  this->Pass->Delete();
}

vtkRayScopePass* vtkRayScopeRenderView::GetRayScopePass() {
  return this->Pass;
}

vtkRayScopeImageAlgorithm* vtkRayScopeRenderView::GetImageAlgorithm() {
  return this->Pass->GetImageAlgorithm();
}

void vtkRayScopeRenderView::SetRayScopeSamples(int n) {
  if (n == this->Samples) return;
  this->Samples = n;
  this->Modified();
}

void vtkRayScopeRenderView::SetRayScopeMaxDepth(int depth) {
  this->GetImageAlgorithm()->SetMaxDepth(depth);
}

void vtkRayScopeRenderView::SetRayScopeMinContribution(double c) {
  this->GetImageAlgorithm()->SetMinContribution(c);
}

void vtkRayScopeRenderView::SetRayScopeShadows(int on) {
  this->GetImageAlgorithm()->SetShadows(on);
}

void vtkRayScopeRenderView::SetRayScopeDisplayMode(int mode) {
  this->Pass->SetDisplayMode(mode);
}

int vtkRayScopeRenderView::GetRayScopeTracedSamples() {
  return this->GetImageAlgorithm()->GetSamples();
}

double vtkRayScopeRenderView::GetRayScopeLastRenderSeconds() {
  return this->Pass->GetLastRenderTime();
}

void vtkRayScopeRenderView::StillRender() {
  this->GetImageAlgorithm()->SetSamples(this->Samples);
  this->Superclass::StillRender();
}

void vtkRayScopeRenderView::InteractiveRender() {
  this->GetImageAlgorithm()->SetSamples(1);
  this->Superclass::InteractiveRender();
}

void vtkRayScopeRenderView::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Samples: " << this->Samples << "\n";
}
