#include "vtkRayScopeSceneSettings.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "vtkCamera.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkSmartPointer.h"

#include "RayScopeSceneBuilder.h"
#include "rayscope/accel/accel_config.h"
#include "rayscope/accel/accel_kind.h"
#include "rayscope/camera.h"
#include "rayscope/light.h"
#include "rayscope/render_settings.h"
#include "vtkRayScopeMaterial.h"

// The Accel values are the core's table's (rayscope/accel/accel_kind.h).
static_assert(vtkRayScopeSceneSettings::ACCEL_BVH ==
                  rayscope::accel_kind_name(rayscope::AccelKind::Bvh).vtk_id &&
              vtkRayScopeSceneSettings::ACCEL_BINARY_BVH ==
                  rayscope::accel_kind_name(rayscope::AccelKind::BinaryBvh).vtk_id &&
              vtkRayScopeSceneSettings::ACCEL_NONE ==
                  rayscope::accel_kind_name(rayscope::AccelKind::None).vtk_id &&
              vtkRayScopeSceneSettings::ACCEL_KDTREE ==
                  rayscope::accel_kind_name(rayscope::AccelKind::KdTree).vtk_id &&
              vtkRayScopeSceneSettings::ACCEL_GRID ==
                  rayscope::accel_kind_name(rayscope::AccelKind::Grid).vtk_id &&
              vtkRayScopeSceneSettings::ACCEL_OCTREE ==
                  rayscope::accel_kind_name(rayscope::AccelKind::Octree).vtk_id &&
              vtkRayScopeSceneSettings::ACCEL_BSP ==
                  rayscope::accel_kind_name(rayscope::AccelKind::Bsp).vtk_id &&
              vtkRayScopeSceneSettings::ACCEL_SPHERES ==
                  rayscope::accel_kind_name(rayscope::AccelKind::Spheres).vtk_id);

vtkStandardNewMacro(vtkRayScopeSceneSettings);

// The Seed setter clamps to 0..VTK_INT_MAX, which is the core's seed range.
static_assert(rayscope::RenderSettings::kMaxSeed == unsigned(VTK_INT_MAX));

struct vtkRayScopeSceneSettings::Internals {
  vtkSmartPointer<vtkRayScopeMaterial> material = vtkSmartPointer<vtkRayScopeMaterial>::New();
  std::vector<Light> lights;
};

bool vtkRayScopeSceneSettings::Light::operator==(const Light& o) const {
  return point == o.point && headlight == o.headlight && std::equal(v, v + 3, o.v) &&
         std::equal(color, color + 3, o.color) && intensity == o.intensity &&
         std::equal(attenuation, attenuation + 3, o.attenuation);
}

vtkRayScopeSceneSettings::vtkRayScopeSceneSettings()
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
      LineRadius(0.0),
      PointRadius(0.0),
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
      Internal(new Internals) {}

vtkRayScopeSceneSettings::~vtkRayScopeSceneSettings() {
  delete this->Internal;
}

void vtkRayScopeSceneSettings::SetSize(int width, int height) {
  this->SetWidth(width);
  this->SetHeight(height);
}

void vtkRayScopeSceneSettings::CopyStructure(vtkRayScopeSceneSettings* other) {
  if (!other || other == this) return;
  this->SetAccel(other->Accel);
  this->SetStorage(other->Storage);
  this->SetLooseFactor(other->LooseFactor);
  this->SetKdSplit(other->KdSplit);
  this->SetGridResolution(other->GridResolution);
}

void vtkRayScopeSceneSettings::CopyCamera(vtkCamera* camera) {
  if (!camera) return;
  this->SetPosition(camera->GetPosition());
  this->SetFocalPoint(camera->GetFocalPoint());
  this->SetViewUp(camera->GetViewUp());
  this->SetViewAngle(camera->GetViewAngle());
  this->SetParallelProjection(camera->GetParallelProjection());
  this->SetParallelScale(camera->GetParallelScale());
}

