#include "vtkRayScopeImageAlgorithm.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include "vtkActor.h"
#include "vtkActorCollection.h"
#include "vtkAlgorithmOutput.h"
#include "vtkCamera.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMapper.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTransform.h"
#include "vtkTransformFilter.h"
#include "vtkTypeInt64Array.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWeakPointer.h"

#include "rayscope/image.h"
#include "rayscope/replay.h"
#include "rayscope/render.h"
#include "rayscope/scene.h"
#include "vtkRayScopeColor.h"
#include "vtkRayScopeMaterial.h"
#include "vtkRayScopeMeshConverter.h"

vtkStandardNewMacro(vtkRayScopeImageAlgorithm);

namespace {

struct UserLight {
  bool point = true;
  double v[3] = {0.0, 0.0, 0.0};  // position or direction
  double color[3] = {1.0, 1.0, 1.0};
  double intensity = 1.0;
  double attenuation[3] = {1.0, 0.0, 0.0};

  bool operator==(const UserLight& o) const {
    return point == o.point && std::equal(v, v + 3, o.v) && std::equal(color, color + 3, o.color) &&
           intensity == o.intensity && std::equal(attenuation, attenuation + 3, o.attenuation);
  }
};

// What CopyRenderer() keeps per actor between calls, so that an unchanged
// actor keeps the same input (no new geometry, no BVH rebuild).
struct ActorEntry {
  vtkWeakPointer<vtkActor> actor;
  vtkSmartPointer<vtkTransformFilter> transform;  // null while the matrix is the identity
  vtkSmartPointer<vtkRayScopeMeshConverter> converter;
  vtkSmartPointer<vtkRayScopeMaterial> material;
  bool used = false;
};

bool same_material(const rayscope::Material& a, const rayscope::Material& b) {
  return a.name == b.name && a.color == b.color && a.ambient == b.ambient &&
         a.diffuse == b.diffuse && a.specular == b.specular &&
         a.specular_color == b.specular_color && a.shininess == b.shininess &&
         a.reflectivity == b.reflectivity && a.transparency == b.transparency && a.ior == b.ior &&
         a.model == b.model && a.checker == b.checker;
}

bool same_light(const rayscope::Light& a, const rayscope::Light& b) {
  return a.type == b.type && a.name == b.name && a.position == b.position &&
         a.direction == b.direction && a.color == b.color && a.intensity == b.intensity &&
         a.attenuation == b.attenuation && a.casts_shadows == b.casts_shadows;
}

template <class T, class Eq>
bool same_list(const std::vector<T>& a, const std::vector<T>& b, Eq eq) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (!eq(a[i], b[i])) return false;
  return true;
}

rayscope::Color linear_color(const double c[3]) {
  return rayscope::Color(rayscope_vtk::srgb_to_linear(c[0]), rayscope_vtk::srgb_to_linear(c[1]),
                         rayscope_vtk::srgb_to_linear(c[2]));
}

rayscope::Vec3 vec3(const double v[3]) {
  return rayscope::Vec3(float(v[0]), float(v[1]), float(v[2]));
}

bool finite3(const double v[3]) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

}  // namespace

struct vtkRayScopeImageAlgorithm::Internals {
  vtkNew<vtkRayScopeMaterial> material;
  std::map<int, vtkSmartPointer<vtkRayScopeMaterial>> input_materials;
  vtkNew<vtkRayScopeMeshConverter> converter;
  std::vector<UserLight> lights;
  std::map<int, vtkSmartPointer<vtkRayScopeMeshConverter>> input_converters;
  std::vector<ActorEntry> actors;  // CopyRenderer()'s cache

  rayscope::Scene scene;
  bool has_scene = false;
  vtkTimeStamp geometry_time;  // when the meshes were last converted
  std::vector<vtkDataSet*> geometry_inputs;
};

vtkRayScopeImageAlgorithm::vtkRayScopeImageAlgorithm()
    : Width(300),
      Height(300),
      Samples(1),
      MaxDepth(5),
      MinContribution(1e-3),
      Threads(0),
      Seed(0),
      ComputeCost(1),
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
      Internal(new Internals) {
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
}

