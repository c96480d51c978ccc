/**
 * @class   vtkRayScopeSceneFilter
 * @brief   The base of the filters that explain a RayScope scene:
 *          vtkRayScopeRayTreeSource, vtkRayScopeAccelSource and
 *          vtkRayScopeRangeQuery.
 *
 * Their scene is their input datasets (port 0: one or more vtkDataSets,
 * optional) rendered with their scene settings (GetSettings()), or the scene
 * of a vtkRayScopeImageAlgorithm given as their scene source
 * (SetSceneSource()): its settings, and its inputs unless the filter has
 * inputs of its own, which then replace them. Without inputs or a scene
 * source, a filter's update is an error and its output empty.
 */
#ifndef vtkRayScopeSceneFilter_h
#define vtkRayScopeSceneFilter_h

#include "RayScopeVTKModule.h"  // export macro
#include "vtkPolyDataAlgorithm.h"
#include "vtkSmartPointer.h"  // Settings, DefaultScene

class vtkRayScopeImageAlgorithm;
class vtkRayScopeSceneSettings;

class RAYSCOPEVTK_EXPORT vtkRayScopeSceneFilter : public vtkPolyDataAlgorithm {
 public:
  vtkTypeMacro(vtkRayScopeSceneFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The image algorithm whose scene and settings are used (its inputs are
  /// replaced by this filter's, when it has any); null (default): the
  /// filter's own inputs and settings.
  virtual void SetSceneSource(vtkRayScopeImageAlgorithm*);
  vtkGetObjectMacro(SceneSource, vtkRayScopeImageAlgorithm);
  ///@}

  ///@{
  /// The scene settings (image and sampling, structure, camera, lights,
  /// material; vtkRayScopeSceneSettings), used when there is no scene source.
  /// Never null: each filter starts with its own, AutoCamera on.
  /// SetSettings() shares one settings object with other RayScope filters,
  /// e.g. a vtkRayScopeImageAlgorithm's GetSettings(), so that one change
  /// reaches all of them (null: new defaults).
  vtkRayScopeSceneSettings* GetSettings();
  void SetSettings(vtkRayScopeSceneSettings* settings);
  ///@}

  /// Includes the scene source's and the settings' modification times.
  vtkMTimeType GetMTime() override;

 protected:
  vtkRayScopeSceneFilter();
  ~vtkRayScopeSceneFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;

  /// The scene algorithm of this filter, its scene updated: the scene source,
  /// or a vtkRayScopeImageAlgorithm made on first use that renders the
  /// filter's inputs (`inputs`, port 0 of RequestData) with its settings.
  /// Null after an error, reported with vtkErrorMacro.
  vtkRayScopeImageAlgorithm* UpdateScene(vtkInformationVector* inputs);
  /// Whether this process makes the output: on several processes (the
  /// scene's controller, see vtkRayScopeImageAlgorithm::SetController()) every
  /// one has the whole scene after UpdateScene(), and process 0 alone makes
  /// the output (one ray tree, one set of boxes); the others leave theirs
  /// empty. Always true on one process.
  static bool OutputOnThisProcess(vtkRayScopeImageAlgorithm* scene);

  vtkRayScopeImageAlgorithm* SceneSource;

 private:
  vtkRayScopeSceneFilter(const vtkRayScopeSceneFilter&) = delete;
  void operator=(const vtkRayScopeSceneFilter&) = delete;

  vtkSmartPointer<vtkRayScopeSceneSettings> Settings;
  vtkSmartPointer<vtkRayScopeImageAlgorithm> DefaultScene;
};

#endif
