#include "vtkRayScopeImageAlgorithm.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>

#include "vtkAlgorithmOutput.h"
#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMapper.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkScalarsToColors.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include "RayScopeImageArrays.h"
#include "RayScopeProgressRelay.h"
#include "rayscope/render_settings.h"
#include "rayscope/scene.h"
#include "rayscope/stats.h"
#include "rayscope_vtk/mesh_conversion.h"
#include "vtkRayScopeImageAlgorithmInternals.h"

// The Accel values are the core's table's (rayscope/accel/accel_kind.h).
static_assert(vtkRayScopeImageAlgorithm::ACCEL_BVH ==
                  rayscope::accel_kind_name(rayscope::AccelKind::Bvh).vtk_id &&
              vtkRayScopeImageAlgorithm::ACCEL_BINARY_BVH ==
                  rayscope::accel_kind_name(rayscope::AccelKind::BinaryBvh).vtk_id &&
              vtkRayScopeImageAlgorithm::ACCEL_NONE ==
                  rayscope::accel_kind_name(rayscope::AccelKind::None).vtk_id &&
              vtkRayScopeImageAlgorithm::ACCEL_KDTREE ==
                  rayscope::accel_kind_name(rayscope::AccelKind::KdTree).vtk_id &&
              vtkRayScopeImageAlgorithm::ACCEL_GRID ==
                  rayscope::accel_kind_name(rayscope::AccelKind::Grid).vtk_id &&
              vtkRayScopeImageAlgorithm::ACCEL_OCTREE ==
                  rayscope::accel_kind_name(rayscope::AccelKind::Octree).vtk_id &&
              vtkRayScopeImageAlgorithm::ACCEL_BSP ==
                  rayscope::accel_kind_name(rayscope::AccelKind::Bsp).vtk_id &&
              vtkRayScopeImageAlgorithm::ACCEL_SPHERES ==
                  rayscope::accel_kind_name(rayscope::AccelKind::Spheres).vtk_id);

vtkStandardNewMacro(vtkRayScopeImageAlgorithm);
vtkCxxSetObjectMacro(vtkRayScopeImageAlgorithm, LookupTable, vtkScalarsToColors);

// The Seed setter clamps to 0..VTK_INT_MAX, which is the core's seed range.
static_assert(rayscope::RenderSettings::kMaxSeed == unsigned(VTK_INT_MAX));

namespace {

bool finite3(const double v[3]) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

}  // namespace

vtkRayScopeImageAlgorithm::vtkRayScopeImageAlgorithm()
    : Width(300),
      Height(300),
      Samples(1),
      MaxDepth(5),
      MinContribution(1e-3),
      MaxSamples(0),
      TargetError(0.0),
      TextureFilter(0),
      Threads(0),
      Seed(0),
      ComputeCost(1),
      Accel(ACCEL_BVH),
      Storage(STORAGE_EVERY_CELL),
      LooseFactor(double(rayscope::kDefaultLooseFactor)),
      KdSplit(KD_SPLIT_SAH),
      GridResolution{0, 0, 0},
      Position{0.0, 0.0, 1.0},
      FocalPoint{0.0, 0.0, 0.0},
      ViewUp{0.0, 1.0, 0.0},
      ViewAngle(30.0),
      ParallelProjection(0),
      ParallelScale(1.0),
      Background{0.0, 0.0, 0.0},
      AmbientLight{1.0, 1.0, 1.0},
      Headlight(1),
      HeadlightIntensity(1.0),
      Shadows(1),
      AutoCamera(0),
      ScalarColoring(COLOR_BY_MAPPER),
      LookupTable(nullptr),
      Internal(new Internals) {
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
}

vtkRayScopeImageAlgorithm::~vtkRayScopeImageAlgorithm() {
  this->SetLookupTable(nullptr);
  delete this->Internal;
}

void vtkRayScopeImageAlgorithm::SetSize(int width, int height) {
  this->SetWidth(width);
  this->SetHeight(height);
}

void vtkRayScopeImageAlgorithm::CopyCamera(vtkCamera* camera) {
  if (!camera) return;
  this->SetPosition(camera->GetPosition());
  this->SetFocalPoint(camera->GetFocalPoint());
  this->SetViewUp(camera->GetViewUp());
  this->SetViewAngle(camera->GetViewAngle());
  this->SetParallelProjection(camera->GetParallelProjection());
  this->SetParallelScale(camera->GetParallelScale());
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
    inputs.push_back(vtkDataSet::SafeDownCast(this->GetInputDataObject(0, i)));
  }
  double b[6];
  if (!rayscope_vtk::finite_bounds(inputs, b)) {
    vtkErrorMacro(<< "ResetCamera: the inputs have no finite points");
    return 0;
  }
  const rayscope_vtk::FittedCamera c =
      rayscope_vtk::fit_camera(b, this->Position, this->FocalPoint, this->ViewUp, this->ViewAngle);
  this->SetFocalPoint(c.focal_point);
  this->SetPosition(c.position);
  this->SetViewUp(c.view_up);
  this->SetParallelScale(c.parallel_scale);
  return 1;
}