vtkRayScopeImageAlgorithm::~vtkRayScopeImageAlgorithm() {
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
  double b[6];
  vtkMath::UninitializeBounds(b);
  bool any = false;
  for (int i = 0; i < n; ++i) {
    vtkAlgorithmOutput* c = this->GetInputConnection(0, i);
    c->GetProducer()->Update(c->GetIndex());
    auto* ds = vtkDataSet::SafeDownCast(this->GetInputDataObject(0, i));
    if (!ds || ds->GetNumberOfPoints() == 0) continue;
    double db[6];
    ds->GetBounds(db);
    if (!any) {
      std::copy(db, db + 6, b);
      any = true;
    } else {
      for (int k = 0; k < 3; ++k) {
        b[2 * k] = std::min(b[2 * k], db[2 * k]);
        b[2 * k + 1] = std::max(b[2 * k + 1], db[2 * k + 1]);
      }
    }
  }
  if (!any) {
    vtkErrorMacro(<< "ResetCamera: the inputs have no points");
    return 0;
  }
  // vtkRenderer::ResetCamera: a sphere around the bounds fills the view angle.
  double center[3], w[3];
  for (int k = 0; k < 3; ++k) {
    center[k] = 0.5 * (b[2 * k] + b[2 * k + 1]);
    w[k] = b[2 * k + 1] - b[2 * k];
  }
  double radius = 0.5 * std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  if (radius == 0.0) radius = 0.5;
  double vn[3] = {this->Position[0] - this->FocalPoint[0], this->Position[1] - this->FocalPoint[1],
                  this->Position[2] - this->FocalPoint[2]};
  if (!(vtkMath::Normalize(vn) > 0.0)) {
    vn[0] = vn[1] = 0.0;
    vn[2] = 1.0;
  }
  const double angle = vtkMath::RadiansFromDegrees(this->ViewAngle);
  const double distance = radius / std::sin(0.5 * angle);
  double up[3] = {this->ViewUp[0], this->ViewUp[1], this->ViewUp[2]};
  double cross[3];
  vtkMath::Cross(vn, up, cross);
  if (!(vtkMath::Norm(cross) > 1e-6)) {
    up[0] = 0.0;
    up[1] = std::abs(vn[1]) > 0.999 ? 0.0 : 1.0;
    up[2] = std::abs(vn[1]) > 0.999 ? -1.0 : 0.0;
  }
  this->SetFocalPoint(center);
  this->SetPosition(center[0] + distance * vn[0], center[1] + distance * vn[1],
                    center[2] + distance * vn[2]);
  this->SetViewUp(up);
  this->SetParallelScale(radius);
  return 1;
}

