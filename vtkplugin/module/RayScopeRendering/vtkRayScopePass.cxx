#include "vtkRayScopePass.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "vtkCamera.h"
#include "vtkExecutive.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkPointData.h"
#include "vtkRenderState.h"
#include "vtkRenderer.h"
#include "vtkUnsignedCharArray.h"
#include "vtk_glew.h"

#include "RayScopeDisplay.h"
#include "rayscope/image.h"
#include "vtkRayScopeImageAlgorithm.h"

vtkStandardNewMacro(vtkRayScopePass);

vtkRayScopePass::vtkRayScopePass()
    : DisplayMode(COLOR),
      ImageReduction(1),
      FinishProgressive(false),
      Tracing(true),
      LastRenderTime(0.0),
      Algorithm(vtkRayScopeImageAlgorithm::New()),
      HasImage(false) {
  this->Algorithm->ComputeCostOff();
}

vtkRayScopePass::~vtkRayScopePass() {
  this->Algorithm->Delete();
}

vtkRayScopeImageAlgorithm* vtkRayScopePass::GetImageAlgorithm() {
  return this->Algorithm;
}

void vtkRayScopePass::SetDisplayMode(int mode) {
  mode = std::clamp(mode, int(COLOR), int(OBJECT_IDS));
  static_assert(int(COLOR) == rayscope_vtkmodule::kDisplayColor &&
                int(COST) == rayscope_vtkmodule::kDisplayCost &&
                int(NORMALS) == rayscope_vtkmodule::kDisplayNormal &&
                int(DEPTH) == rayscope_vtkmodule::kDisplayDepth &&
                int(OBJECT_IDS) == rayscope_vtkmodule::kDisplayObjectId);
  if (mode == COST) this->Algorithm->ComputeCostOn();
  if (mode == this->DisplayMode) return;
  this->DisplayMode = mode;
  this->Modified();
}

vtkImageData* vtkRayScopePass::GetLastImage() {
  return this->HasImage ? this->Algorithm->GetOutput() : nullptr;
}

void vtkRayScopePass::Render(const vtkRenderState* s) {
  this->NumberOfRenderedProps = 0;
  vtkRenderer* ren = s->GetRenderer();
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!window) {
    vtkErrorMacro(<< "vtkRayScopePass needs an OpenGL render window");
    return;
  }
  // Viewport and scissor box of this renderer (what vtkCameraPass sets up for
  // the OpenGL passes), then its background color and depth.
  ren->GetActiveCamera()->UpdateViewport(ren);
  ren->Clear();
  if (!this->Tracing) return;
  const auto start = std::chrono::steady_clock::now();

  vtkRayScopeImageAlgorithm* alg = this->Algorithm;
  const int inputs = alg->CopyRenderer(ren);
  if (inputs <= 0) return;  // nothing to trace: the cleared background is the image
  // The viewport (CopyRenderer sized the image to it), and the image traced:
  // F times smaller with an image reduction F.
  int width, height, x0, y0;
  ren->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
  const int f = this->ImageReduction;
  if (f > 1) alg->SetSize((width + f - 1) / f, (height + f - 1) / f);
  this->HasImage = false;
  // With several processes (the algorithm's controller: ParaView's MPI ranks)
  // every process traces a share of the image and process 0 gets all of it;
  // the algorithm has reported any error once, on one process.
  vtkMultiProcessController* c = alg->GetController();
  const bool parallel = c && c->GetNumberOfProcesses() > 1;
  // Its update is then collective: every process traces on every render,
  // whatever changed on it (the gathered scene and its structure are kept
  // while no process's geometry changes). A progressive image goes on if
  // nothing changed since the last render (Refine() then marks it modified on
  // every process too).
  if (alg->GetProgressive())
    alg->Refine(this->FinishProgressive);
  else if (parallel)
    alg->Modified();
  if (!alg->GetExecutive()->Update()) {
    if (!parallel) vtkErrorMacro(<< "ray tracing failed (see the vtkRayScopeImageAlgorithm error)");
    return;
  }
  if (parallel && c->GetLocalProcessId() != 0) return;  // its share went to process 0
  vtkImageData* image = alg->GetOutput();
  if (!image) {  // the algorithm's output port makes images; anything else is a bug
    vtkErrorMacro(<< "the ray tracer's output is not an image");
    return;
  }
  this->HasImage = true;
  int dims[3];
  image->GetDimensions(dims);

  std::vector<unsigned char> shown;  // the display mode's bytes, when not the colors
  void* pixels = nullptr;
  if (this->DisplayMode != COLOR) {
    shown = rayscope_vtkmodule::display_pixels(image, this->DisplayMode);
    if (!shown.empty()) pixels = shown.data();
  } else if (auto* color = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars()))
    pixels = color->GetVoidPointer(0);
  if (!pixels) {
    vtkErrorMacro(<< (this->DisplayMode == COST
                          ? "the ray-traced image has no Cost array: turn the image algorithm's "
                            "ComputeCost on for DisplayMode COST"
                          : std::string("the ray-traced image has no array for the display mode ") +
                                rayscope_vtkmodule::display_mode_name(this->DisplayMode)));
    return;
  }
  // The image is as large as the renderer (or F times smaller: each pixel is
  // repeated over its F x F block); drawn 1:1 over the viewport.
  std::vector<unsigned char> blocks;
  if (f > 1) {
    const auto* src = static_cast<const unsigned char*>(pixels);
    blocks.resize(size_t(width) * size_t(height) * 3);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        std::copy_n(src + 3 * (size_t(y / f) * size_t(dims[0]) + size_t(x / f)), 3,
                    blocks.data() + 3 * (size_t(y) * size_t(width) + size_t(x)));
    pixels = blocks.data();
    dims[0] = width;
    dims[1] = height;
  }
  window->DrawPixels(x0, y0, x0 + dims[0] - 1, y0 + dims[1] - 1, 3, VTK_UNSIGNED_CHAR, pixels);
  if (parallel) {
    // The other processes drew nothing; their images are composited with this
    // one by depth (ParaView's parallel render), so this one is made nearest
    // everywhere: it is the whole image.
    vtkOpenGLState* state = window->GetState();
    state->vtkglDepthMask(GL_TRUE);
    state->vtkglClearDepth(0.0);
    state->vtkglClear(GL_DEPTH_BUFFER_BIT);
    state->vtkglClearDepth(1.0);
  }
  this->LastRenderTime =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  this->NumberOfRenderedProps = inputs;
}

void vtkRayScopePass::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "DisplayMode: " << rayscope_vtkmodule::display_mode_name(this->DisplayMode)
     << "\n";
  os << indent << "ImageReduction: " << this->ImageReduction << "\n";
  os << indent << "FinishProgressive: " << this->FinishProgressive << "\n";
  os << indent << "Tracing: " << this->Tracing << "\n";
  os << indent << "LastRenderTime: " << this->LastRenderTime << "\n";
  os << indent << "ImageAlgorithm:\n";
  this->Algorithm->PrintSelf(os, indent.GetNextIndent());
}
