// vtkRayScopeImageAlgorithm::CopyRenderer(): a vtkRenderer's actors, lights
// and camera as the algorithm's inputs and parameters, with the per-actor
// cache that lets an unchanged actor keep its input (vtkRayScopeRendererCopy.h).
#include <algorithm>
#include <cmath>
#include <vector>

#include "vtkAbstractVolumeMapper.h"
#include "vtkActor.h"
#include "vtkActorCollection.h"
#include "vtkAlgorithmOutput.h"
#include "vtkCamera.h"
#include "vtkCompositePolyDataMapper2.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMapper.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkTransform.h"
#include "vtkTransformFilter.h"
#include "vtkVolume.h"
#include "vtkVolumeCollection.h"

#include "vtkRayScopeImageAlgorithmInternals.h"

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
  std::vector<rayscope_vtkmodule::SceneLight> lights;
  auto headlight = [&](double intensity, const double* color) {
    rayscope_vtkmodule::SceneLight l;
    l.point = false;
    l.headlight = true;
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
    rayscope_vtkmodule::SceneLight l;
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
  this->GetSettings()->SetLights(lights);

  // Volumes are not ray-traced: said once per volume.
  vtkVolumeCollection* volumes = ren->GetVolumes();
  vtkCollectionSimpleIterator vit;
  volumes->InitTraversal(vit);
  while (vtkVolume* volume = volumes->GetNextVolume(vit)) {
    if (!volume->GetVisibility()) continue;
    auto& warned = in.warned_volumes;
    if (std::find(warned.begin(), warned.end(), volume) != warned.end()) continue;
    warned.erase(std::remove(warned.begin(), warned.end(), nullptr), warned.end());
    warned.push_back(volume);
    vtkAbstractVolumeMapper* vm = volume->GetMapper();
    vtkWarningMacro(<< "CopyRenderer: the renderer's vtkVolume (" << volume << ", "
                    << (vm ? vm->GetClassName() : "no mapper")
                    << ") is not drawn: RayScope ray-traces surfaces, lines and points, not "
                       "volumes; show its outer surface (e.g. vtkGeometryFilter) or a contour");
  }

  // Actors.
  for (rayscope_vtkmodule::CopiedActor& e : in.actors) e.used = false;
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
    auto it =
        std::find_if(in.actors.begin(), in.actors.end(),
                     [&](const rayscope_vtkmodule::CopiedActor& e) { return e.actor == actor; });
    if (it == in.actors.end()) {
      rayscope_vtkmodule::CopiedActor e;
      e.actor = actor;
      e.converter = vtkSmartPointer<vtkRayScopeMeshConverter>::New();
      e.material = vtkSmartPointer<vtkRayScopeMaterial>::New();
      in.actors.push_back(e);
      it = in.actors.end() - 1;
    }
    rayscope_vtkmodule::CopiedActor& e = *it;
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
    e.converter->SetLineWidth(actor->GetProperty()->GetLineWidth());
    e.converter->SetPointSize(actor->GetProperty()->GetPointSize());
    e.material->CopyProperty(actor->GetProperty());
    auto* composite = vtkCompositePolyDataMapper2::SafeDownCast(mapper);
    e.block_attributes = composite ? composite->GetCompositeDataDisplayAttributes() : nullptr;
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
    this->SetInputBlockAttributes(int(i), in.actors[entries[i]].block_attributes);
  }
  // Inputs that are gone lose their converters and materials; so do actors.
  for (auto it = in.input_converters.begin(); it != in.input_converters.end();)
    it = it->first >= int(entries.size()) ? in.input_converters.erase(it) : std::next(it);
  for (auto it = in.input_materials.begin(); it != in.input_materials.end();)
    it = it->first >= int(entries.size()) ? in.input_materials.erase(it) : std::next(it);
  for (auto it = in.input_block_attributes.begin(); it != in.input_block_attributes.end();)
    it = it->first >= int(entries.size()) ? in.input_block_attributes.erase(it) : std::next(it);
  in.actors.erase(std::remove_if(in.actors.begin(), in.actors.end(),
                                 [](const rayscope_vtkmodule::CopiedActor& e) { return !e.used; }),
                  in.actors.end());
  return int(connections.size());
}
