/**
 * @class   vtkRayScopeViewInformation
 * @brief   What a RayScope view traced last, gathered from where it traces.
 *
 * With a pvserver, the RayScope view traces on the server's ranks and the
 * client's view only shows the image: the client learns what the server
 * traced (the image's size and samples, its progressive passes, the seconds
 * it took) by gathering this information from the server's root, whose view
 * holds the assembled image. vtkRayScopeRenderView's information getters
 * (TracedSize, TracedSamples, ImagePasses, LastRenderSeconds) read it.
 */
#ifndef vtkRayScopeViewInformation_h
#define vtkRayScopeViewInformation_h

#include "RayScopeParaViewViewModule.h"  // export macro
#include "vtkPVInformation.h"

class RAYSCOPEPARAVIEWVIEW_EXPORT vtkRayScopeViewInformation : public vtkPVInformation {
 public:
  static vtkRayScopeViewInformation* New();
  vtkTypeMacro(vtkRayScopeViewInformation, vtkPVInformation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Reads what a vtkRayScopeRenderView traced on this process.
  void CopyFromObject(vtkObject* view) override;
  /// Takes the root's values (gathered from the root only).
  void AddInformation(vtkPVInformation* other) override;
  void CopyToStream(vtkClientServerStream* stream) override;
  void CopyFromStream(const vtkClientServerStream* stream) override;

  /// Passes in the image shown, and in the complete image.
  vtkGetVector2Macro(Passes, int);
  /// Width and height of the last traced image.
  vtkGetVector2Macro(Size, int);
  /// N of the N x N samples per pixel of the last render.
  vtkGetMacro(Samples, int);
  /// Wall-clock seconds of the last ray-traced image.
  vtkGetMacro(Seconds, double);

 protected:
  vtkRayScopeViewInformation();
  ~vtkRayScopeViewInformation() override = default;

  int Passes[2] = {1, 1};
  int Size[2] = {0, 0};
  int Samples = 1;
  double Seconds = 0.0;

 private:
  vtkRayScopeViewInformation(const vtkRayScopeViewInformation&) = delete;
  void operator=(const vtkRayScopeViewInformation&) = delete;
};

#endif
