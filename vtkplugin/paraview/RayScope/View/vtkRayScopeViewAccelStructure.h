/**
 * @class   vtkRayScopeViewAccelStructure
 * @brief   The acceleration structure a RayScope render view's rays walk.
 *
 * vtkRayScopeAccelSource whose scene is the view's (SetView(): the scene,
 * structure, camera and settings the view last traced, through its pass's
 * image algorithm): its boxes are the ones the view's rays walk, and the
 * visit counts of a pixel (VisitMode 1) count that pixel's rays in the view,
 * with no second camera or settings to keep in step. Pixels are the view's,
 * in VTK image coordinates ((0, 0) bottom-left). The plugin registers it as
 * the source "View Acceleration Structure" (RayScopeViewAccelStructure;
 * ViewAccelerationStructure() in paraview.simple).
 */
#ifndef vtkRayScopeViewAccelStructure_h
#define vtkRayScopeViewAccelStructure_h

#include "RayScopeParaViewViewModule.h"  // export macro
#include "vtkRayScopeAccelSource.h"

class vtkView;

class RAYSCOPEPARAVIEWVIEW_EXPORT vtkRayScopeViewAccelStructure : public vtkRayScopeAccelSource {
 public:
  static vtkRayScopeViewAccelStructure* New();
  vtkTypeMacro(vtkRayScopeViewAccelStructure, vtkRayScopeAccelSource);

  /// The view whose scene is shown: a vtkRayScopeRenderView (another view is
  /// an error when the structure updates; null: none).
  void SetView(vtkView* view);

 protected:
  vtkRayScopeViewAccelStructure() = default;
  ~vtkRayScopeViewAccelStructure() override = default;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

 private:
  vtkRayScopeViewAccelStructure(const vtkRayScopeViewAccelStructure&) = delete;
  void operator=(const vtkRayScopeViewAccelStructure&) = delete;

  bool ViewIsRayScope = false;
};

#endif
