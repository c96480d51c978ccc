// The scene of vtkRayScopeRayTreeSource, vtkRayScopeAccelSource and
// vtkRayScopeRangeQuery (private header): their input datasets and their scene
// settings, or the vtkRayScopeImageAlgorithm given as their scene source.
#pragma once

#include "vtkSmartPointer.h"

class vtkAlgorithm;
class vtkInformation;
class vtkInformationVector;
class vtkRayScopeImageAlgorithm;
class vtkRayScopeSceneSettings;

namespace rayscope_vtkmodule {

/// Input port 0 of the ray-tree and structure sources: vtkDataSet, repeatable, and
/// optional (without a connection the scene source's own inputs are used).
void fill_scene_input_port(vtkInformation* info);

/// The settings a ray-tree, structure or range-query source starts with: the
/// defaults, with AutoCamera on (the camera fitted to the source's inputs).
vtkSmartPointer<vtkRayScopeSceneSettings> new_source_settings();

/// SetSettings() of those sources: `held` becomes `settings` (null: new
/// source settings). True when it changed.
bool replace_settings(vtkSmartPointer<vtkRayScopeSceneSettings>& held,
                      vtkRayScopeSceneSettings* settings);

/// The scene algorithm of a ray-tree, structure or range-query source `self`,
/// its scene updated: `source` (SetSceneSource), or without one `fallback`, a
/// vtkRayScopeImageAlgorithm made on first use that renders with `settings`. When
/// `inputs` (port 0 of `self`) has datasets, they become the scene
/// algorithm's inputs, replacing its own. Null after an error, reported on
/// `self` with vtkErrorMacro.
vtkRayScopeImageAlgorithm* update_scene(vtkAlgorithm* self, vtkInformationVector* inputs,
                                        vtkRayScopeImageAlgorithm* source,
                                        vtkRayScopeSceneSettings* settings,
                                        vtkSmartPointer<vtkRayScopeImageAlgorithm>& fallback);

}  // namespace rayscope_vtkmodule