int vtkRayScopeImageAlgorithm::AddPointLight(double x, double y, double z, double r, double g,
                                             double b, double intensity) {
  rayscope_vtk::SceneLight l;
  l.point = true;
  l.v[0] = x;
  l.v[1] = y;
  l.v[2] = z;
  l.color[0] = r;
  l.color[1] = g;
  l.color[2] = b;
  l.intensity = intensity;
  this->Internal->lights.push_back(l);
  this->Modified();
  return int(this->Internal->lights.size()) - 1;
}

int vtkRayScopeImageAlgorithm::AddDirectionalLight(double dx, double dy, double dz, double r,
                                                   double g, double b, double intensity) {
  int i = this->AddPointLight(dx, dy, dz, r, g, b, intensity);
  this->Internal->lights[size_t(i)].point = false;
  return i;
}

void vtkRayScopeImageAlgorithm::SetLightAttenuation(int index, double constant, double linear,
                                                    double quadratic) {
  if (index < 0 || size_t(index) >= this->Internal->lights.size()) {
    vtkErrorMacro(<< "SetLightAttenuation: no light " << index);
    return;
  }
  double* a = this->Internal->lights[size_t(index)].attenuation;
  if (a[0] == constant && a[1] == linear && a[2] == quadratic) return;
  a[0] = constant;
  a[1] = linear;
  a[2] = quadratic;
  this->Modified();
}

void vtkRayScopeImageAlgorithm::RemoveAllLights() {
  if (this->Internal->lights.empty()) return;
  this->Internal->lights.clear();
  this->Modified();
}

int vtkRayScopeImageAlgorithm::AddLight(double type, double x, double y, double z, double r,
                                        double g, double b, double intensity) {
  if (type == double(LIGHT_POINT)) return this->AddPointLight(x, y, z, r, g, b, intensity);
  if (type == double(LIGHT_DIRECTIONAL))
    return this->AddDirectionalLight(x, y, z, r, g, b, intensity);
  vtkErrorMacro(<< "AddLight: type " << type
                << " is neither LIGHT_POINT (0) nor LIGHT_DIRECTIONAL (1)");
  return -1;
}

int vtkRayScopeImageAlgorithm::GetNumberOfLights() {
  return int(this->Internal->lights.size());
}

vtkRayScopeMaterial* vtkRayScopeImageAlgorithm::GetMaterial() {
  return this->Internal->material;
}

void vtkRayScopeImageAlgorithm::SetMaterial(vtkRayScopeMaterial* material) {
  if (material && material == this->Internal->material) return;
  this->Internal->material =
      material ? material : vtkSmartPointer<vtkRayScopeMaterial>::New().GetPointer();
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

vtkMTimeType vtkRayScopeImageAlgorithm::GetMTime() {
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->LookupTable) t = std::max(t, this->LookupTable->GetMTime());
  t = std::max(t, this->Internal->material->GetMTime());
  t = std::max(t, this->Internal->converter->GetMTime());
  for (auto& [index, m] : this->Internal->input_materials) t = std::max(t, m->GetMTime());
  for (auto& [index, c] : this->Internal->input_converters) t = std::max(t, c->GetMTime());
  return t;
}

std::string vtkRayScopeImageAlgorithm::GetObjectName(int object) {
  return "input " + std::to_string(object);
}

