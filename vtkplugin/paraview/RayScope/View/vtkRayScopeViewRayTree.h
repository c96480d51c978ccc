/**
 * @class   vtkRayScopeViewRayTree
 * @brief   The ray tree of a pixel of a RayScope render view.
 *
 * vtkRayScopeRayTreeSource whose scene is the view's (SetView(): the scene,
 * camera, lights and settings the view last traced, through its pass's image
 * algorithm), so that the tree is the one behind that pixel of the view, with
 * no second camera or settings to keep in step. Pixels are the view's, in VTK
 * image coordinates ((0, 0) bottom-left). The plugin registers it as the
 * source "View Ray Tree" (RayScopeViewRayTree; ViewRayTree() in paraview.simple).
 */
#ifndef vtkRayScopeViewRayTree_h
#define vtkRayScopeViewRayTree_h

#include "RayScopeParaViewViewModule.h"  // export macro
#include "vtkRayScopeRayTreeSource.h"

class vtkView;

class RAYSCOPEPARAVIEWVIEW_EXPORT vtkRayScopeViewRayTree : public vtkRayScopeRayTreeSource {
 public:
  static vtkRayScopeViewRayTree* New();
  vtkTypeMacro(vtkRayScopeViewRayTree, vtkRayScopeRayTreeSource);

  /// The view whose scene is replayed: a vtkRayScopeRenderView (another view
  /// is an error when the tree updates; null: none).
  void SetView(vtkView* view);

 protected:
  vtkRayScopeViewRayTree() = default;
  ~vtkRayScopeViewRayTree() override = default;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

 private:
  vtkRayScopeViewRayTree(const vtkRayScopeViewRayTree&) = delete;
  void operator=(const vtkRayScopeViewRayTree&) = delete;

  bool ViewIsRayScope = false;
};

#endif
