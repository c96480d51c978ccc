#include "RayScopeSceneBuilder.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <string>

#include "vtkCompositeDataSet.h"
#include "vtkDataSet.h"

#include "rayscope/image.h"
#include "rayscope/render.h"
#include "rayscope_vtkio/dataset_leaves.h"
#include "rayscope_vtkio/line_conversion.h"
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

// The headlight (if on) and the other lights, as core lights; headlights at
// the eye of the scene's camera (placed first).
std::vector<rayscope::Light> core_lights(vtkRayScopeImageAlgorithm* alg,
                                         const std::vector<SceneLight>& lights,
                                         const rayscope::Scene& s) {
  std::vector<rayscope::Light> out;
  const bool shadows = alg->GetShadows() != 0;
  auto headlight = [&](const rayscope::Color& color, double intensity) {
    rayscope::Light l = rayscope::headlight(s.camera, color, float(intensity));
    l.casts_shadows = shadows;
    out.push_back(l);
  };
  if (alg->GetHeadlight()) headlight(rayscope::Color(1.0f), alg->GetHeadlightIntensity());
  for (size_t i = 0; i < lights.size(); ++i) {
    const SceneLight& u = lights[i];
    if (u.headlight) {
      headlight(linear_color(u.color), u.intensity);
      continue;
    }
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

// The material of object `source`: its input's (or the default), with the
// color and opacity its composite mapper's display attributes give the block.
rayscope::Material object_material(vtkRayScopeImageAlgorithm* alg, const ObjectSource& source,
                                   const rayscope_vtkio::DatasetLeaf& leaf) {
  vtkRayScopeMaterial* m = alg->GetInputMaterial(source.input);
  rayscope::Material out = (m ? m : alg->GetMaterial())->ToCore();
  out.name = source.name;
  if (leaf.has_color) out.color = linear_color(leaf.color);
  if (leaf.has_opacity) out.transparency = float(1.0 - std::clamp(leaf.opacity, 0.0, 1.0));
  return out;
}

// The radii of the tubes and spheres of a dataset converted by `converter`:
// the settings' LineRadius and PointRadius, or where those are 0 the
// automatic radius, rayscope_vtkio::automatic_radius(diagonal) times the
// converter's LineWidth or PointSize.
rayscope_vtkio::CurveRadii curve_radii(vtkRayScopeImageAlgorithm* alg,
                                       vtkRayScopeMeshConverter* converter, double diagonal) {
  vtkRayScopeSceneSettings* settings = alg->GetSettings();
  const double automatic = rayscope_vtkio::automatic_radius(diagonal);
  rayscope_vtkio::CurveRadii radii;
  radii.line = settings->GetLineRadius() > 0.0
                   ? settings->GetLineRadius()
                   : automatic * std::max(converter->GetLineWidth(), 0.0);
  radii.point = settings->GetPointRadius() > 0.0
                    ? settings->GetPointRadius()
                    : automatic * std::max(converter->GetPointSize(), 0.0);
  radii.array = settings->GetRadiusArray();
  return radii;
}

// "input 2", or "input 2 block 5 'wall'" for a leaf of a composite input.
std::string object_name(vtkRayScopeImageAlgorithm* alg, int input, vtkDataObject* data,
                        const rayscope_vtkio::DatasetLeaf& leaf) {
  std::string name = alg->GetInputName(input);
  if (data == leaf.data) return name;
  name += " block " + std::to_string(leaf.flat_index);
  if (!leaf.name.empty()) name += " '" + leaf.name + "'";
  return name;
}

}  // namespace

int SceneBuilder::CheckDrawable(vtkRayScopeImageAlgorithm* alg,
                                const std::vector<vtkDataSet*>& data,
                                const std::vector<ObjectSource>& sources,
                                const std::vector<rayscope::TriangleMesh>& meshes,
                                const std::vector<size_t>& tube_of,
                                const std::vector<size_t>& point_of) {
  // What a dataset with nothing to draw is: its class and size tell an empty
  // reader output (0 points) from, e.g., a dataset of polygons of 2 points.
  auto what = [&](size_t i) {
    return sources[i].name + " (" + data[i]->GetClassName() + " with " +
           std::to_string(data[i]->GetNumberOfPoints()) + " points, " +
           std::to_string(data[i]->GetNumberOfCells()) + " cells)";
  };
  if (meshes.empty()) {
    vtkErrorWithObjectMacro(alg, << "nothing to render: the composite inputs hold no dataset");
    return 0;
  }
  std::vector<bool> drawn(meshes.size());
  for (size_t i = 0; i < meshes.size(); ++i) drawn[i] = !meshes[i].triangles.empty();
  for (size_t i : tube_of) drawn[i] = true;
  for (size_t i : point_of) drawn[i] = true;
  const auto n = size_t(std::count(drawn.begin(), drawn.end(), true));
  static constexpr const char* kDrawable = "surface triangles, lines or vertices";
  if (n == 0) {
    vtkErrorWithObjectMacro(alg, << "nothing to render: "
                                 << (meshes.size() == 1 ? what(0) + " has no "
                                                        : std::string("no input dataset or "
                                                                      "block has "))
                                 << kDrawable);
    return 0;
  }
  // An empty dataset (no points) beside others loses nothing and is common
  // (empty blocks of composite data, the placeholder actors of ParaView's
  // representations): left out quietly, as OpenGL draws nothing for it. One
  // with points but nothing to draw is named.
  for (size_t i = 0; i < meshes.size(); ++i)
    if (!drawn[i] && data[i]->GetNumberOfPoints() > 0)
      vtkWarningWithObjectMacro(alg, << what(i) << " has no " << kDrawable << ": it is not shown");
  return 1;
}

void SceneBuilder::SetFixedScene(const rayscope::Scene& scene) {
  this->Scene = scene;
  this->Fixed = true;
  this->HasScene = false;
  this->GeometryInputs.clear();
  this->Objects.clear();
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
  // The settings' values are rayscope::KdSplitRule's.
  static_assert(int(rayscope::KdSplitRule::Sah) == vtkRayScopeSceneSettings::KD_SPLIT_SAH &&
                int(rayscope::KdSplitRule::Median) == vtkRayScopeSceneSettings::KD_SPLIT_MEDIAN &&
                int(rayscope::KdSplitRule::AlternatingMedian) ==
                    vtkRayScopeSceneSettings::KD_SPLIT_ALTERNATING_MEDIAN);
  accel.kdtree.rule = rayscope::KdSplitRule(alg->GetKdSplit());
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
  this->PlaceCamera(alg);
  return this->PrepareCamera(alg);
}

int SceneBuilder::Update(vtkRayScopeImageAlgorithm* alg, const std::vector<SceneLight>& lights) {
  if (this->Fixed) return this->UpdateFixed(alg);
  const int n = alg->GetNumberOfSceneInputs();
  if (n == 0) {
    vtkErrorWithObjectMacro(alg, << "no input: connect at least one vtkDataSet or composite "
                                    "dataset to port 0");
    return 0;
  }
  // The scene objects: every input dataset, and every visible leaf of every
  // composite input, in input order and then flat-index order.
  std::vector<ObjectSource> sources;
  std::vector<rayscope_vtkio::DatasetLeaf> leaves;
  for (int i = 0; i < n; ++i) {
    vtkDataObject* data = alg->GetSceneInput(i);
    if (!vtkDataSet::SafeDownCast(data) && !vtkCompositeDataSet::SafeDownCast(data)) {
      vtkErrorWithObjectMacro(alg, << alg->GetInputName(i) << " is "
                                   << (data ? data->GetClassName() : "missing")
                                   << ", not a vtkDataSet or vtkCompositeDataSet");
      return 0;
    }
    rayscope_vtkio::DatasetLeaves found =
        rayscope_vtkio::dataset_leaves(data, alg->GetInputBlockAttributes(i));
    for (const std::string& skipped : found.skipped)
      vtkWarningWithObjectMacro(
          alg, << alg->GetInputName(i) << " " << skipped << " is not a dataset: it is not shown");
    for (const rayscope_vtkio::DatasetLeaf& leaf : found.leaves) {
      sources.push_back(
          {i, data == leaf.data ? -1 : int(leaf.flat_index), object_name(alg, i, data, leaf)});
      leaves.push_back(leaf);
    }
  }
  const std::vector<vtkDataSet*> datasets = rayscope_vtkio::leaf_datasets(leaves);

  // Geometry is converted again only when a dataset or its converter changed.
  auto converter_of = [&](size_t object) { return alg->GetConverterOf(sources[object].input); };
  vtkRayScopeSceneSettings* settings = alg->GetSettings();
  const CurveSettings curves{settings->GetLineRadius(), settings->GetPointRadius(),
                             settings->GetRadiusArray()};
  bool regeometry = !this->HasScene || datasets != this->GeometryInputs || curves != this->Curves;
  for (size_t i = 0; i < datasets.size(); ++i)
    regeometry |= datasets[i]->GetMTime() > this->GeometryTime.GetMTime() ||
                  converter_of(i)->GetMTime() > this->GeometryTime.GetMTime();
  std::vector<rayscope::TriangleMesh> meshes;
  std::vector<rayscope::TubeSet> tubes;
  std::vector<rayscope::PointSet> points;
  // The dataset of each tube set and point set.
  std::vector<size_t> tube_of = this->TubeOf, point_of = this->PointOf;
  // The local origin (the center of the inputs' bounds, for data far from the
  // world's origin) keeps float's precision there; it changes only with the
  // geometry (a camera move converts nothing).
  rayscope::DVec3 origin = this->Scene.origin;
  if (regeometry) {
    origin = rayscope_vtkio::local_origin(datasets);
    const double o[3] = {origin.x, origin.y, origin.z};
    meshes.resize(datasets.size());
    tube_of.clear();
    point_of.clear();
    // The automatic radius of tubes and spheres is a fraction of this.
    double b[6];
    const double diagonal = rayscope_vtkio::finite_bounds(datasets, b)
                                ? std::hypot(b[1] - b[0], b[3] - b[2], b[5] - b[4])
                                : 1.0;
    for (size_t i = 0; i < datasets.size(); ++i) {
      std::string why;
      rayscope::TubeSet lines;
      rayscope::PointSet vertices;
      if (!converter_of(i)->ConvertToMesh(datasets[i], meshes[i], &why, o) ||
          !converter_of(i)->ConvertLinesAndPoints(
              datasets[i], curve_radii(alg, converter_of(i), diagonal), lines, vertices, why, o)) {
        vtkErrorWithObjectMacro(alg, << sources[i].name << " (" << datasets[i]->GetClassName()
                                     << ") cannot be converted: " << why);
        return 0;
      }
      meshes[i].name = sources[i].name;
      meshes[i].material = uint32_t(i);
      if (!lines.segments.empty()) {
        lines.name = sources[i].name + " lines";
        lines.material = uint32_t(i);
        tubes.push_back(std::move(lines));
        tube_of.push_back(i);
      }
      if (!vertices.positions.empty()) {
        vertices.name = sources[i].name + " vertices";
        vertices.material = uint32_t(i);
        points.push_back(std::move(vertices));
        point_of.push_back(i);
      }
    }
    ++this->Conversions;
    if (!this->CheckDrawable(alg, datasets, sources, meshes, tube_of, point_of)) return 0;
  }

  std::vector<rayscope::Material> materials(sources.size());
  for (size_t i = 0; i < sources.size(); ++i)
    materials[i] = object_material(alg, sources[i], leaves[i]);
  // Other material and light values (a headlight following the camera, a new
  // color) are read while tracing and are simply replaced.
  rayscope::Scene& s = this->Scene;
  if (regeometry) s.origin = origin;
  this->PlaceCamera(alg, datasets);
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
      s.tubes = std::move(tubes);
      s.points = std::move(points);
      this->GeometryInputs.clear();
    }
    s.materials = std::move(materials);
    s.lights = std::move(core);
    if (!this->Commit(alg, accel)) return 0;
    // Input data the scene worked around (non-finite points, normals, colors):
    // rendered without it, reported once per problem and input.
    for (const std::string& w : s.summary().warnings) vtkWarningWithObjectMacro(alg, << w);
    if (regeometry) {
      this->GeometryInputs = datasets;
      this->TubeOf = tube_of;
      this->PointOf = point_of;
      this->Curves = curves;
      this->GeometryTime.Modified();
    }
  }
  // Objects in the scene's order: meshes (one per dataset), tube sets, point sets.
  this->Objects = sources;
  for (size_t i : tube_of) {
    this->Objects.push_back(sources[i]);
    this->Objects.back().name += " lines";
  }
  for (size_t i : point_of) {
    this->Objects.push_back(sources[i]);
    this->Objects.back().name += " vertices";
  }
  s.background = linear_color(alg->GetBackground());
  s.ambient_light = linear_color(alg->GetAmbientLight());
  return this->PrepareCamera(alg);
}

