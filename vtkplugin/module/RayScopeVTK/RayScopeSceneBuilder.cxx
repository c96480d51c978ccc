#include "RayScopeSceneBuilder.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <string>

#include "vtkDataSet.h"
#include "vtkMath.h"

#include "rayscope/image.h"
#include "rayscope/render.h"
#include "rayscope_vtkio/mesh_conversion.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeMaterial.h"
#include "vtkRayScopeMeshConverter.h"

namespace rayscope_vtkmodule {

namespace {

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
  return rayscope::Color(rayscope::srgb_to_linear(c[0]), rayscope::srgb_to_linear(c[1]),
                         rayscope::srgb_to_linear(c[2]));
}

rayscope::Vec3 vec3(const double v[3]) {
  return rayscope::Vec3(float(v[0]), float(v[1]), float(v[2]));
}

rayscope::DVec3 dvec3(const double v[3]) {
  return rayscope::DVec3(v[0], v[1], v[2]);
}

// A VTK world position in the scene's local coordinates (Scene::origin).
rayscope::Vec3 local(const rayscope::Scene& s, const double v[3]) {
  return s.to_local(rayscope::DVec3(v[0], v[1], v[2]));
}

// The headlight (if on) and the other lights, as core lights.
std::vector<rayscope::Light> core_lights(vtkRayScopeImageAlgorithm* alg,
                                         const std::vector<SceneLight>& lights,
                                         const rayscope::Scene& s) {
  std::vector<rayscope::Light> out;
  const bool shadows = alg->GetShadows() != 0;
  if (alg->GetHeadlight()) {
    rayscope::Light l;
    l.type = rayscope::Light::Type::Directional;
    l.name = "headlight";
    const double* p = alg->GetPosition();
    const double* f = alg->GetFocalPoint();
    double d[3] = {f[0] - p[0], f[1] - p[1], f[2] - p[2]};
    vtkMath::Normalize(d);
    l.direction = vec3(d);
    l.color = rayscope::Color(1.0f);
    l.intensity = float(alg->GetHeadlightIntensity());
    l.casts_shadows = shadows;
    out.push_back(l);
  }
  for (size_t i = 0; i < lights.size(); ++i) {
    const SceneLight& u = lights[i];
    rayscope::Light l;
    l.type = u.point ? rayscope::Light::Type::Point : rayscope::Light::Type::Directional;
    l.name = "light " + std::to_string(i);
    (u.point ? l.position : l.direction) = u.point ? local(s, u.v) : vec3(u.v);
    l.color = linear_color(u.color);
    l.intensity = float(u.intensity);
    l.attenuation = vec3(u.attenuation);
    l.casts_shadows = shadows;
    out.push_back(l);
  }
  return out;
}

}  // namespace

int SceneBuilder::CheckTriangles(vtkRayScopeImageAlgorithm* alg,
                                 const std::vector<vtkDataSet*>& inputs,
                                 const std::vector<rayscope::TriangleMesh>& meshes) {
  // What an input without triangles is: its class and size tell an empty
  // reader output (0 points) from a dataset of lines, vertices or a 1-D image.
  auto what = [&](size_t i) {
    return alg->GetObjectName(int(i)) + " (" + inputs[i]->GetClassName() + " with " +
           std::to_string(inputs[i]->GetNumberOfPoints()) + " points, " +
           std::to_string(inputs[i]->GetNumberOfCells()) + " cells)";
  };
  size_t empty = 0;
  for (const rayscope::TriangleMesh& m : meshes) empty += m.triangles.empty();
  if (empty == meshes.size()) {
    vtkErrorWithObjectMacro(
        alg, << "nothing to render: " << (meshes.size() == 1 ? what(0) : std::string("no input"))
             << " has no surface triangles");
    return 0;
  }
  for (size_t i = 0; i < meshes.size(); ++i)
    if (meshes[i].triangles.empty())
      vtkWarningWithObjectMacro(alg, << what(i) << " has no surface triangles: it is not shown");
  return 1;
}

void SceneBuilder::SetFixedScene(const rayscope::Scene& scene) {
  this->Scene = scene;
  this->Fixed = true;
  this->HasScene = false;
  this->GeometryInputs.clear();
}

