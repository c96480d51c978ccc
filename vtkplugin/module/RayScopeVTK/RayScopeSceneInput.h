// The scene of vtkRayScopeRayTreeSource and vtkRayScopeAccelSource (private
// header): their input datasets, and the vtkRayScopeImageAlgorithm that holds
// the camera, lights, materials and sampling.
#pragma once

#include "vtkSmartPointer.h"

class vtkAlgorithm;
class vtkInformation;
class vtkInformationVector;
class vtkRayScopeImageAlgorithm;

namespace rayscope_vtk {

/// Input port 0 of the ray-tree and structure sources: vtkDataSet, repeatable, and
/// optional (without a connection the scene source's own inputs are used).
void fill_scene_input_port(vtkInformation* info);

/// The scene algorithm of a ray-tree or structure source `self`, its scene updated:
/// `source` (SetSceneSource), or without one `fallback`, a default
/// vtkRayScopeImageAlgorithm made on first use with AutoCamera on. When
/// `inputs` (port 0 of `self`) has datasets, they become the scene
/// algorithm's inputs, replacing its own. Null after an error, reported on
/// `self` with vtkErrorMacro.
vtkRayScopeImageAlgorithm* update_scene(vtkAlgorithm* self, vtkInformationVector* inputs,
                                        vtkRayScopeImageAlgorithm* source,
                                        vtkSmartPointer<vtkRayScopeImageAlgorithm>& fallback);

}  // namespace rayscope_vtk
