#include "vtkRayScopeImageAlgorithm.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <iterator>
#include <stdexcept>

#include "vtkAlgorithmOutput.h"
#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkCompositeDataDisplayAttributes.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMapper.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkScalarsToColors.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"

#include "RayScopeParallel.h"
#include "RayScopeProgressRelay.h"
#include "rayscope/camera.h"
#include "rayscope/render_settings.h"
#include "rayscope/scene.h"
#include "rayscope/stats.h"
#include "rayscope_vtkio/data_arrays.h"
#include "rayscope_vtkio/dataset_leaves.h"
#include "rayscope_vtkio/image_arrays.h"
#include "rayscope_vtkio/mesh_conversion.h"
#include "vtkRayScopeImageAlgorithmInternals.h"

vtkStandardNewMacro(vtkRayScopeImageAlgorithm);

namespace {
double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace
vtkCxxSetObjectMacro(vtkRayScopeImageAlgorithm, LookupTable, vtkScalarsToColors);

vtkRayScopeImageAlgorithm::vtkRayScopeImageAlgorithm()
    : ScalarColoring(COLOR_BY_MAPPER),
      LookupTable(nullptr),
      BalanceTiles(true),
      Progressive(false),
      Internal(new Internals) {
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
}

vtkRayScopeImageAlgorithm::~vtkRayScopeImageAlgorithm() {
  this->SetLookupTable(nullptr);
  delete this->Internal;
}

int vtkRayScopeImageAlgorithm::ResetCamera() {
  const int n = this->GetNumberOfInputConnections(0);
  if (n == 0) {
    vtkErrorMacro(<< "ResetCamera: no input datasets");
    return 0;
  }
  std::vector<vtkDataSet*> inputs;
  for (int i = 0; i < n; ++i) {
    vtkAlgorithmOutput* c = this->GetInputConnection(0, i);
    c->GetProducer()->Update(c->GetIndex());
    const rayscope_vtkio::DatasetLeaves found = rayscope_vtkio::dataset_leaves(
        this->GetInputDataObject(0, i), this->GetInputBlockAttributes(i));
    for (const rayscope_vtkio::DatasetLeaf& leaf : found.leaves) inputs.push_back(leaf.data);
  }
  double b[6];
  if (!rayscope_vtkio::finite_bounds(inputs, b)) {
    vtkErrorMacro(<< "ResetCamera: the inputs have no finite points");
    return 0;
  }
  // Aspect 1: the bounds fill the vertical view angle whatever the image's shape.
  auto dvec3 = [](const double* v) { return rayscope::DVec3(v[0], v[1], v[2]); };
  const rayscope::CameraFit c =
      rayscope::fit_bounds(rayscope::DVec3(b[0], b[2], b[4]), rayscope::DVec3(b[1], b[3], b[5]),
                           dvec3(this->GetPosition()), dvec3(this->GetFocalPoint()),
                           dvec3(this->GetViewUp()), this->GetViewAngle(), 1.0);
  this->SetFocalPoint(c.look_at.x, c.look_at.y, c.look_at.z);
  this->SetPosition(c.eye.x, c.eye.y, c.eye.z);
  this->SetViewUp(c.up.x, c.up.y, c.up.z);
  this->SetParallelScale(c.parallel_scale);
  return 1;
}

vtkRayScopeSceneSettings* vtkRayScopeImageAlgorithm::GetSettings() {
  return this->Internal->settings;
}

void vtkRayScopeImageAlgorithm::SetSettings(vtkRayScopeSceneSettings* settings) {
  if (settings && settings == this->Internal->settings) return;
  this->Internal->settings =
      settings ? settings : vtkSmartPointer<vtkRayScopeSceneSettings>::New().GetPointer();
  this->Modified();
}

void vtkRayScopeImageAlgorithm::SetInputMaterial(int index, vtkRayScopeMaterial* material) {
  if (index < 0) {
    vtkErrorMacro(<< "SetInputMaterial: input index " << index << " is negative");
    return;
  }
  auto& m = this->Internal->input_materials;
  auto it = m.find(index);
  if (!material) {
    if (it == m.end()) return;
    m.erase(it);
  } else {
    if (it != m.end() && it->second == material) return;
    m[index] = material;
  }
  this->Modified();
}

vtkRayScopeMaterial* vtkRayScopeImageAlgorithm::GetInputMaterial(int index) {
  auto it = this->Internal->input_materials.find(index);
  return it == this->Internal->input_materials.end() ? nullptr : it->second.Get();
}

vtkRayScopeMeshConverter* vtkRayScopeImageAlgorithm::GetConverter() {
  return this->Internal->converter;
}

void vtkRayScopeImageAlgorithm::SetInputConverter(int index, vtkRayScopeMeshConverter* converter) {
  if (index < 0) {
    vtkErrorMacro(<< "SetInputConverter: input index " << index << " is negative");
    return;
  }
  auto& m = this->Internal->input_converters;
  auto it = m.find(index);
  if (!converter) {
    if (it == m.end()) return;
    m.erase(it);
  } else {
    if (it != m.end() && it->second == converter) return;
    m[index] = converter;
  }
  this->Modified();
}

vtkRayScopeMeshConverter* vtkRayScopeImageAlgorithm::GetInputConverter(int index) {
  auto it = this->Internal->input_converters.find(index);
  return it == this->Internal->input_converters.end() ? nullptr : it->second.Get();
}

void vtkRayScopeImageAlgorithm::SetInputBlockAttributes(
    int index, vtkCompositeDataDisplayAttributes* attributes) {
  if (index < 0) {
    vtkErrorMacro(<< "SetInputBlockAttributes: input index " << index << " is negative");
    return;
  }
  auto& m = this->Internal->input_block_attributes;
  auto it = m.find(index);
  if (!attributes) {
    if (it == m.end()) return;
    m.erase(it);
  } else {
    if (it != m.end() && it->second == attributes) return;
    m[index] = attributes;
  }
  this->Modified();
}

vtkCompositeDataDisplayAttributes* vtkRayScopeImageAlgorithm::GetInputBlockAttributes(int index) {
  auto it = this->Internal->input_block_attributes.find(index);
  return it == this->Internal->input_block_attributes.end() ? nullptr : it->second.Get();
}

vtkMTimeType vtkRayScopeImageAlgorithm::GetMTime() {
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->LookupTable) t = std::max(t, this->LookupTable->GetMTime());
  t = std::max(t, this->Internal->settings->GetMTime());
  t = std::max(t, this->Internal->converter->GetMTime());
  for (auto& [index, m] : this->Internal->input_materials) t = std::max(t, m->GetMTime());
  for (auto& [index, c] : this->Internal->input_converters) t = std::max(t, c->GetMTime());
  for (auto& [index, a] : this->Internal->input_block_attributes) t = std::max(t, a->GetMTime());
  return t;
}

