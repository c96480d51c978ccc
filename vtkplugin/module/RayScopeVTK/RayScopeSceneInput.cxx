#include "RayScopeSceneInput.h"

#include <vector>

#include "vtkAlgorithm.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"

#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeSceneSettings.h"

namespace rayscope_vtkmodule {

void fill_scene_input_port(vtkInformation* info) {
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  info->Set(vtkAlgorithm::INPUT_IS_REPEATABLE(), 1);
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
}

vtkSmartPointer<vtkRayScopeSceneSettings> new_source_settings() {
  auto settings = vtkSmartPointer<vtkRayScopeSceneSettings>::New();
  settings->AutoCameraOn();
  return settings;
}

bool replace_settings(vtkSmartPointer<vtkRayScopeSceneSettings>& held,
                      vtkRayScopeSceneSettings* settings) {
  if (settings && settings == held) return false;
  held = settings ? vtkSmartPointer<vtkRayScopeSceneSettings>(settings) : new_source_settings();
  return true;
}

vtkRayScopeImageAlgorithm* update_scene(vtkAlgorithm* self, vtkInformationVector* inputs,
                                        vtkRayScopeImageAlgorithm* source,
                                        vtkRayScopeSceneSettings* settings,
                                        vtkSmartPointer<vtkRayScopeImageAlgorithm>& fallback) {
  std::vector<vtkDataObject*> data;
  for (int i = 0; inputs && i < inputs->GetNumberOfInformationObjects(); ++i)
    data.push_back(inputs->GetInformationObject(i)->Get(vtkDataObject::DATA_OBJECT()));
  vtkRayScopeImageAlgorithm* scene = source;
  if (!scene) {
    if (data.empty()) {
      vtkErrorWithObjectMacro(self, << "no scene: connect datasets to input port 0 or call "
                                       "SetSceneSource(vtkRayScopeImageAlgorithm)");
      return nullptr;
    }
    if (!fallback) fallback = vtkSmartPointer<vtkRayScopeImageAlgorithm>::New();
    fallback->SetSettings(settings);
    scene = fallback;
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
    vtkErrorWithObjectMacro(self, << "the scene could not be built (see the error before)");
    return nullptr;
  }
  return scene;
}

}  // namespace rayscope_vtkmodule
