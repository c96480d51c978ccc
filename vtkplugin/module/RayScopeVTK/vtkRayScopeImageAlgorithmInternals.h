// The private state of vtkRayScopeImageAlgorithm, shared by its source files
// (vtkRayScopeImageAlgorithm.cxx, vtkRayScopeRendererCopy.cxx). Private header.
#pragma once

#include <map>
#include <vector>

#include "vtkNew.h"
#include "vtkSmartPointer.h"

#include "RayScopeSceneBuilder.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeMaterial.h"
#include "vtkRayScopeMeshConverter.h"
#include "vtkRayScopeRendererCopy.h"

struct vtkRayScopeImageAlgorithm::Internals {
  vtkNew<vtkRayScopeMaterial> material;
  std::map<int, vtkSmartPointer<vtkRayScopeMaterial>> input_materials;
  vtkNew<vtkRayScopeMeshConverter> converter;
  std::map<int, vtkSmartPointer<vtkRayScopeMeshConverter>> input_converters;
  std::vector<rayscope_vtk::SceneLight> lights;
  rayscope_vtk::CopiedActors actors;  // CopyRenderer()'s cache
  rayscope_vtk::SceneBuilder builder;
};
