#include "vtkRayScopeBVHSource.h"

#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkRayScopeBVHSource);

vtkRayScopeBVHSource::vtkRayScopeBVHSource() {
  vtkWarningMacro(<< "vtkRayScopeBVHSource is deprecated and will be removed in the next release: "
                     "use vtkRayScopeAccelSource (the same filter)");
}
