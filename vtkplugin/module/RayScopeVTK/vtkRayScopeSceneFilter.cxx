#include "vtkRayScopeSceneFilter.h"

#include <algorithm>
#include <vector>

#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"

#include "RayScopeParallel.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeSceneSettings.h"

vtkCxxSetObjectMacro(vtkRayScopeSceneFilter, SceneSource, vtkRayScopeImageAlgorithm);

namespace {

// What a filter starts with: the defaults, with the camera fitted to its
// inputs.
vtkSmartPointer<vtkRayScopeSceneSettings> new_filter_settings() {
  auto settings = vtkSmartPointer<vtkRayScopeSceneSettings>::New();
  settings->AutoCameraOn();
  return settings;
}

}  // namespace

vtkRayScopeSceneFilter::vtkRayScopeSceneFilter()
    : SceneSource(nullptr), Settings(new_filter_settings()) {
  this->SetNumberOfInputPorts(1);
}

vtkRayScopeSceneFilter::~vtkRayScopeSceneFilter() {
  this->SetSceneSource(nullptr);
}

vtkRayScopeSceneSettings* vtkRayScopeSceneFilter::GetSettings() {
  return this->Settings;
}

void vtkRayScopeSceneFilter::SetSettings(vtkRayScopeSceneSettings* settings) {
  if (settings && settings == this->Settings) return;
  this->Settings =
      settings ? vtkSmartPointer<vtkRayScopeSceneSettings>(settings) : new_filter_settings();
  this->Modified();
}

vtkMTimeType vtkRayScopeSceneFilter::GetMTime() {
  vtkMTimeType t = std::max(this->Superclass::GetMTime(), this->Settings->GetMTime());
  if (this->SceneSource) t = std::max(t, this->SceneSource->GetMTime());
  return t;
}

int vtkRayScopeSceneFilter::FillInputPortInformation(int port, vtkInformation* info) {
  if (port != 0) return 0;
  // Composite data is taken whole, as vtkRayScopeImageAlgorithm takes it.
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  info->Set(vtkAlgorithm::INPUT_IS_REPEATABLE(), 1);
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

vtkRayScopeImageAlgorithm* vtkRayScopeSceneFilter::UpdateScene(vtkInformationVector* inputs) {
  std::vector<vtkDataObject*> data;
  for (int i = 0; inputs && i < inputs->GetNumberOfInformationObjects(); ++i)
    data.push_back(inputs->GetInformationObject(i)->Get(vtkDataObject::DATA_OBJECT()));
  vtkRayScopeImageAlgorithm* scene = this->SceneSource;
  if (!scene) {
    if (data.empty()) {
      vtkErrorMacro(<< "no scene: connect datasets to input port 0 or call "
                       "SetSceneSource(vtkRayScopeImageAlgorithm)");
      return nullptr;
    }
    if (!this->DefaultScene) this->DefaultScene = vtkSmartPointer<vtkRayScopeImageAlgorithm>::New();
    this->DefaultScene->SetSettings(this->Settings);
    scene = this->DefaultScene;
  }
  if (!data.empty()) {
    // Re-connected only when the datasets changed, so that an unchanged input
    // leaves the scene (and its BVH) as it is.
    bool same = scene->GetNumberOfInputConnections(0) == int(data.size());
    for (size_t i = 0; same && i < data.size(); ++i)
      same = scene->GetInputDataObject(0, int(i)) == data[i];
    if (!same) {
      scene->RemoveAllInputConnections(0);
      for (vtkDataObject* d : data) scene->AddInputDataObject(0, d);
    }
  }
  if (!scene->UpdateScene()) {
    vtkErrorMacro(<< "the scene could not be built (see the error before)");
    return nullptr;
  }
  return scene;
}

void vtkRayScopeSceneFilter::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SceneSource: " << this->SceneSource << "\n";
  os << indent << "Settings:\n";
  this->Settings->PrintSelf(os, indent.GetNextIndent());
}

bool vtkRayScopeSceneFilter::OutputOnThisProcess(vtkRayScopeImageAlgorithm* scene) {
  return rayscope_vtkmodule::process_index(scene->GetController()) == 0;
}