std::string vtkRayScopeImageAlgorithm::GetInputName(int input) {
  return "input " + std::to_string(input);
}

std::string vtkRayScopeImageAlgorithm::GetObjectName(int object) {
  const auto& objects = this->Internal->builder.GetObjects();
  return object >= 0 && size_t(object) < objects.size() ? objects[size_t(object)].name
                                                        : std::string();
}

std::string vtkRayScopeImageAlgorithm::ValidateParameters() {
  if (std::string e = this->Internal->settings->Validate(); !e.empty()) return e;
  for (auto& [index, mat] : this->Internal->input_materials)
    if (std::string m = mat->Validate(); !m.empty())
      return "material of input " + std::to_string(index) + ": " + m;
  return {};
}

void vtkRayScopeImageAlgorithm::WarnAboutUnconnectedInputs() {
  // Set before the inputs are connected is normal VTK use; still unconnected
  // when the image is made, the setting is probably a wrong index.
  const int n = this->GetNumberOfInputConnections(0);
  auto warn = [&](const char* what, int index) {
    vtkWarningMacro(<< what << " is set for input " << index << ", but only " << n
                    << (n == 1 ? " input is" : " inputs are") << " connected: it is not used");
  };
  for (auto& [index, m] : this->Internal->input_materials)
    if (index >= n) warn("a material (SetInputMaterial)", index);
  for (auto& [index, c] : this->Internal->input_converters)
    if (index >= n) warn("a converter (SetInputConverter)", index);
  for (auto& [index, a] : this->Internal->input_block_attributes)
    if (index >= n) warn("block attributes (SetInputBlockAttributes)", index);
}

