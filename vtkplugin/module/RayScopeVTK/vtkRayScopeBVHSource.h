/**
 * @class   vtkRayScopeBVHSource
 * @brief   Deprecated name of vtkRayScopeAccelSource.
 *
 * The structure source draws whichever acceleration structure the scene
 * walks, not only the BVH, and is named vtkRayScopeAccelSource for that. This
 * class is the same filter under its old name, kept for one release so that
 * scripts written for it keep working; each new instance warns once
 * (vtkWarningMacro) that the name is deprecated.
 */
#ifndef vtkRayScopeBVHSource_h
#define vtkRayScopeBVHSource_h

#include "RayScopeVTKModule.h"  // export macro
#include "vtkRayScopeAccelSource.h"

class RAYSCOPEVTK_EXPORT vtkRayScopeBVHSource : public vtkRayScopeAccelSource {
 public:
  static vtkRayScopeBVHSource* New();
  vtkTypeMacro(vtkRayScopeBVHSource, vtkRayScopeAccelSource);

 protected:
  vtkRayScopeBVHSource();
  ~vtkRayScopeBVHSource() override = default;

 private:
  vtkRayScopeBVHSource(const vtkRayScopeBVHSource&) = delete;
  void operator=(const vtkRayScopeBVHSource&) = delete;
};

#endif