void SceneBuilder::PlaceCamera(vtkRayScopeImageAlgorithm* alg,
                               const std::vector<vtkDataSet*>& data) {
  rayscope::Scene& s = this->Scene;
  const rayscope::DVec3 position = dvec3(alg->GetPosition()), focal = dvec3(alg->GetFocalPoint());
  rayscope::CameraFit c{position, focal, dvec3(alg->GetViewUp()), alg->GetParallelScale()};
  double b[6];
  // Aspect 1: the bounds fill the vertical view angle whatever the image's shape.
  if (alg->GetAutoCamera() && rayscope_vtkio::finite_bounds(data, b))
    c = rayscope::fit_bounds(rayscope::DVec3(b[0], b[2], b[4]), rayscope::DVec3(b[1], b[3], b[5]),
                             position, focal, c.up, alg->GetViewAngle(), 1.0);
  s.camera.eye = s.to_local(c.eye);
  s.camera.look_at = s.to_local(c.look_at);
  s.camera.up = rayscope::Vec3(c.up);
  s.camera.vfov_degrees = float(alg->GetViewAngle());
  s.camera.parallel = alg->GetParallelProjection() != 0;
  s.camera.parallel_scale = float(c.parallel_scale);
}

int SceneBuilder::PrepareCamera(vtkRayScopeImageAlgorithm* alg) {
  rayscope::Scene& s = this->Scene;
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
