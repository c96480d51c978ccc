/**
 * @class   vtkRayScopePass
 * @brief   A vtkRenderPass that ray-traces the renderer's scene with RayScope
 *          (Whitted: hard shadows, reflection, refraction) and shows the image
 *          in the render window.
 *
 * Any VTK application switches a renderer to ray tracing with
 *
 * @code
 *   vtkNew<vtkRayScopePass> pass;
 *   renderer->SetPass(pass);
 * @endcode
 *
 * as with VTK's own vtkOSPRayPass. Each render converts the renderer with
 * vtkRayScopeImageAlgorithm::CopyRenderer() (visible actors with their mappers'
 * colors and vtkProperty materials, lights, the active camera; see there for
 * what is and is not taken), ray-traces it at the renderer's size and draws the
 * image into the renderer's viewport. The scene is kept between renders: only
 * new or modified geometry is converted again and the BVH is rebuilt only then,
 * so moving the camera or changing colors, lights or materials costs one ray
 * traced image.
 *
 * Reflectivity and index of refraction, which vtkProperty lacks, are set on an
 * actor's property with vtkRayScopeMaterial::SetPropertyReflectivity() and
 * SetPropertyIndexOfRefraction(); opacity < 1 makes a dielectric (glass).
 *
 * The render settings live in the image algorithm only: GetImageAlgorithm()
 * is the vtkRayScopeImageAlgorithm holding the scene, and the pass renders with
 * its Samples (N x N per pixel), MaxDepth, MinContribution, Shadows, Threads
 * and ComputeCost, e.g. pass.GetImageAlgorithm().SetSamples(3) in Python
 * (CopyRenderer() sets only the inputs, camera, size, background and lights). The pass
 * switches ComputeCost off when it is made (counting rays and BVH work per
 * pixel makes a render a few percent slower); with it on, the last image has
 * the "Cost" arrays and the totals in its field data (see
 * vtkRayScopeImageAlgorithm). DisplayMode COST shows the per-pixel BVH cost as
 * a heat map instead of the colors. GetLastImage() is the last ray-traced
 * image with all its arrays. vtkRayScopeRayTreeSource and vtkRayScopeAccelSource
 * take GetImageAlgorithm() as their scene source to show the ray tree of a
 * pixel of this very view, or its BVH.
 *
 * The pass draws colors only: the depth buffer is cleared, not written, and
 * OpenGL props of the same renderer are not drawn. Draw overlays (a ray tree,
 * BVH boxes) in a second renderer on a higher layer of the window.
 */
#ifndef vtkRayScopePass_h
#define vtkRayScopePass_h

#include "RayScopeRenderingModule.h"  // export macro
#include "vtkRenderPass.h"

class vtkImageData;
class vtkRayScopeImageAlgorithm;

class RAYSCOPERENDERING_EXPORT vtkRayScopePass : public vtkRenderPass {
 public:
  static vtkRayScopePass* New();
  vtkTypeMacro(vtkRayScopePass, vtkRenderPass);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Ray-traces the renderer of `s` and draws the image into its viewport.
  void Render(const vtkRenderState* s) override;

  /// What the window shows (the values of vtkRayScopeViewer's image modes).
  enum DisplayModes {
    COLOR = 0,      ///< the ray-traced colors (default)
    COST = 1,       ///< structure nodes visited per pixel as a heat map
    NORMALS = 2,    ///< the first hit's shading normal, (n + 1) / 2; misses black
    DEPTH = 3,      ///< the first hit's distance, near white to far dark (log scale); misses black
    OBJECT_IDS = 4  ///< one color per object; misses black
  };
  /// Setting COST switches the image algorithm's ComputeCost on (the heat map
  /// needs the "Cost" array); the others leave it as it is. Clamped to the
  /// modes above.
  virtual void SetDisplayMode(int mode);
  vtkGetMacro(DisplayMode, int);
  void SetDisplayModeToColor() { this->SetDisplayMode(COLOR); }
  void SetDisplayModeToCost() { this->SetDisplayMode(COST); }
  void SetDisplayModeToNormals() { this->SetDisplayMode(NORMALS); }
  void SetDisplayModeToDepth() { this->SetDisplayMode(DEPTH); }
  void SetDisplayModeToObjectIds() { this->SetDisplayMode(OBJECT_IDS); }

  ///@{
  /// Traces one pixel for each F x F block of the viewport (an image F times
  /// smaller on each side, each traced pixel drawn as its block): F^2 times
  /// fewer rays, for renders that must be fast, such as ParaView's while the
  /// camera moves. 1 (default): every pixel. Clamped to 1..16.
  vtkSetClampMacro(ImageReduction, int, 1, 16);
  vtkGetMacro(ImageReduction, int);
  ///@}

  ///@{
  /// With the image algorithm's Progressive on, each render adds a pass of
  /// one sample per pixel to the image while the scene and camera stay as
  /// they are (vtkRayScopeImageAlgorithm::Refine()), so that a view that
  /// renders again while it rests refines its image; GetImagePasses() tells
  /// how far it is. FinishProgressive (off by default): each render adds all
  /// the passes the image lacks, as a screenshot needs.
  vtkSetMacro(FinishProgressive, bool);
  vtkGetMacro(FinishProgressive, bool);
  vtkBooleanMacro(FinishProgressive, bool);
  ///@}

  ///@{
  /// Off: the pass only clears the viewport to the renderer's background and
  /// traces nothing (ParaView's client, whose image comes from the server's
  /// ranks, while its own renderer holds no data). On by default.
  vtkSetMacro(Tracing, bool);
  vtkGetMacro(Tracing, bool);
  ///@}

  /// The algorithm that holds the scene of the last render and the render
  /// settings (never null).
  vtkRayScopeImageAlgorithm* GetImageAlgorithm();

  /// The last ray-traced image (null before the first successful render).
  vtkImageData* GetLastImage();

  /// Wall-clock seconds of the last ray-traced image (conversion included).
  vtkGetMacro(LastRenderTime, double);

 protected:
  vtkRayScopePass();
  ~vtkRayScopePass() override;

  int DisplayMode;
  int ImageReduction;
  bool FinishProgressive;
  bool Tracing;
  double LastRenderTime;

 private:
  vtkRayScopePass(const vtkRayScopePass&) = delete;
  void operator=(const vtkRayScopePass&) = delete;

  vtkRayScopeImageAlgorithm* Algorithm;
  bool HasImage;
};

#endif
