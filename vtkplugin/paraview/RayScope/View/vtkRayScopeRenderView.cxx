#include "vtkRayScopeRenderView.h"

#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPVRenderViewSettings.h"
#include "vtkPVSynchronizedRenderer.h"
#include "vtkProcessModule.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopePass.h"
#include "vtkRayScopeSceneSettings.h"
#include "vtkRayScopeViewInformation.h"
#include "vtkSMProxy.h"
#include "vtkSMProxyIterator.h"
#include "vtkSMSession.h"

vtkRayScopeRenderView* vtkRayScopeRenderView::New() {
  // On several ranks, ParaView composites the ranks' images. Each rank here
  // traces a share of the pixels over the whole scene and rank 0 draws the
  // assembled image (vtkRayScopePass), so the composite must take rank 0's
  // full-size image as it is: compositing by depth over the whole image, not
  // IceT's, which renders each rank only where its own data projects. The
  // view's synchronized renderer is made in vtkPVRenderView's constructor
  // with the render-view settings' choice of IceT: it is set for this
  // construction only.
  vtkPVRenderViewSettings* settings = vtkPVRenderViewSettings::GetInstance();
  const bool icet_disabled = settings->GetDisableIceT();
  settings->SetDisableIceT(true);
  auto* view = new vtkRayScopeRenderView;
  settings->SetDisableIceT(icet_disabled);
  view->InitializeObjectBase();
  return view;
}

vtkRayScopeRenderView::vtkRayScopeRenderView()
    : TracedInfo(vtkSmartPointer<vtkRayScopeViewInformation>::New()), Pass(vtkRayScopePass::New()) {
  // The synchronized renderer puts the pass on the view's renderer (on every
  // rank that renders).
  this->SynchronizedRenderers->SetRenderPass(this->Pass);
  // The ranks and a server render on the view's own background, not on black
  // (ParaView's compositing repaints the background where the image is
  // transparent): the background is part of the ray-traced image (seen in
  // reflections and refractions), and rank 0's image covers the whole view.
  // ParaView's switch for a ray tracer that paints its own background (its
  // path tracer's) turns the black background off on both synchronizers.
  this->SynchronizedRenderers->SetEnableRayTracing(true);
  this->SynchronizedRenderers->SetEnablePathTracing(true);
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

vtkRayScopeImageAlgorithm* vtkRayScopeRenderView::SceneOf(vtkView* view, bool& is_rayscope) {
  auto* rayscope = vtkRayScopeRenderView::SafeDownCast(view);
  is_rayscope = view == nullptr || rayscope != nullptr;
  return rayscope ? rayscope->GetImageAlgorithm() : nullptr;
}

const char* vtkRayScopeRenderView::NotRayScopeError() {
  return "View: not a RayScope view (create one with CreateView('RayScopeView'))";
}

void vtkRayScopeRenderView::SetRayScopeSamples(int n) {
  if (n == this->Samples) return;
  this->Samples = n;
  this->Modified();
}

void vtkRayScopeRenderView::SetRayScopeInteractiveReduction(int n) {
  if (n == this->InteractiveReduction) return;
  this->InteractiveReduction = n;
  this->Modified();
}

void vtkRayScopeRenderView::SetRayScopeProgressive(int on) {
  if (bool(on) == this->Progressive) return;
  this->Progressive = on != 0;
  this->Modified();
}

void vtkRayScopeRenderView::SetRayScopeStructure(vtkRayScopeSceneSettings* structure) {
  if (structure == this->Structure) return;
  this->Structure = structure;
  this->Modified();
}

void vtkRayScopeRenderView::TakeStructure() {
  if (this->Structure) this->GetImageAlgorithm()->GetSettings()->CopyStructure(this->Structure);
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

vtkRayScopeViewInformation* vtkRayScopeRenderView::Traced() {
  this->TracedInfo->CopyFromObject(this);
  // A client whose image the server's ranks trace asks the server's root:
  // its own algorithm traced nothing.
  if (this->Pass->GetTracing()) return this->TracedInfo;
  auto* session = vtkSMSession::SafeDownCast(this->GetSession());
  vtkNew<vtkSMProxyIterator> views;
  views->SetSession(session);
  views->SetModeToOneGroup();
  for (views->Begin("views"); session && !views->IsAtEnd(); views->Next()) {
    vtkSMProxy* proxy = views->GetProxy();
    if (proxy->GetClientSideObject() != this) continue;
    proxy->GatherInformation(this->TracedInfo, vtkPVSession::RENDER_SERVER);
    break;
  }
  return this->TracedInfo;
}

int vtkRayScopeRenderView::GetRayScopeTracedSamples() {
  return this->Traced()->GetSamples();
}

int* vtkRayScopeRenderView::GetRayScopeTracedSize() {
  this->Traced()->GetSize(this->TracedSize);
  return this->TracedSize;
}

int* vtkRayScopeRenderView::GetRayScopeImagePasses() {
  this->Traced()->GetPasses(this->ImagePasses);
  return this->ImagePasses;
}

double vtkRayScopeRenderView::GetRayScopeLastRenderSeconds() {
  return this->Traced()->GetSeconds();
}

void vtkRayScopeRenderView::StillRender() {
  this->TakeStructure();
  this->GetImageAlgorithm()->SetSamples(this->Samples);
  this->GetImageAlgorithm()->SetProgressive(this->Progressive);
  this->Pass->SetFinishProgressive(this->GetInCaptureScreenshot());
  this->Pass->SetImageReduction(1);
  this->Superclass::StillRender();
}

void vtkRayScopeRenderView::InteractiveRender() {
  this->TakeStructure();
  this->GetImageAlgorithm()->SetSamples(1);
  this->GetImageAlgorithm()->SetProgressive(false);
  this->Pass->SetImageReduction(this->InteractiveReduction);
  this->Superclass::InteractiveRender();
}

void vtkRayScopeRenderView::Render(bool interactive, bool skip_rendering) {
  // In client-server mode with the render on the server, the client's
  // renderer holds the representations' empty placeholders and its image is
  // replaced by the server's: it only clears to the background.
  const bool remote = interactive ? this->GetUseDistributedRenderingForLODRender()
                                  : this->GetUseDistributedRenderingForRender();
  this->Pass->SetTracing(
      !(remote && vtkProcessModule::GetProcessType() == vtkProcessModule::PROCESS_CLIENT));
  this->Superclass::Render(interactive, skip_rendering);
}

void vtkRayScopeRenderView::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Samples: " << this->Samples << "\n";
  os << indent << "InteractiveReduction: " << this->InteractiveReduction << "\n";
  os << indent << "Progressive: " << this->Progressive << "\n";
}