std::string vtkRayScopeImageAlgorithm::ValidateParameters() {
  if (!finite3(this->Position) || !finite3(this->FocalPoint) || !finite3(this->ViewUp))
    return "camera Position, FocalPoint and ViewUp must be finite";
  double d[3] = {this->FocalPoint[0] - this->Position[0], this->FocalPoint[1] - this->Position[1],
                 this->FocalPoint[2] - this->Position[2]};
  if (!(vtkMath::Norm(d) > 0.0)) return "camera Position and FocalPoint coincide";
  double up[3] = {this->ViewUp[0], this->ViewUp[1], this->ViewUp[2]}, c[3];
  vtkMath::Cross(d, up, c);
  if (!(vtkMath::Norm(c) > 1e-12 * vtkMath::Norm(d) * vtkMath::Norm(up)))
    return "camera ViewUp is zero or parallel to the view direction";
  if (!this->ParallelProjection && !(this->ViewAngle > 0.0 && this->ViewAngle < 180.0))
    return "ViewAngle must be in (0, 180) degrees";
  if (this->ParallelProjection &&
      !(std::isfinite(this->ParallelScale) && this->ParallelScale > 0.0))
    return "ParallelScale must be finite and > 0";
  auto unit3 = [](const double* v) {
    for (int k = 0; k < 3; ++k)
      if (!(std::isfinite(v[k]) && v[k] >= 0.0 && v[k] <= 1.0)) return false;
    return true;
  };
  if (!unit3(this->Background)) return "Background components must be in [0, 1]";
  if (!unit3(this->AmbientLight)) return "AmbientLight components must be in [0, 1]";
  if (!(std::isfinite(this->HeadlightIntensity) && this->HeadlightIntensity >= 0.0))
    return "HeadlightIntensity must be finite and >= 0";
  for (size_t i = 0; i < this->Internal->lights.size(); ++i) {
    const rayscope_vtk::SceneLight& l = this->Internal->lights[i];
    const std::string name = "light " + std::to_string(i);
    if (!finite3(l.v)) return name + ": position/direction must be finite";
    if (!l.point && !(vtkMath::Norm(l.v) > 0.0)) return name + ": direction must be non-zero";
    if (!unit3(l.color)) return name + ": color components must be in [0, 1]";
    if (!(std::isfinite(l.intensity) && l.intensity >= 0.0))
      return name + ": intensity must be finite and >= 0";
    for (double a : l.attenuation)
      if (!(std::isfinite(a) && a >= 0.0))
        return name + ": attenuation values must be finite and >= 0";
  }
  rayscope::AccelKind kind;
  if (!rayscope::accel_kind_of_vtk_id(this->Accel, kind))
    return "Accel " + std::to_string(this->Accel) + " names no structure of this build";
  if (std::string e = rayscope::accel_storage_error(kind, rayscope_vtk::storage_of(this->Storage));
      !e.empty())
    return e;
  if (std::string e = rayscope::loose_factor_error(float(this->LooseFactor)); !e.empty())
    return "LooseFactor: " + e;
  for (int r : this->GridResolution)
    if (r < 0) return "GridResolution: cells per axis must be >= 0 (0: automatic)";
  if (std::string e = rayscope::grid_resolution_error(rayscope_vtk::grid_resolution_of(this));
      !e.empty())
    return "GridResolution: " + e;
  if (std::string m = this->Internal->material->Validate(); !m.empty())
    return "default material: " + m;
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
}

rayscope::RenderSettings vtkRayScopeImageAlgorithm::GetRenderSettings() {
  rayscope::RenderSettings s;
  s.width = this->Width;
  s.height = this->Height;
  s.samples = this->Samples;
  s.max_depth = this->MaxDepth;
  s.min_contribution = float(this->MinContribution);
  s.max_samples = this->MaxSamples;
  s.target_error = float(this->TargetError);
  s.texture_filter = this->TextureFilter != 0;
  s.threads = this->Threads;
  s.seed = uint32_t(this->Seed);
  s.statistics = this->ComputeCost != 0;
  return s;
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
  this->SetStorage(rayscope_vtk::storage_value_of(scene.accel().storage()));
  this->SetLooseFactor(double(scene.accel().config().loose_factor));
  const glm::uvec3 res = scene.accel().config().grid.resolution;
  this->SetGridResolution(int(res.x), int(res.y), int(res.z));
  this->SetKdSplit(scene.accel().config().kdtree.rule == rayscope::KdSplitRule::Median
                       ? KD_SPLIT_MEDIAN
                       : KD_SPLIT_SAH);
  this->Modified();
}