rayscope::RenderSettings vtkRayScopeImageAlgorithm::GetRenderSettings() {
  return this->Internal->settings->GetRenderSettings();
}

void vtkRayScopeImageAlgorithm::SetCoreScene(const rayscope::Scene& scene) {
  this->Internal->builder.SetFixedScene(scene);
  const rayscope::Camera& c = scene.camera;
  const rayscope::DVec3 eye = scene.to_world(c.eye), at = scene.to_world(c.look_at);
  this->SetPosition(eye.x, eye.y, eye.z);
  this->SetFocalPoint(at.x, at.y, at.z);
  this->SetViewUp(c.up.x, c.up.y, c.up.z);
  this->SetViewAngle(c.vfov_degrees);
  this->SetParallelProjection(c.parallel);
  this->SetParallelScale(c.parallel_scale);
  this->SetAccel(rayscope::accel_kind_name(scene.accel().kind()).vtk_id);
  this->SetStorage(rayscope_vtkmodule::storage_value_of(scene.accel().storage()));
  this->SetLooseFactor(double(scene.accel().config().loose_factor));
  const glm::uvec3 res = scene.accel().config().grid.resolution;
  this->SetGridResolution(int(res.x), int(res.y), int(res.z));
  this->SetKdSplit(int(scene.accel().config().kdtree.rule));  // the values are the rule's
  this->Modified();
}

void vtkRayScopeImageAlgorithm::FramebufferToImage(const rayscope::Framebuffer& fb,
                                                   const rayscope::RayCounters& counters,
                                                   vtkImageData* image) {
  rayscope_vtkio::framebuffer_to_image(fb, counters, image);
}

rayscope::Scene* vtkRayScopeImageAlgorithm::GetCoreScene() {
  return this->Internal->builder.GetScene();
}

vtkIdType vtkRayScopeImageAlgorithm::GetNumberOfGeometryConversions() {
  return vtkIdType(this->Internal->builder.GetConversions());
}

vtkIdType vtkRayScopeImageAlgorithm::GetNumberOfSceneCommits() {
  return vtkIdType(this->Internal->builder.GetCommits());
}

void vtkRayScopeImageAlgorithm::SetController(vtkMultiProcessController* controller) {
  if (this->Internal->controller == controller) return;
  this->Internal->controller = controller;
  this->Modified();
}

vtkMultiProcessController* vtkRayScopeImageAlgorithm::GetController() {
  return this->Internal->controller;
}

int vtkRayScopeImageAlgorithm::GetNumberOfSceneInputs() {
  return this->Internal->use_gathered ? int(this->Internal->gathered.Get().size())
                                      : this->GetNumberOfInputConnections(0);
}

vtkDataObject* vtkRayScopeImageAlgorithm::GetSceneInput(int index) {
  if (index < 0 || index >= this->GetNumberOfSceneInputs()) return nullptr;
  return this->Internal->use_gathered ? this->Internal->gathered.Get()[size_t(index)].Get()
                                      : this->GetInputDataObject(0, index);
}

int vtkRayScopeImageAlgorithm::BuildScene() {
  vtkMultiProcessController* c = this->Internal->controller;
  if (rayscope_vtkmodule::process_count(c) == 1) {
    this->Internal->use_gathered = false;
    return this->BuildSceneHere();
  }
  // Every process checks the same parameters and builds the same scene from
  // the same gathered pieces: process 0 reports what goes wrong, and all agree
  // on the outcome (an exception, such as running out of memory, may still
  // strike one process alone).
  rayscope_vtkmodule::FirstProcessSpeaks once(c);
  return rayscope_vtkmodule::on_any_process(c, !this->BuildSceneHere()) ? 0 : 1;
}