int vtkRayScopeImageAlgorithm::AddPointLight(double x, double y, double z, double r, double g,
                                             double b, double intensity) {
  UserLight l;
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

int vtkRayScopeImageAlgorithm::GetNumberOfLights() {
  return int(this->Internal->lights.size());
}

vtkRayScopeMaterial* vtkRayScopeImageAlgorithm::GetMaterial() {
  return this->Internal->material;
}

void vtkRayScopeImageAlgorithm::SetInputMaterial(int index, vtkRayScopeMaterial* material) {
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

namespace {

bool is_identity(vtkMatrix4x4* m) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (m->GetElement(i, j) != (i == j ? 1.0 : 0.0)) return false;
  return true;
}

void copy_converter_settings(vtkRayScopeMeshConverter* from, vtkRayScopeMeshConverter* to) {
  to->SetComputeNormals(from->GetComputeNormals());
  to->SetSplitting(from->GetSplitting());
  to->SetFeatureAngle(from->GetFeatureAngle());
  to->SetNonlinearSubdivisionLevel(from->GetNonlinearSubdivisionLevel());
}

}  // namespace

int vtkRayScopeImageAlgorithm::CopyRenderer(vtkRenderer* ren) {
  if (!ren) {
    vtkErrorMacro(<< "CopyRenderer: the renderer is null");
    return -1;
  }
  Internals& in = *this->Internal;

  // Camera and image.
  vtkCamera* camera = ren->GetActiveCamera();
  const int* size = ren->GetSize();
  const int w = std::max(1, size[0]), h = std::max(1, size[1]);
  this->SetSize(w, h);
  this->CopyCamera(camera);
  if (camera->GetUseHorizontalViewAngle()) {
    const double half = 0.5 * vtkMath::RadiansFromDegrees(camera->GetViewAngle());
    this->SetViewAngle(
        vtkMath::DegreesFromRadians(2.0 * std::atan(std::tan(half) * double(h) / double(w))));
  }
  this->SetBackground(ren->GetBackground());
  this->SetAmbientLight(ren->GetAmbient());

  // Lights, placed where the OpenGL render would place them.
  ren->UpdateLightsGeometryToFollowCamera();
  std::vector<UserLight> lights;
  auto headlight = [&](double intensity, const double* color) {
    UserLight l;
    l.point = false;
    for (int k = 0; k < 3; ++k) {
      l.v[k] = camera->GetFocalPoint()[k] - camera->GetPosition()[k];
      l.color[k] = color[k];
    }
    l.intensity = intensity;
    lights.push_back(l);
  };
  vtkLightCollection* lc = ren->GetLights();
  if (lc->GetNumberOfItems() == 0 && ren->GetAutomaticLightCreation()) {
    const double white[3] = {1.0, 1.0, 1.0};
    headlight(1.0, white);
  }
  vtkCollectionSimpleIterator lit;
  lc->InitTraversal(lit);
  while (vtkLight* light = lc->GetNextLight(lit)) {
    if (!light->GetSwitch()) continue;
    if (light->LightTypeIsHeadlight() && !light->GetPositional()) {
      headlight(light->GetIntensity(), light->GetDiffuseColor());
      continue;
    }
    double p[3], f[3];
    light->GetTransformedPosition(p);
    light->GetTransformedFocalPoint(f);
    UserLight l;
    l.point = light->GetPositional() != 0;
    for (int k = 0; k < 3; ++k) {
      l.v[k] = l.point ? p[k] : f[k] - p[k];
      l.color[k] = light->GetDiffuseColor()[k];
    }
    if (l.point)
      std::copy(light->GetAttenuationValues(), light->GetAttenuationValues() + 3, l.attenuation);
    l.intensity = light->GetIntensity();
    lights.push_back(l);
  }
  this->SetHeadlight(0);
  if (lights != in.lights) {
    in.lights = std::move(lights);
    this->Modified();
  }

  // Actors.
  for (ActorEntry& e : in.actors) e.used = false;
  std::vector<vtkAlgorithmOutput*> connections;
  std::vector<size_t> entries;  // indices into in.actors (which may grow meanwhile)
  vtkActorCollection* actors = ren->GetActors();
  vtkCollectionSimpleIterator ait;
  actors->InitTraversal(ait);
  while (vtkActor* actor = actors->GetNextActor(ait)) {
    vtkMapper* mapper = actor->GetMapper();
    if (!actor->GetVisibility() || !mapper || mapper->GetNumberOfInputConnections(0) < 1) continue;
    vtkAlgorithmOutput* source = mapper->GetInputConnection(0, 0);
    if (!source) continue;
    auto it = std::find_if(in.actors.begin(), in.actors.end(),
                           [&](const ActorEntry& e) { return e.actor == actor; });
    if (it == in.actors.end()) {
      ActorEntry e;
      e.actor = actor;
      e.converter = vtkSmartPointer<vtkRayScopeMeshConverter>::New();
      e.material = vtkSmartPointer<vtkRayScopeMaterial>::New();
      in.actors.push_back(e);
      it = in.actors.end() - 1;
    }
    ActorEntry& e = *it;
    e.used = true;
    vtkMatrix4x4* matrix = actor->GetMatrix();
    vtkAlgorithmOutput* connection = source;
    if (!is_identity(matrix)) {
      if (!e.transform) {
        e.transform = vtkSmartPointer<vtkTransformFilter>::New();
        vtkNew<vtkTransform> t;
        e.transform->SetTransform(t);
      }
      auto* t = static_cast<vtkTransform*>(e.transform->GetTransform());
      vtkMatrix4x4* current = t->GetMatrix();
      bool same = true;
      for (int i = 0; i < 16 && same; ++i) same = current->GetData()[i] == matrix->GetData()[i];
      if (!same) t->SetMatrix(matrix);
      if (e.transform->GetInputConnection(0, 0) != source) e.transform->SetInputConnection(source);
      connection = e.transform->GetOutputPort();
    } else {
      e.transform = nullptr;
    }
    copy_converter_settings(in.converter, e.converter);
    e.converter->SetMapper(mapper);
    e.material->CopyProperty(actor->GetProperty());
    connections.push_back(connection);
    entries.push_back(size_t(it - in.actors.begin()));
  }

  bool same_inputs = int(connections.size()) == this->GetNumberOfInputConnections(0);
  for (size_t i = 0; same_inputs && i < connections.size(); ++i)
    same_inputs = this->GetInputConnection(0, int(i)) == connections[i];
  if (!same_inputs) {
    this->RemoveAllInputConnections(0);
    for (vtkAlgorithmOutput* c : connections) this->AddInputConnection(0, c);
  }
  for (size_t i = 0; i < entries.size(); ++i) {
    this->SetInputConverter(int(i), in.actors[entries[i]].converter);
    this->SetInputMaterial(int(i), in.actors[entries[i]].material);
  }
  // Inputs that are gone lose their converters and materials; so do actors.
  for (auto it = in.input_converters.begin(); it != in.input_converters.end();)
    it = it->first >= int(entries.size()) ? in.input_converters.erase(it) : std::next(it);
  for (auto it = in.input_materials.begin(); it != in.input_materials.end();)
    it = it->first >= int(entries.size()) ? in.input_materials.erase(it) : std::next(it);
  in.actors.erase(std::remove_if(in.actors.begin(), in.actors.end(),
                                 [](const ActorEntry& e) { return !e.used; }),
                  in.actors.end());
  return int(connections.size());
}

vtkMTimeType vtkRayScopeImageAlgorithm::GetMTime() {
  vtkMTimeType t = this->Superclass::GetMTime();
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
  std::ostringstream e;
  if (this->Width < 1 || this->Height < 1 || this->Width > 32768 || this->Height > 32768 ||
      double(this->Width) * double(this->Height) > 268435456.0) {
    e << "image size " << this->Width << "x" << this->Height
      << " is invalid: Width and Height must be in 1..32768 (at most 2^28 pixels)";
    return e.str();
  }
  if (this->Samples < 1 || this->Samples > 64)
    return "Samples must be in 1..64 (N for N x N samples per pixel), got " +
           std::to_string(this->Samples);
  if (this->MaxDepth < 0 || this->MaxDepth > 64)
    return "MaxDepth must be in 0..64, got " + std::to_string(this->MaxDepth);
  if (!std::isfinite(this->MinContribution) || this->MinContribution < 0.0)
    return "MinContribution must be finite and >= 0";
  if (this->Threads < 0 || this->Threads > 1024)
    return "Threads must be in 0..1024 (0: all hardware threads), got " +
           std::to_string(this->Threads);
  if (this->Seed < 0) return "Seed must be >= 0";
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
    const UserLight& l = this->Internal->lights[i];
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
  if (std::string m = this->Internal->material->Validate(); !m.empty())
    return "default material: " + m;
  for (auto& [index, mat] : this->Internal->input_materials)
    if (std::string m = mat->Validate(); !m.empty())
      return "material of input " + std::to_string(index) + ": " + m;
  return {};
}

rayscope::RenderSettings vtkRayScopeImageAlgorithm::GetRenderSettings() {
  rayscope::RenderSettings s;
  s.width = this->Width;
  s.height = this->Height;
  s.samples = this->Samples;
  s.max_depth = this->MaxDepth;
  s.min_contribution = float(this->MinContribution);
  s.threads = this->Threads;
  s.seed = uint32_t(std::max(0, this->Seed));
  s.statistics = this->ComputeCost != 0;
  return s;
}

rayscope::Scene* vtkRayScopeImageAlgorithm::GetCoreScene() {
  return this->Internal->has_scene ? &this->Internal->scene : nullptr;
}

int vtkRayScopeImageAlgorithm::BuildScene() {
  Internals& in = *this->Internal;
  if (std::string e = this->ValidateParameters(); !e.empty()) {
    vtkErrorMacro(<< e);
    return 0;
  }
  const int n = this->GetNumberOfInputConnections(0);
  if (n == 0) {
    vtkErrorMacro(<< "no input: connect at least one vtkDataSet to port 0");
    return 0;
  }
  std::vector<vtkDataSet*> inputs(size_t(n), nullptr);
  for (int i = 0; i < n; ++i) {
    inputs[size_t(i)] = vtkDataSet::SafeDownCast(this->GetInputDataObject(0, i));
    if (!inputs[size_t(i)]) {
      vtkErrorMacro(<< "input " << i << " is not a vtkDataSet");
      return 0;
    }
  }

  // Geometry is converted again only when an input or the converter changed.
  auto converter_of = [&](int i) {
    vtkRayScopeMeshConverter* c = this->GetInputConverter(i);
    return c ? c : in.converter.Get();
  };
  bool regeometry = !in.has_scene || inputs != in.geometry_inputs;
  for (int i = 0; i < n; ++i)
    regeometry |= inputs[size_t(i)]->GetMTime() > in.geometry_time.GetMTime() ||
                  converter_of(i)->GetMTime() > in.geometry_time.GetMTime();
  std::vector<rayscope::TriangleMesh> meshes;
  if (regeometry) {
    meshes.resize(size_t(n));
    for (int i = 0; i < n; ++i) {
      if (!converter_of(i)->ConvertToMesh(inputs[size_t(i)], meshes[size_t(i)])) {
        vtkErrorMacro(<< "input " << i << " could not be converted to triangles");
        return 0;
      }
      meshes[size_t(i)].name = this->GetObjectName(i);
      meshes[size_t(i)].material = uint32_t(i);
    }
  }

  std::vector<rayscope::Material> materials;
  materials.resize(size_t(n));
  for (int i = 0; i < n; ++i) {
    vtkRayScopeMaterial* m = this->GetInputMaterial(i);
    materials[size_t(i)] = (m ? m : in.material.Get())->ToCore();
    materials[size_t(i)].name = this->GetObjectName(i);
  }

  std::vector<rayscope::Light> lights;
  if (this->Headlight) {
    rayscope::Light l;
    l.type = rayscope::Light::Type::Directional;
    l.name = "headlight";
    double d[3] = {this->FocalPoint[0] - this->Position[0], this->FocalPoint[1] - this->Position[1],
                   this->FocalPoint[2] - this->Position[2]};
    vtkMath::Normalize(d);
    l.direction = vec3(d);
    l.color = rayscope::Color(1.0f);
    l.intensity = float(this->HeadlightIntensity);
    l.casts_shadows = this->Shadows != 0;
    lights.push_back(l);
  }
  for (size_t i = 0; i < in.lights.size(); ++i) {
    const UserLight& u = in.lights[i];
    rayscope::Light l;
    l.type = u.point ? rayscope::Light::Type::Point : rayscope::Light::Type::Directional;
    l.name = "light " + std::to_string(i);
    (u.point ? l.position : l.direction) = vec3(u.v);
    l.color = linear_color(u.color);
    l.intensity = float(u.intensity);
    l.attenuation =
        rayscope::Vec3(float(u.attenuation[0]), float(u.attenuation[1]), float(u.attenuation[2]));
    l.casts_shadows = this->Shadows != 0;
    lights.push_back(l);
  }

  // commit() rebuilds the BVH; it is needed for new geometry and whenever
  // what commit() summarises changes (number of lights, whether any material
  // reflects or refracts). Other material and light values (a headlight
  // following the camera, a new color) are read while tracing and are simply
  // replaced.
  rayscope::Scene& s = in.scene;
  bool recommit =
      regeometry || materials.size() != s.materials.size() || lights.size() != s.lights.size();
  for (size_t i = 0; !recommit && i < materials.size(); ++i)
    recommit = materials[i].reflective() != s.materials[i].reflective() ||
               materials[i].refractive() != s.materials[i].refractive();
  if (!recommit) {
    if (!same_list(materials, s.materials, same_material)) s.materials = std::move(materials);
    if (!same_list(lights, s.lights, same_light)) s.lights = std::move(lights);
  } else {
    in.has_scene = false;
    if (regeometry) {
      s.meshes = std::move(meshes);
      in.geometry_inputs.clear();
    }
    s.materials = std::move(materials);
    s.lights = std::move(lights);
    try {
      s.commit();
    } catch (const std::exception& e) {
      vtkErrorMacro(<< "invalid scene: " << e.what());
      return 0;
    }
    // Input data the scene worked around (non-finite points, normals, colors):
    // rendered without it, reported once per problem and input.
    for (const std::string& w : s.summary().warnings) vtkWarningMacro(<< w);
    if (regeometry) {
      in.geometry_inputs = inputs;
      in.geometry_time.Modified();
    }
  }
  s.camera.eye = vec3(this->Position);
  s.camera.look_at = vec3(this->FocalPoint);
  s.camera.up = vec3(this->ViewUp);
  s.camera.vfov_degrees = float(this->ViewAngle);
  s.camera.parallel = this->ParallelProjection != 0;
  s.camera.parallel_scale = float(this->ParallelScale);
  s.background = linear_color(this->Background);
  s.ambient_light = linear_color(this->AmbientLight);
  try {
    rayscope::prepare_frame(s, this->GetRenderSettings());
  } catch (const std::exception& e) {
    vtkErrorMacro(<< "invalid camera or settings: " << e.what());
    return 0;
  }
  in.has_scene = true;
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
  return 1;
}

int vtkRayScopeImageAlgorithm::RequestInformation(vtkInformation*, vtkInformationVector**,
                                                  vtkInformationVector* outputVector) {
  if (std::string e = this->ValidateParameters(); !e.empty()) {
    vtkErrorMacro(<< e);
    return 0;
  }
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

namespace {

vtkSmartPointer<vtkFloatArray> float_array(const char* name, int comps, vtkIdType n) {
  auto a = vtkSmartPointer<vtkFloatArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(comps);
  a->SetNumberOfTuples(n);
  return a;
}

vtkSmartPointer<vtkIntArray> int_array(const char* name, vtkIdType n) {
  auto a = vtkSmartPointer<vtkIntArray>::New();
  a->SetName(name);
  a->SetNumberOfTuples(n);
  return a;
}

void add_counter(vtkFieldData* fd, const char* name, std::initializer_list<uint64_t> values) {
  vtkNew<vtkTypeInt64Array> a;
  a->SetName(name);
  a->SetNumberOfComponents(int(values.size()));
  a->SetNumberOfTuples(1);
  int k = 0;
  for (uint64_t v : values) a->SetTypedComponent(0, k++, vtkTypeInt64(v));
  fd->AddArray(a);
}

}  // namespace

int vtkRayScopeImageAlgorithm::RequestData(vtkInformation*, vtkInformationVector**,
                                           vtkInformationVector* outputVector) {
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  if (!output) {
    vtkErrorMacro(<< "no output image");
    return 0;
  }
  this->UpdateProgress(0.0);
  if (!this->BuildScene()) return 0;
  rayscope::Scene& scene = this->Internal->scene;
  const rayscope::RenderSettings settings = this->GetRenderSettings();

  // The core calls the progress function from its worker threads; observers
  // of ProgressEvent (Python callbacks included) must run on this thread, so
  // the render runs on its own thread while this one relays its progress.
  rayscope::Framebuffer fb;
  rayscope::RayCounters counters;
  std::exception_ptr failure;
  std::mutex mutex;
  std::condition_variable cv;
  size_t done = 0, total = 1;
  bool finished = false;
  std::thread worker([&] {
    try {
      fb = rayscope::render(scene, settings, &counters, [&](size_t d, size_t t) {
        std::lock_guard<std::mutex> lock(mutex);
        done = std::max(done, d);  // calls are serialised but may arrive out of order
        total = t;
        cv.notify_one();
      });
    } catch (...) {
      failure = std::current_exception();
    }
    std::lock_guard<std::mutex> lock(mutex);
    finished = true;
    cv.notify_one();
  });
  {
    double reported = 0.0;
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      cv.wait_for(lock, std::chrono::milliseconds(100));
      if (finished) break;
      // In steps of at least 1%, as VTK's filters report.
      const double p = double(done) / double(std::max<size_t>(total, 1));
      if (p >= reported + 0.01) {
        reported = p;
        lock.unlock();
        this->UpdateProgress(p);
        lock.lock();
      }
    }
  }
  worker.join();
  if (failure) {
    try {
      std::rethrow_exception(failure);
    } catch (const std::exception& e) {
      vtkErrorMacro(<< "render failed: " << e.what());
    }
    return 0;
  }

  const int w = fb.width, h = fb.height;
  const vtkIdType np = vtkIdType(w) * vtkIdType(h);
  output->Initialize();
  output->SetExtent(0, w - 1, 0, h - 1, 0, 0);
  output->SetSpacing(1.0, 1.0, 1.0);
  output->SetOrigin(0.0, 0.0, 0.0);

  vtkNew<vtkUnsignedCharArray> color;
  color->SetName("Color");
  color->SetNumberOfComponents(3);
  color->SetNumberOfTuples(np);
  auto linear = float_array("LinearColor", 3, np);
  auto depth = float_array("Depth", 1, np);
  auto normal = float_array("Normal", 3, np);
  auto object = int_array("ObjectId", np);
  const bool cost = !fb.cost.empty();
  vtkSmartPointer<vtkIntArray> cost_nodes, cost_rays, cost_boxes, cost_prims;
  if (cost) {
    cost_nodes = int_array("Cost", np);
    cost_rays = int_array("CostRays", np);
    cost_boxes = int_array("CostBoxes", np);
    cost_prims = int_array("CostPrimitives", np);
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int j = 0; j < h; ++j) {
    const int y = h - 1 - j;  // VTK row 0 is the bottom row
    for (int x = 0; x < w; ++x) {
      const size_t c = fb.index(x, y);
      const vtkIdType v = vtkIdType(j) * w + x;
      for (int k = 0; k < 3; ++k) {
        const float lin = fb.color[c][k];
        color->SetTypedComponent(
            v, k, (unsigned char)std::lround(255.0f * rayscope::linear_to_srgb(lin)));
        linear->SetTypedComponent(v, k, lin);
        normal->SetTypedComponent(v, k, fb.normal[c][k]);
      }
      depth->SetValue(v, std::isfinite(fb.depth[c]) ? fb.depth[c] : nan);
      object->SetValue(v, int(fb.object_id[c]));
      if (cost) {
        cost_nodes->SetValue(v, int(fb.cost[c].nodes));
        cost_rays->SetValue(v, int(fb.cost[c].rays));
        cost_boxes->SetValue(v, int(fb.cost[c].boxes));
        cost_prims->SetValue(v, int(fb.cost[c].prims));
      }
    }
  }
  vtkPointData* pd = output->GetPointData();
  pd->SetScalars(color);
  pd->AddArray(linear);
  pd->AddArray(depth);
  pd->AddArray(normal);
  pd->AddArray(object);
  if (cost) {
    pd->AddArray(cost_nodes);
    pd->AddArray(cost_rays);
    pd->AddArray(cost_boxes);
    pd->AddArray(cost_prims);
  }
  vtkFieldData* fd = output->GetFieldData();
  add_counter(fd, "RayCounts",
              {counters.rays[0], counters.rays[1], counters.rays[2], counters.rays[3]});
  add_counter(fd, "ShadowRaysOccluded", {counters.shadow_occluded});
  if (cost) {
    add_counter(fd, "NodesVisited", {counters.nodes_visited});
    add_counter(fd, "BoxesTested", {counters.boxes_tested});
    add_counter(fd, "PrimitivesTested", {counters.prims_tested});
  }
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
  os << indent << "Threads: " << this->Threads << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "ComputeCost: " << this->ComputeCost << "\n";
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