void vtkRayScopeImageAlgorithm::FramebufferToImage(const rayscope::Framebuffer& fb,
                                                   const rayscope::RayCounters& counters,
                                                   vtkImageData* image) {
  rayscope_vtk::framebuffer_to_image(fb, counters, image);
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

int vtkRayScopeImageAlgorithm::BuildScene() {
  // The one check of the parameters per update: the render settings by the
  // core's own RenderSettings::validate(), then what only VTK has.
  try {
    this->GetRenderSettings().validate();
  } catch (const std::invalid_argument& e) {
    vtkErrorMacro(<< "invalid render settings: " << e.what());
    return 0;
  }
  if (std::string e = this->ValidateParameters(); !e.empty()) {
    vtkErrorMacro(<< e);
    return 0;
  }
  this->WarnAboutUnconnectedInputs();
  if (!this->ConfigureColoring()) return 0;
  return this->Internal->builder.Update(this, this->Internal->lights);
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
  for (int i = 0; i < this->GetNumberOfInputConnections(0); ++i) {
    auto* ds = vtkDataSet::SafeDownCast(this->GetInputDataObject(0, i));
    vtkDataArray* a = !ds     ? nullptr
                      : cells ? ds->GetCellData()->GetArray(name)
                              : ds->GetPointData()->GetArray(name);
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
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
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
  int extent[6] = {0, this->Width - 1, 0, this->Height - 1, 0, 0};
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
  // Every input is needed whole, whatever part of the image is asked for.
  vtkInformationVector* inputs = inputVector[0];
  for (int i = 0; i < inputs->GetNumberOfInformationObjects(); ++i) {
    vtkInformation* info = inputs->GetInformationObject(i);
    info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
    info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
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
  if (!this->BuildScene()) return 0;
  rayscope::RayCounters counters;
  rayscope::Framebuffer fb;
  try {
    fb = rayscope_vtk::render_relaying_progress(*this->GetCoreScene(), this->GetRenderSettings(),
                                                &counters,
                                                [this](double p) { this->UpdateProgress(p); });
  } catch (const std::exception& e) {
    vtkErrorMacro(<< "render failed: " << e.what());
    return 0;
  }
  rayscope_vtk::framebuffer_to_image(fb, counters, output);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkRayScopeImageAlgorithm::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  auto v3 = [&](const char* name, const double* v) {
    os << indent << name << ": (" << v[0] << ", " << v[1] << ", " << v[2] << ")\n";
  };
  os << indent << "Width: " << this->Width << "\n";
  os << indent << "Height: " << this->Height << "\n";
  os << indent << "Samples: " << this->Samples << "\n";
  os << indent << "MaxDepth: " << this->MaxDepth << "\n";
  os << indent << "MinContribution: " << this->MinContribution << "\n";
  os << indent << "MaxSamples: " << this->MaxSamples << "\n";
  os << indent << "TargetError: " << this->TargetError << "\n";
  os << indent << "TextureFilter: " << this->TextureFilter << "\n";
  os << indent << "Threads: " << this->Threads << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "ComputeCost: " << this->ComputeCost << "\n";
  rayscope::AccelKind kind;
  os << indent << "Accel: "
     << (rayscope::accel_kind_of_vtk_id(this->Accel, kind) ? rayscope::to_string(kind) : "?")
     << "\n";
  os << indent << "Storage: " << rayscope::to_string(rayscope_vtk::storage_of(this->Storage))
     << "\n";
  os << indent << "LooseFactor: " << this->LooseFactor << "\n";
  os << indent << "GridResolution: " << this->GridResolution[0] << " " << this->GridResolution[1]
     << " " << this->GridResolution[2] << "\n";
  os << indent << "KdSplit: " << (this->KdSplit == KD_SPLIT_MEDIAN ? "median" : "sah") << "\n";
  v3("Position", this->Position);
  v3("FocalPoint", this->FocalPoint);
  v3("ViewUp", this->ViewUp);
  os << indent << "ViewAngle: " << this->ViewAngle << "\n";
  os << indent << "ParallelProjection: " << this->ParallelProjection << "\n";
  os << indent << "ParallelScale: " << this->ParallelScale << "\n";
  v3("Background", this->Background);
  v3("AmbientLight", this->AmbientLight);
  os << indent << "Headlight: " << this->Headlight << "\n";
  os << indent << "HeadlightIntensity: " << this->HeadlightIntensity << "\n";
  os << indent << "Shadows: " << this->Shadows << "\n";
  os << indent << "AutoCamera: " << this->AutoCamera << "\n";
  os << indent << "ScalarColoring: " << this->ScalarColoring << "\n";
  os << indent << "LookupTable: " << this->LookupTable << "\n";
  os << indent << "Lights: " << this->Internal->lights.size() << "\n";
  os << indent << "Material:\n";
  this->Internal->material->PrintSelf(os, indent.GetNextIndent());
  for (auto& [index, m] : this->Internal->input_materials) {
    os << indent << "Material of input " << index << ":\n";
    m->PrintSelf(os, indent.GetNextIndent());
  }
  os << indent << "Converter:\n";
  this->Internal->converter->PrintSelf(os, indent.GetNextIndent());
}