int vtkRayScopeImageAlgorithm::BuildSceneHere() {
  // The one check of the parameters per update (the settings', then the
  // inputs' own materials).
  vtkMultiProcessController* c = this->Internal->controller;
  const bool parallel = rayscope_vtkmodule::process_count(c) > 1;
  std::string e = this->ValidateParameters();
  if (parallel && rayscope_vtkmodule::on_any_process(c, !e.empty())) {
    if (e.empty()) e = "another process refused the parameters";
  }
  if (!e.empty()) {
    vtkErrorMacro(<< e);
    return 0;
  }
  this->WarnAboutUnconnectedInputs();
  if (parallel) {
    std::vector<vtkDataObject*> local;
    for (int i = 0; i < this->GetNumberOfInputConnections(0); ++i)
      local.push_back(this->GetInputDataObject(0, i));
    std::string why;
    const auto start = std::chrono::steady_clock::now();
    const bool gathered = this->Internal->gathered.Update(c, local, why);
    this->Internal->seconds[0] = seconds_since(start);
    if (!gathered) {
      vtkErrorMacro(<< "gathering the inputs from " << rayscope_vtkmodule::process_count(c)
                    << " processes failed: " << why);
      return 0;
    }
  }
  this->Internal->use_gathered = parallel;
  if (!this->ConfigureColoring()) return 0;
  const auto start = std::chrono::steady_clock::now();
  const int built = this->Internal->builder.Update(this, this->Internal->settings->GetLights());
  this->Internal->seconds[1] = seconds_since(start);
  return built;
}

vtkRayScopeMeshConverter* vtkRayScopeImageAlgorithm::GetConverterOf(int index) {
  if (vtkRayScopeMeshConverter* own = this->GetInputConverter(index)) return own;
  return this->ScalarColoring == COLOR_BY_MAPPER ? this->Internal->converter.Get()
                                                 : this->Internal->coloring_converter.Get();
}

int vtkRayScopeImageAlgorithm::ConfigureColoring() {
  if (this->ScalarColoring == COLOR_BY_MAPPER) return 1;
  vtkRayScopeMeshConverter* from = this->Internal->converter;
  vtkRayScopeMeshConverter* to = this->Internal->coloring_converter;
  to->SetComputeNormals(from->GetComputeNormals());
  to->SetSplitting(from->GetSplitting());
  to->SetFeatureAngle(from->GetFeatureAngle());
  to->SetNonlinearSubdivisionLevel(from->GetNonlinearSubdivisionLevel());
  vtkMapper* mapper = to->GetMapper();  // the converter's own vtkDataSetMapper
  if (this->ScalarColoring == COLOR_SOLID) {
    mapper->ScalarVisibilityOff();
    return 1;
  }
  vtkInformation* array = this->GetInputArrayInformation(0);
  const char* name = array ? array->Get(vtkDataObject::FIELD_NAME()) : nullptr;
  if (!name || !*name) {
    vtkErrorMacro(<< "ScalarColoring is COLOR_BY_ARRAY but no array is chosen: call "
                     "SetInputArrayToProcess(0, 0, 0, association, name)");
    return 0;
  }
  const bool cells =
      array->Has(vtkDataObject::FIELD_ASSOCIATION()) &&
      array->Get(vtkDataObject::FIELD_ASSOCIATION()) == vtkDataObject::FIELD_ASSOCIATION_CELLS;
  mapper->ScalarVisibilityOn();
  mapper->SetColorModeToMapScalars();
  mapper->SetScalarMode(cells ? VTK_SCALAR_MODE_USE_CELL_FIELD_DATA
                              : VTK_SCALAR_MODE_USE_POINT_FIELD_DATA);
  mapper->SelectColorArray(name);
  if (this->LookupTable) {
    mapper->SetLookupTable(this->LookupTable);
    mapper->UseLookupTableScalarRangeOn();
    return 1;
  }
  // VTK's default table over the array's range on every input.
  mapper->SetLookupTable(this->Internal->default_table);
  mapper->UseLookupTableScalarRangeOff();
  double range[2] = {VTK_DOUBLE_MAX, VTK_DOUBLE_MIN};
  for (int i = 0; i < this->GetNumberOfSceneInputs(); ++i)
    for (const rayscope_vtkio::DatasetLeaf& leaf :
         rayscope_vtkio::dataset_leaves(this->GetSceneInput(i), this->GetInputBlockAttributes(i))
             .leaves) {
      vtkDataArray* a = cells ? leaf.data->GetCellData()->GetArray(name)
                              : leaf.data->GetPointData()->GetArray(name);
      if (!a || a->GetNumberOfTuples() == 0) continue;
      double r[2];
      a->GetRange(r, a->GetNumberOfComponents() > 1 ? -1 : 0);
      range[0] = std::min(range[0], r[0]);
      range[1] = std::max(range[1], r[1]);
    }
  if (range[0] <= range[1]) mapper->SetScalarRange(range);
  return 1;
}

