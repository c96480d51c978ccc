#include "vtkRayScopeViewInformation.h"

#include <algorithm>

#include "vtkClientServerStream.h"
#include "vtkObjectFactory.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopePass.h"
#include "vtkRayScopeRenderView.h"

vtkStandardNewMacro(vtkRayScopeViewInformation);

vtkRayScopeViewInformation::vtkRayScopeViewInformation() {
  this->RootOnly = 1;
}

void vtkRayScopeViewInformation::CopyFromObject(vtkObject* object) {
  auto* view = vtkRayScopeRenderView::SafeDownCast(object);
  if (!view) return;
  vtkRayScopeImageAlgorithm* alg = view->GetImageAlgorithm();
  this->Passes[0] = alg->GetImagePasses();
  this->Passes[1] = alg->GetImageTotalPasses();
  this->Size[0] = alg->GetWidth();
  this->Size[1] = alg->GetHeight();
  this->Samples = alg->GetSamples();
  this->Seconds = view->GetRayScopePass()->GetLastRenderTime();
}

void vtkRayScopeViewInformation::AddInformation(vtkPVInformation* other) {
  auto* info = vtkRayScopeViewInformation::SafeDownCast(other);
  if (!info) return;
  std::copy_n(info->Passes, 2, this->Passes);
  std::copy_n(info->Size, 2, this->Size);
  this->Samples = info->Samples;
  this->Seconds = info->Seconds;
}

void vtkRayScopeViewInformation::CopyToStream(vtkClientServerStream* stream) {
  stream->Reset();
  *stream << vtkClientServerStream::Reply << this->Passes[0] << this->Passes[1] << this->Size[0]
          << this->Size[1] << this->Samples << this->Seconds << vtkClientServerStream::End;
}

void vtkRayScopeViewInformation::CopyFromStream(const vtkClientServerStream* stream) {
  stream->GetArgument(0, 0, &this->Passes[0]);
  stream->GetArgument(0, 1, &this->Passes[1]);
  stream->GetArgument(0, 2, &this->Size[0]);
  stream->GetArgument(0, 3, &this->Size[1]);
  stream->GetArgument(0, 4, &this->Samples);
  stream->GetArgument(0, 5, &this->Seconds);
}

void vtkRayScopeViewInformation::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Passes: " << this->Passes[0] << " of " << this->Passes[1] << "\n";
  os << indent << "Size: " << this->Size[0] << " x " << this->Size[1] << "\n";
  os << indent << "Samples: " << this->Samples << "\n";
  os << indent << "Seconds: " << this->Seconds << "\n";
}
