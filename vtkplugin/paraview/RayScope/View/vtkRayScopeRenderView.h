/**
 * @class   vtkRayScopeRenderView
 * @brief   ParaView's render view, ray-traced by RayScope.
 *
 * A vtkPVRenderView whose renderer draws through a vtkRayScopePass: every
 * visible representation (surfaces, composite data, lines as tubes and points
 * as spheres, with their solid colors or scalar colors, opacity and the
 * RayScope material properties of their actors), the view's lights (light kit
 * and headlight), background and camera are converted as
 * vtkRayScopeImageAlgorithm::CopyRenderer() converts a renderer, and the image
 * is traced at the view's size. The plugin registers it as the "RayScope"
 * view (proxy RayScopeView, e.g. CreateView('RayScopeView') in
 * paraview.simple).
 *
 * While the camera moves (ParaView's interactive renders) the view traces one
 * sample per pixel, and one pixel per InteractiveReduction x InteractiveReduction
 * block (2 x 2 by default); a still render traces Samples x Samples for every pixel: with
 * Progressive on (the default) one sample per pixel per still render, each
 * added to the image while the camera rests (ParaView's client renders again
 * until ImagePasses says the image is complete), and all of them at once for
 * a screenshot; the complete image is the one-render image bit for bit. The render
 * settings are the pass's image algorithm's (GetImageAlgorithm()), which
 * validates them: the setters below forward to it.
 *
 * On several ranks (pvbatch or pvserver under MPI) the ranks render
 * together: the image algorithm gathers the representations' pieces from
 * every rank when they change, every rank traces a share of the image's
 * tiles (handed out by estimated cost) over the whole scene, and rank 0 assembles the image, which
 * ParaView delivers as its composited image (vtkRayScopeImageAlgorithm::SetController()). Shadows
 * and reflections between pieces on different ranks are there, and the image is the one-rank image.
 */
#ifndef vtkRayScopeRenderView_h
#define vtkRayScopeRenderView_h

#include "RayScopeParaViewViewModule.h"  // export macro
#include "vtkPVRenderView.h"
#include "vtkSmartPointer.h"  // Structure

class vtkRayScopeImageAlgorithm;
class vtkRayScopePass;
class vtkRayScopeSceneSettings;
class vtkRayScopeViewInformation;
class vtkView;

class RAYSCOPEPARAVIEWVIEW_EXPORT vtkRayScopeRenderView : public vtkPVRenderView {
 public:
  static vtkRayScopeRenderView* New();
  vtkTypeMacro(vtkRayScopeRenderView, vtkPVRenderView);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Samples per pixel of a still render: N x N (an interactive render
  /// traces 1).
  void SetRayScopeSamples(int n);
  int GetRayScopeSamples() { return this->Samples; }
  /// While the camera moves, one pixel is traced for each N x N block of the
  /// view (vtkRayScopePass::SetImageReduction); a still render traces every
  /// pixel. 1: every pixel while moving too.
  void SetRayScopeInteractiveReduction(int n);
  int GetRayScopeInteractiveReduction() { return this->InteractiveReduction; }
  /// Still renders refine the image one sample per pixel at a time (on, the
  /// default), or trace all Samples x Samples in one render (off).
  void SetRayScopeProgressive(int on);
  /// Bounces after the primary hit, the smallest contribution a secondary ray
  /// must carry to be traced, and hard shadows on or off
  /// (vtkRayScopeImageAlgorithm's MaxDepth, MinContribution, Shadows).
  void SetRayScopeMaxDepth(int depth);
  void SetRayScopeMinContribution(double c);
  void SetRayScopeShadows(int on);
  /// The structure the view's rays walk: the Accel, Storage, LooseFactor,
  /// KdSplit and GridResolution of `structure` (the view proxy's Structure
  /// subproxy, whose properties are the filters'), taken at each render.
  void SetRayScopeStructure(vtkRayScopeSceneSettings* structure);
  /// What the view shows: vtkRayScopePass::COLOR, COST (the structure's cost
  /// heat map), NORMALS, DEPTH or OBJECT_IDS.
  void SetRayScopeDisplayMode(int mode);

  /// What the last render traced, on this process or, on a client whose
  /// image the server's ranks trace, on the server (vtkRayScopeViewInformation).
  /// Samples per pixel (N of N x N): Samples after a still render, 1 after
  /// an interactive one.
  int GetRayScopeTracedSamples();
  /// Width and height of the last traced image: the view's size after a
  /// still render, InteractiveReduction times smaller after an interactive one.
  int* GetRayScopeTracedSize() VTK_SIZEHINT(2);
  /// Passes (samples per pixel) in the image shown, and in the complete image:
  /// equal once a progressive image is complete (1 and 1 after an interactive
  /// render, or without Progressive).
  int* GetRayScopeImagePasses() VTK_SIZEHINT(2);
  /// Wall-clock seconds of the last ray-traced image, conversion included
  /// (vtkRayScopePass::GetLastRenderTime()).
  double GetRayScopeLastRenderSeconds();

  /// The pass drawing the view, and the algorithm holding its scene and
  /// settings (never null).
  vtkRayScopePass* GetRayScopePass();
  vtkRayScopeImageAlgorithm* GetImageAlgorithm();

  /// The image algorithm of `view` when it is a RayScope view, for the
  /// sources that replay its scene (View Ray Tree, View Acceleration
  /// Structure); null otherwise, with `is_rayscope` false unless `view` is
  /// null too (no view chosen yet).
  static vtkRayScopeImageAlgorithm* SceneOf(vtkView* view, bool& is_rayscope);
  /// The error of such a source whose view is another kind.
  static const char* NotRayScopeError();

  void StillRender() override;
  void InteractiveRender() override;

 protected:
  vtkRayScopeRenderView();
  ~vtkRayScopeRenderView() override;

  // A client whose images come from the server's ranks traces nothing.
  void Render(bool interactive, bool skip_rendering) override;
  // What the last render traced (see GetRayScopeTracedSamples()).
  vtkRayScopeViewInformation* Traced();

  int Samples = 1;
  int InteractiveReduction = 2;
  bool Progressive = true;
  int TracedSize[2] = {0, 0};
  int ImagePasses[2] = {1, 1};
  vtkSmartPointer<vtkRayScopeViewInformation> TracedInfo;

 private:
  vtkRayScopeRenderView(const vtkRayScopeRenderView&) = delete;
  void operator=(const vtkRayScopeRenderView&) = delete;

  // Takes Structure's settings into the pass's image algorithm.
  void TakeStructure();

  vtkRayScopePass* Pass;
  vtkSmartPointer<vtkRayScopeSceneSettings> Structure;
};

#endif