int vtkRayScopeImageAlgorithm::UpdateScene() {
  const int n = this->GetNumberOfInputConnections(0);
  for (int i = 0; i < n; ++i) {
    vtkAlgorithmOutput* c = this->GetInputConnection(0, i);
    if (c && c->GetProducer()) c->GetProducer()->Update(c->GetIndex());
  }
  return this->BuildScene();
}

int vtkRayScopeImageAlgorithm::FillInputPortInformation(int port, vtkInformation* info) {
  if (port != 0) return 0;
  // Composite data is taken whole (one scene of all leaves), not block by
  // block as the composite pipeline would run a dataset algorithm.
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  info->Set(vtkAlgorithm::INPUT_IS_REPEATABLE(), 1);
  // Optional for the pipeline: a core scene (SetCoreScene) needs no input;
  // without one, the scene builder reports the missing input.
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkRayScopeImageAlgorithm::RequestInformation(vtkInformation*, vtkInformationVector**,
                                                  vtkInformationVector* outputVector) {
  // The size is checked with the other parameters in RequestData; a bad one
  // gives an empty extent or one RequestData then rejects.
  vtkInformation* out = outputVector->GetInformationObject(0);
  int extent[6] = {0, this->GetWidth() - 1, 0, this->GetHeight() - 1, 0, 0};
  out->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  double spacing[3] = {1.0, 1.0, 1.0}, origin[3] = {0.0, 0.0, 0.0};
  out->Set(vtkDataObject::SPACING(), spacing, 3);
  out->Set(vtkDataObject::ORIGIN(), origin, 3);
  vtkDataObject::SetPointDataActiveScalarInfo(out, VTK_UNSIGNED_CHAR, 3);
  return 1;
}

int vtkRayScopeImageAlgorithm::RequestUpdateExtent(vtkInformation*,
                                                   vtkInformationVector** inputVector,
                                                   vtkInformationVector*) {
  // Every input is needed whole, whatever part of the image is asked for:
  // on one process all of it, on several this process's piece of it (the
  // pieces are gathered in RequestData).
  vtkMultiProcessController* c = this->Internal->controller;
  vtkInformationVector* inputs = inputVector[0];
  for (int i = 0; i < inputs->GetNumberOfInformationObjects(); ++i) {
    vtkInformation* info = inputs->GetInformationObject(i);
    info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(),
              rayscope_vtkmodule::process_index(c));
    info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(),
              rayscope_vtkmodule::process_count(c));
    info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
    if (info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
      info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
                info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
  }
  return 1;
}

