// The private state of vtkRayScopeImageAlgorithm, shared by its source files
// (vtkRayScopeImageAlgorithm.cxx, vtkRayScopeRendererCopy.cxx). Private header.
#pragma once

#include <map>
#include <memory>
#include <vector>

#include "vtkCompositeDataDisplayAttributes.h"
#include "vtkImageData.h"
#include "vtkLookupTable.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"
#include "vtkVolume.h"
#include "vtkWeakPointer.h"

#include "RayScopeParallel.h"
#include "RayScopeSceneBuilder.h"
#include "rayscope/progressive.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeMaterial.h"
#include "vtkRayScopeMeshConverter.h"
#include "vtkRayScopeRendererCopy.h"
#include "vtkRayScopeSceneSettings.h"

struct vtkRayScopeImageAlgorithm::Internals {
  vtkSmartPointer<vtkRayScopeSceneSettings> settings =
      vtkSmartPointer<vtkRayScopeSceneSettings>::New();
  std::map<int, vtkSmartPointer<vtkRayScopeMaterial>> input_materials;
  vtkNew<vtkRayScopeMeshConverter> converter;
  // Inputs without a converter of their own, when ScalarColoring is not
  // COLOR_BY_MAPPER: `converter`'s settings, a mapper of its own.
  vtkNew<vtkRayScopeMeshConverter> coloring_converter;
  vtkNew<vtkLookupTable> default_table;  // COLOR_BY_ARRAY without LookupTable
  std::map<int, vtkSmartPointer<vtkRayScopeMeshConverter>> input_converters;
  std::map<int, vtkSmartPointer<vtkCompositeDataDisplayAttributes>> input_block_attributes;
  // Volumes CopyRenderer() warned about (once each).
  std::vector<vtkWeakPointer<vtkVolume>> warned_volumes;
  rayscope_vtkmodule::CopiedActors actors;  // CopyRenderer()'s cache
  rayscope_vtkmodule::SceneBuilder builder;
  // The processes that render together (SetController).
  vtkSmartPointer<vtkMultiProcessController> controller =
      vtkMultiProcessController::GetGlobalController();
  // With more than one process: every process's pieces of the inputs, which
  // the scene is made of instead of this process's own (GetSceneInput()).
  rayscope_vtkmodule::GatheredInputs gathered;
  bool use_gathered = false;
  // Seconds of the last update's steps: gather, build, trace, assemble.
  double seconds[4] = {0, 0, 0, 0};
  // Tiles per process of the last image (BalanceTiles), kept while its
  // progressive passes go on.
  std::shared_ptr<const std::vector<int>> owners;
  // Progressive rendering: the image so far, what it was made of, and what
  // Refine() asked of the next update: to go on with this image (when
  // nothing changed since), and to trace all the passes it lacks.
  rayscope::ProgressiveImage progressive;
  // The framebuffer each update renders into, kept so that its memory is
  // not allocated and page-faulted in again for every frame.
  rayscope::Framebuffer frame;
  // The image the output is a shallow copy of: the next update fills its
  // arrays again when nothing downstream kept them, so that a frame does not
  // allocate and page-fault in 32 bytes a pixel of new arrays.
  vtkNew<vtkImageData> image;
  rayscope::RenderSettings image_settings;
  vtkIdType image_conversions = -1, image_commits = -1;
  vtkMTimeType image_mtime = 0, refine_mtime = 0;
  bool go_on = false, to_the_end = false;
};