rayscope::PrimStorage storage_of(int storage) {
  return storage == vtkRayScopeImageAlgorithm::STORAGE_SMALLEST_CELL
             ? rayscope::PrimStorage::SmallestCell
         : storage == vtkRayScopeImageAlgorithm::STORAGE_SPLIT ? rayscope::PrimStorage::Split
                                                               : rayscope::PrimStorage::EveryCell;
}

int storage_value_of(rayscope::PrimStorage storage) {
  return storage == rayscope::PrimStorage::SmallestCell
             ? vtkRayScopeImageAlgorithm::STORAGE_SMALLEST_CELL
         : storage == rayscope::PrimStorage::Split ? vtkRayScopeImageAlgorithm::STORAGE_SPLIT
                                                   : vtkRayScopeImageAlgorithm::STORAGE_EVERY_CELL;
}

glm::uvec3 grid_resolution_of(const int r[3]) {
  return glm::uvec3(uint32_t(std::max(r[0], 0)), uint32_t(std::max(r[1], 0)),
                    uint32_t(std::max(r[2], 0)));
}

rayscope::AccelConfig accel_config_of(vtkRayScopeImageAlgorithm* alg) {
  rayscope::AccelConfig accel;
  if (!rayscope::accel_kind_of_vtk_id(alg->GetAccel(), accel.kind))
    accel.kind = rayscope::AccelConfig{}.kind;
  accel.storage = storage_of(alg->GetStorage());
  accel.loose_factor = float(alg->GetLooseFactor());
  accel.grid.resolution = grid_resolution_of(alg->GetGridResolution());
  accel.kdtree.rule = alg->GetKdSplit() == vtkRayScopeImageAlgorithm::KD_SPLIT_MEDIAN
                          ? rayscope::KdSplitRule::Median
                          : rayscope::KdSplitRule::Sah;
  return accel;
}

static bool same_structure(const rayscope::Aggregate& built, const rayscope::AccelConfig& accel) {
  const rayscope::AccelConfig& c = built.config();
  return c.kind == accel.kind && c.storage == accel.storage &&
         c.loose_factor == accel.loose_factor && c.kdtree.rule == accel.kdtree.rule &&
         c.grid.resolution == accel.grid.resolution;
}

int SceneBuilder::Commit(vtkRayScopeImageAlgorithm* alg, const rayscope::AccelConfig& accel) {
  try {
    this->Scene.commit(accel);
    ++this->Commits;
  } catch (const std::exception& e) {
    vtkErrorWithObjectMacro(alg, << "invalid scene: " << e.what());
    return 0;
  }
  return 1;
}

int SceneBuilder::UpdateFixed(vtkRayScopeImageAlgorithm* alg) {
  rayscope::Scene& s = this->Scene;
  const rayscope::AccelConfig accel = accel_config_of(alg);
  if (!same_structure(s.accel(), accel)) {
    this->HasScene = false;
    if (!this->Commit(alg, accel)) return 0;
  }
  return this->PrepareCamera(alg);
}

