// What vtkRayScopeImageAlgorithm::CopyRenderer() (vtkRayScopeRendererCopy.cxx)
// keeps between calls (private header).
#pragma once

#include <vector>

#include "vtkSmartPointer.h"
#include "vtkWeakPointer.h"

class vtkActor;
class vtkCompositeDataDisplayAttributes;
class vtkRayScopeMaterial;
class vtkRayScopeMeshConverter;
class vtkTransformFilter;

namespace rayscope_vtkmodule {

/// One actor of the copied renderer: an unchanged actor keeps the same input,
/// converter and material, so its geometry is not converted again and the
/// BVH is not rebuilt.
struct CopiedActor {
  vtkWeakPointer<vtkActor> actor;
  vtkSmartPointer<vtkTransformFilter> transform;  // null while the matrix is the identity
  vtkSmartPointer<vtkRayScopeMeshConverter> converter;
  vtkSmartPointer<vtkRayScopeMaterial> material;
  // A composite mapper's block visibility, colors and opacity (else null).
  vtkSmartPointer<vtkCompositeDataDisplayAttributes> block_attributes;
  bool used = false;
};

/// The actors of the last CopyRenderer() call.
using CopiedActors = std::vector<CopiedActor>;

}  // namespace rayscope_vtkmodule