int vtkRayScopeImageAlgorithm::RequestData(vtkInformation*, vtkInformationVector**,
                                           vtkInformationVector* outputVector) {
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  if (!output) {
    vtkErrorMacro(<< "no output image");
    return 0;
  }
  output->Initialize();  // empty unless the render succeeds
  this->UpdateProgress(0.0);
  // With several processes every step below is collective, and every process
  // fails together: the pipeline downstream is collective too, and a process
  // that went on would wait for the others forever.
  vtkMultiProcessController* c = this->Internal->controller;
  std::fill(std::begin(this->Internal->seconds), std::end(this->Internal->seconds), 0.0);
  if (rayscope_vtkmodule::process_count(c) > 1) {
    // Process 0's background and ambient light for all: ParaView sets them
    // on the rank that shows the image (its client-server satellites render
    // on black), and every share must be traced alike.
    double colors[6];
    this->GetBackground(colors);
    this->GetAmbientLight(colors + 3);
    c->Broadcast(colors, 6, 0);
    this->SetBackground(colors);
    this->SetAmbientLight(colors + 3);
  }
  if (!this->BuildScene()) return 0;
  const int processes = rayscope_vtkmodule::process_count(c);
  rayscope::RenderSettings settings = this->GetRenderSettings();
  if (!rayscope_vtkmodule::same_on_every_process(
          c, {settings.width, settings.height, settings.samples, settings.max_samples,
              settings.statistics ? 1 : 0})) {
    rayscope_vtkmodule::FirstProcessSpeaks once(c);
    vtkErrorMacro(<< "the " << processes
                  << " processes were asked for images of different sizes or samples: each "
                     "must trace its share of the same image");
    return 0;
  }
  // Go on with the last progressive image, or start a new one: every process
  // decides alike.
  Internals& in = *this->Internal;
  const bool progressive = this->Progressive && settings.max_samples == 0;
  const bool asked = this->GetMTime() == in.refine_mtime;  // by Refine(), nothing since
  bool go_on = progressive && asked && in.go_on && in.progressive.passes() > 0 &&
               settings == in.image_settings &&
               this->GetNumberOfGeometryConversions() == in.image_conversions &&
               this->GetNumberOfSceneCommits() == in.image_commits;
  bool to_the_end = asked && in.to_the_end;
  in.go_on = in.to_the_end = false;
  if (processes > 1) {
    go_on = !rayscope_vtkmodule::on_any_process(c, !go_on);
    to_the_end = rayscope_vtkmodule::on_any_process(c, to_the_end);
  }
  in.image_settings = settings;
  in.image_conversions = this->GetNumberOfGeometryConversions();
  in.image_commits = this->GetNumberOfSceneCommits();
  rayscope::Scene& scene = *this->GetCoreScene();
  bool failed = false;
  if (!go_on) {
    in.progressive = rayscope::ProgressiveImage{};
    if (progressive) in.progressive.restart(settings);
    in.owners = nullptr;
    // With several processes, this one traces its share of the tiles.
    if (processes > 1 && this->BalanceTiles) {
      try {
        in.owners = rayscope_vtkmodule::balanced_owners(c, scene, settings);
      } catch (const std::exception& e) {
        rayscope_vtkmodule::FirstProcessSpeaks once(c);
        vtkErrorMacro(<< "render failed: " << e.what());
        return 0;
      }
    }
  }
  settings.share = {rayscope_vtkmodule::process_index(c), processes, in.owners};
  // The passes to trace now: the whole render, or the progressive image's
  // next pass (or all it lacks; none when it is complete).
  const int left = in.progressive.total() - in.progressive.passes();
  const int passes = !progressive ? 1 : to_the_end ? left : std::min(left, 1);
  rayscope::RayCounters counters;
  rayscope::Framebuffer& fb = in.frame;
  for (int pass = 0; pass < passes; ++pass) {
    const rayscope::RenderSettings traced =
        progressive ? in.progressive.next_pass(settings) : settings;
    rayscope::RayCounters pass_counters;
    auto start = std::chrono::steady_clock::now();
    try {
      rayscope_vtkmodule::render_relaying_progress(
          fb, scene, traced, &pass_counters,
          [&](double p) { this->UpdateProgress((pass + p) / passes); });
    } catch (const std::exception& e) {
      vtkErrorMacro(<< "render failed: " << e.what());
      failed = true;
    }
    in.seconds[2] += seconds_since(start);
    if (processes > 1) {
      if (rayscope_vtkmodule::on_any_process(c, failed)) failed = true;
      if (failed) break;
      // Process 0 makes the image; the others' outputs stay empty.
      start = std::chrono::steady_clock::now();
      rayscope_vtkmodule::assemble_image(c, traced, fb, pass_counters);
      in.seconds[3] += seconds_since(start);
    } else if (failed) {
      break;
    }
    // Every process counts the passes (process 0's image is the assembled
    // one; the others add their own shares, which nobody shows).
    if (progressive) in.progressive.add(fb, pass_counters);
    counters = pass_counters;
  }
  if (failed) {
    in.progressive = rayscope::ProgressiveImage{};
    return 0;
  }
  in.image_mtime = this->GetMTime();
  if (processes > 1 && rayscope_vtkmodule::process_index(c) != 0) return 1;
  if (progressive)
    rayscope_vtkio::framebuffer_to_image(in.progressive.image(), in.progressive.counters(),
                                         in.image, settings.threads);
  else
    rayscope_vtkio::framebuffer_to_image(fb, counters, in.image, settings.threads);
  output->ShallowCopy(in.image);
  if (processes > 1) rayscope_vtkmodule::add_process_array(output, settings);
  const double* t = in.seconds;
  rayscope_vtkio::add_field_tuple<vtkDoubleArray>(output->GetFieldData(), "Seconds",
                                                  {t[0], t[1], t[2], t[3]});
  if (progressive)
    rayscope_vtkio::add_field_tuple<vtkIntArray>(output->GetFieldData(), "ProgressivePasses",
                                                 {in.progressive.passes(), in.progressive.total()});
  this->AddObjectArrays(output);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkRayScopeImageAlgorithm::Refine(bool to_the_end) {
  Internals& in = *this->Internal;
  const bool unchanged = this->GetMTime() == in.image_mtime;
  in.go_on = unchanged;
  in.to_the_end = to_the_end;
  // A complete image of an unchanged scene is final on one process; with
  // several, every update is collective (the others may have changed).
  if (!unchanged || !in.progressive.complete() ||
      rayscope_vtkmodule::process_count(in.controller) > 1)
    this->Modified();
  in.refine_mtime = this->GetMTime();
}

int vtkRayScopeImageAlgorithm::GetImagePasses() {
  return this->Progressive ? this->Internal->progressive.passes() : 1;
}

int vtkRayScopeImageAlgorithm::GetImageTotalPasses() {
  return this->Progressive ? this->Internal->progressive.total() : 1;
}

void vtkRayScopeImageAlgorithm::AddObjectArrays(vtkImageData* image) {
  const auto& objects = this->Internal->builder.GetObjects();
  const auto n = vtkIdType(objects.size());
  auto input = rayscope_vtkio::make_array<vtkIntArray>("ObjectInput", 1, n);
  auto flat = rayscope_vtkio::make_array<vtkIntArray>("ObjectFlatIndex", 1, n);
  auto name = vtkSmartPointer<vtkStringArray>::New();
  name->SetName("ObjectName");
  name->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i) {
    input->SetValue(i, objects[size_t(i)].input);
    flat->SetValue(i, objects[size_t(i)].flat_index);
    name->SetValue(i, objects[size_t(i)].name);
  }
  image->GetFieldData()->AddArray(input);
  image->GetFieldData()->AddArray(flat);
  image->GetFieldData()->AddArray(name);
}

void vtkRayScopeImageAlgorithm::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Settings:\n";
  this->Internal->settings->PrintSelf(os, indent.GetNextIndent());
  os << indent << "ScalarColoring: " << this->ScalarColoring << "\n";
  os << indent << "BalanceTiles: " << this->BalanceTiles << "\n";
  os << indent << "Progressive: " << this->Progressive << "\n";
  os << indent << "LookupTable: " << this->LookupTable << "\n";
  for (auto& [index, m] : this->Internal->input_materials) {
    os << indent << "Material of input " << index << ":\n";
    m->PrintSelf(os, indent.GetNextIndent());
  }
  os << indent << "Converter:\n";
  this->Internal->converter->PrintSelf(os, indent.GetNextIndent());
}