int SceneBuilder::Update(vtkRayScopeImageAlgorithm* alg, const std::vector<SceneLight>& lights) {
  if (this->Fixed) return this->UpdateFixed(alg);
  const int n = alg->GetNumberOfInputConnections(0);
  if (n == 0) {
    vtkErrorWithObjectMacro(alg, << "no input: connect at least one vtkDataSet to port 0");
    return 0;
  }
  std::vector<vtkDataSet*> inputs(size_t(n), nullptr);
  for (int i = 0; i < n; ++i) {
    inputs[size_t(i)] = vtkDataSet::SafeDownCast(alg->GetInputDataObject(0, i));
    if (!inputs[size_t(i)]) {
      vtkErrorWithObjectMacro(alg, << "input " << i << " is not a vtkDataSet");
      return 0;
    }
  }

  // Geometry is converted again only when an input or its converter changed.
  auto converter_of = [&](int i) { return alg->GetConverterOf(i); };
  bool regeometry = !this->HasScene || inputs != this->GeometryInputs;
  for (int i = 0; i < n; ++i)
    regeometry |= inputs[size_t(i)]->GetMTime() > this->GeometryTime.GetMTime() ||
                  converter_of(i)->GetMTime() > this->GeometryTime.GetMTime();
  std::vector<rayscope::TriangleMesh> meshes;
  // The local origin (the center of the inputs' bounds, for data far from the
  // world's origin) keeps float's precision there; it changes only with the
  // geometry (a camera move converts nothing).
  rayscope::DVec3 origin = this->Scene.origin;
  if (regeometry) {
    origin = rayscope_vtkio::local_origin(inputs);
    const double o[3] = {origin.x, origin.y, origin.z};
    meshes.resize(size_t(n));
    for (int i = 0; i < n; ++i) {
      std::string why;
      if (!converter_of(i)->ConvertToMesh(inputs[size_t(i)], meshes[size_t(i)], &why, o)) {
        vtkErrorWithObjectMacro(alg, << alg->GetObjectName(i) << " ("
                                     << inputs[size_t(i)]->GetClassName()
                                     << ") cannot be converted to triangles: " << why);
        return 0;
      }
      meshes[size_t(i)].name = alg->GetObjectName(i);
      meshes[size_t(i)].material = uint32_t(i);
    }
    ++this->Conversions;
    if (!this->CheckTriangles(alg, inputs, meshes)) return 0;
  }

  std::vector<rayscope::Material> materials(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    vtkRayScopeMaterial* m = alg->GetInputMaterial(i);
    materials[size_t(i)] = (m ? m : alg->GetMaterial())->ToCore();
    materials[size_t(i)].name = alg->GetObjectName(i);
  }
  // Other material and light values (a headlight following the camera, a new
  // color) are read while tracing and are simply replaced.
  rayscope::Scene& s = this->Scene;
  if (regeometry) s.origin = origin;
  std::vector<rayscope::Light> core = core_lights(alg, lights, s);
  const rayscope::AccelConfig accel = accel_config_of(alg);
  bool recommit = regeometry || materials.size() != s.materials.size() ||
                  core.size() != s.lights.size() || !same_structure(s.accel(), accel);
  for (size_t i = 0; !recommit && i < materials.size(); ++i)
    recommit = materials[i].reflective() != s.materials[i].reflective() ||
               materials[i].refractive() != s.materials[i].refractive();
  if (!recommit) {
    if (!same_list(materials, s.materials, same_material)) s.materials = std::move(materials);
    if (!same_list(core, s.lights, same_light)) s.lights = std::move(core);
  } else {
    this->HasScene = false;
    if (regeometry) {
      s.meshes = std::move(meshes);
      this->GeometryInputs.clear();
    }
    s.materials = std::move(materials);
    s.lights = std::move(core);
    if (!this->Commit(alg, accel)) return 0;
    // Input data the scene worked around (non-finite points, normals, colors):
    // rendered without it, reported once per problem and input.
    for (const std::string& w : s.summary().warnings) vtkWarningWithObjectMacro(alg, << w);
    if (regeometry) {
      this->GeometryInputs = inputs;
      this->GeometryTime.Modified();
    }
  }
  s.background = linear_color(alg->GetBackground());
  s.ambient_light = linear_color(alg->GetAmbientLight());
  return this->PrepareCamera(alg, inputs);
}

int SceneBuilder::PrepareCamera(vtkRayScopeImageAlgorithm* alg,
                                const std::vector<vtkDataSet*>& inputs) {
  rayscope::Scene& s = this->Scene;
  const rayscope::DVec3 position = dvec3(alg->GetPosition()), focal = dvec3(alg->GetFocalPoint());
  rayscope::CameraFit c{position, focal, dvec3(alg->GetViewUp()), alg->GetParallelScale()};
  double b[6];
  // Aspect 1: the bounds fill the vertical view angle whatever the image's shape.
  if (alg->GetAutoCamera() && rayscope_vtkio::finite_bounds(inputs, b))
    c = rayscope::fit_bounds(rayscope::DVec3(b[0], b[2], b[4]), rayscope::DVec3(b[1], b[3], b[5]),
                             position, focal, c.up, alg->GetViewAngle(), 1.0);
  s.camera.eye = s.to_local(c.eye);
  s.camera.look_at = s.to_local(c.look_at);
  s.camera.up = rayscope::Vec3(c.up);
  s.camera.vfov_degrees = float(alg->GetViewAngle());
  s.camera.parallel = alg->GetParallelProjection() != 0;
  s.camera.parallel_scale = float(c.parallel_scale);
  try {
    rayscope::prepare_frame(s, alg->GetRenderSettings());
  } catch (const std::exception& e) {
    vtkErrorWithObjectMacro(alg, << "invalid camera: " << e.what());
    return 0;
  }
  this->HasScene = true;
  return 1;
}

}  // namespace rayscope_vtkmodule