int vtkRayScopeSceneSettings::AddPointLight(double x, double y, double z, double r, double g,
                                            double b, double intensity) {
  Light l;
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

int vtkRayScopeSceneSettings::AddDirectionalLight(double dx, double dy, double dz, double r,
                                                  double g, double b, double intensity) {
  int i = this->AddPointLight(dx, dy, dz, r, g, b, intensity);
  this->Internal->lights[size_t(i)].point = false;
  return i;
}

void vtkRayScopeSceneSettings::SetLightAttenuation(int index, double constant, double linear,
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

void vtkRayScopeSceneSettings::RemoveAllLights() {
  if (this->Internal->lights.empty()) return;
  this->Internal->lights.clear();
  this->Modified();
}

int vtkRayScopeSceneSettings::AddLight(double type, double x, double y, double z, double r,
                                       double g, double b, double intensity) {
  if (type == double(LIGHT_POINT)) return this->AddPointLight(x, y, z, r, g, b, intensity);
  if (type == double(LIGHT_DIRECTIONAL))
    return this->AddDirectionalLight(x, y, z, r, g, b, intensity);
  vtkErrorMacro(<< "AddLight: type " << type
                << " is neither LIGHT_POINT (0) nor LIGHT_DIRECTIONAL (1)");
  return -1;
}

int vtkRayScopeSceneSettings::GetNumberOfLights() {
  return int(this->Internal->lights.size());
}

const std::vector<vtkRayScopeSceneSettings::Light>& vtkRayScopeSceneSettings::GetLights() {
  return this->Internal->lights;
}

void vtkRayScopeSceneSettings::SetLights(const std::vector<Light>& lights) {
  if (lights == this->Internal->lights) return;
  this->Internal->lights = lights;
  this->Modified();
}

vtkRayScopeMaterial* vtkRayScopeSceneSettings::GetMaterial() {
  return this->Internal->material;
}

void vtkRayScopeSceneSettings::SetMaterial(vtkRayScopeMaterial* material) {
  if (material && material == this->Internal->material) return;
  this->Internal->material =
      material ? material : vtkSmartPointer<vtkRayScopeMaterial>::New().GetPointer();
  this->Modified();
}

vtkMTimeType vtkRayScopeSceneSettings::GetMTime() {
  return std::max(this->Superclass::GetMTime(), this->Internal->material->GetMTime());
}

std::string vtkRayScopeSceneSettings::Validate() {
  try {
    this->GetRenderSettings().validate();
  } catch (const std::invalid_argument& e) {
    return std::string("invalid render settings: ") + e.what();
  }
  auto dvec3 = [](const double* v) { return rayscope::DVec3(v[0], v[1], v[2]); };
  rayscope::CameraNames names;
  names.eye = "Position";
  names.look_at = "FocalPoint";
  names.up = "ViewUp";
  names.fov = "ViewAngle";
  names.parallel_scale = "ParallelScale";
  if (std::string e = rayscope::camera_error(
          dvec3(this->Position), dvec3(this->FocalPoint), dvec3(this->ViewUp), this->ViewAngle,
          this->ParallelProjection != 0, this->ParallelScale, names);
      !e.empty())
    return "camera " + e;
  // VTK colors are sRGB in [0, 1]; the core checks the rest of a light.
  auto unit3 = [](const double* v) {
    for (int k = 0; k < 3; ++k)
      if (!(std::isfinite(v[k]) && v[k] >= 0.0 && v[k] <= 1.0)) return false;
    return true;
  };
  if (!unit3(this->Background)) return "Background components must be in [0, 1]";
  if (!unit3(this->AmbientLight)) return "AmbientLight components must be in [0, 1]";
  const rayscope::DVec3 white(1.0), no_attenuation(1.0, 0.0, 0.0);
  if (std::string e = rayscope::light_error(rayscope::Light::Type::Directional,
                                            dvec3(this->FocalPoint) - dvec3(this->Position), white,
                                            this->HeadlightIntensity, no_attenuation);
      !e.empty())
    return "headlight: " + e;
  for (size_t i = 0; i < this->Internal->lights.size(); ++i) {
    const Light& l = this->Internal->lights[i];
    const std::string name = "light " + std::to_string(i);
    if (!unit3(l.color)) return name + ": color components must be in [0, 1]";
    if (std::string e = rayscope::light_error(
            l.point ? rayscope::Light::Type::Point : rayscope::Light::Type::Directional, dvec3(l.v),
            dvec3(l.color), l.intensity, dvec3(l.attenuation));
        !e.empty())
      return name + ": " + e;
  }
  rayscope::AccelKind kind;
  if (!rayscope::accel_kind_of_vtk_id(this->Accel, kind))
    return "Accel " + std::to_string(this->Accel) + " names no structure of this build";
  if (std::string e =
          rayscope::accel_storage_error(kind, rayscope_vtkmodule::storage_of(this->Storage));
      !e.empty())
    return e;
  if (std::string e = rayscope::loose_factor_error(float(this->LooseFactor)); !e.empty())
    return "LooseFactor: " + e;
  if (!std::isfinite(this->LineRadius) || this->LineRadius < 0.0)
    return "LineRadius must be finite and >= 0 (0: automatic)";
  if (!std::isfinite(this->PointRadius) || this->PointRadius < 0.0)
    return "PointRadius must be finite and >= 0 (0: automatic)";
  for (int r : this->GridResolution)
    if (r < 0) return "GridResolution: cells per axis must be >= 0 (0: automatic)";
  if (std::string e = rayscope::grid_resolution_error(
          rayscope_vtkmodule::grid_resolution_of(this->GridResolution));
      !e.empty())
    return "GridResolution: " + e;
  if (std::string m = this->Internal->material->Validate(); !m.empty())
    return "default material: " + m;
  return {};
}

rayscope::RenderSettings vtkRayScopeSceneSettings::GetRenderSettings() {
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
  // With Cost arrays every ray is traced alone, so that the costs describe
  // the walks that the structure source's visit counts and the ray trees
  // show (both follow single rays); without them, packets (the same image).
  s.packets = !s.statistics;
  return s;
}

void vtkRayScopeSceneSettings::PrintSelf(ostream& os, vtkIndent indent) {
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
  os << indent << "Storage: " << rayscope::to_string(rayscope_vtkmodule::storage_of(this->Storage))
     << "\n";
  os << indent << "LooseFactor: " << this->LooseFactor << "\n";
  os << indent << "LineRadius: " << this->LineRadius << "\n";
  os << indent << "PointRadius: " << this->PointRadius << "\n";
  os << indent << "RadiusArray: " << this->RadiusArray << "\n";
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
  os << indent << "Lights: " << this->Internal->lights.size() << "\n";
  os << indent << "Material:\n";
  this->Internal->material->PrintSelf(os, indent.GetNextIndent());
}
