/**
 * @class   vtkRayScopeImageAlgorithm
 * @brief   Ray-traces VTK datasets (Whitted: shadows, reflection, refraction)
 *          into vtkImageData.
 *
 * Input port 0 takes one or more connections (AddInputConnection /
 * AddInputData) of vtkDataSet or composite data (vtkMultiBlockDataSet,
 * vtkPartitionedDataSet, vtkPartitionedDataSetCollection, nested in any way).
 * Every dataset becomes a scene object: an input dataset, and each leaf of a
 * composite input (its empty blocks and blocks hidden by SetInputBlockAttributes()
 * left out). All are traced together, so blocks shadow and reflect each
 * other, and the output is one image. Objects are numbered input by input,
 * a composite input's leaves in flat-index order (vtkDataObjectTreeIterator's);
 * with dataset inputs only, object k is input k. An object is its dataset's
 * surface triangles as vtkRayScopeMeshConverter makes them (colored through the
 * converter's mapper settings), with its input's material (SetInputMaterial)
 * or the default material (GetMaterial()), and the block's color and opacity
 * where the block attributes set them.
 *
 * Input that cannot be rendered is an error (vtkErrorMacro) and leaves the
 * output empty: no input, an input whose cells name points it lacks, or
 * inputs that have no surface triangles at all (an empty dataset, a 1-D
 * image, a reader's output after it failed). An input with points but nothing
 * to draw, next to others that have something, is a warning (vtkWarningMacro);
 * an empty one (no points: an empty block, a placeholder actor of ParaView's
 * representations) is left out quietly. A material or converter set for an
 * input index that is not connected when the image is made is a warning too
 * (it is kept for when that input is connected, and unused until then).
 *
 * The camera follows vtkCamera (Position, FocalPoint, ViewUp, vertical
 * ViewAngle in degrees, ParallelProjection with ParallelScale = half the image
 * height in world units; CopyCamera() takes them from a vtkCamera). Lights are
 * a headlight (a white light at the eye, rayscope::headlight(): a point light
 * at the camera's position, or along the view for a parallel camera, so it
 * casts no shadow the eye can see; on by default) plus any point and
 * directional lights added (CopyRenderer() takes all of this, and the
 * datasets, from a vtkRenderer). Colors are sRGB display values as everywhere in
 * VTK (see vtkRayScopeMeshConverter); shading is computed in linear RGB.
 *
 * The output has extent [0, Width-1] x [0, Height-1] x [0, 0], spacing 1 and
 * origin 0. As in VTK images, pixel (0, 0) is the bottom-left pixel and row j
 * is the core's (and the rayscope command's) row Height-1-j, whose (0, 0) is
 * the top-left pixel. Point data:
 *
 * - "Color": unsigned char RGB, sRGB-encoded exactly as `rayscope render`
 *   writes PNG files (the active scalars).
 * - "LinearColor": float RGB, the linear radiance of the pixel.
 * - "Depth": float distance along the primary ray of sample 0 to the first
 *   hit, NaN on the background.
 * - "Normal": float unit shading normal at that hit, 0 on the background.
 * - "ObjectId": int, the scene object hit by sample 0, -1 on the background
 *   (the input index when every input is a dataset; field data below says
 *   which input and block each object is).
 * - "Cost": int, BVH nodes visited by every ray of the pixel (all samples,
 *   secondary and shadow rays included); with "CostRays", "CostBoxes",
 *   "CostPrimitives". Only when ComputeCost is on (default; it renders with the
 *   core's counting integrator, slightly slower).
 * - "Samples": int, the samples the pixel took. Only with adaptive sampling
 *   (MaxSamples > 0).
 * - "Process": int, the process that traced the pixel. Only when several
 *   processes render together (see SetController()).
 *
 * Field data: "RayCounts" (primary, shadow, reflection, refraction rays),
 * "ShadowRaysOccluded", "NodesVisited", "BoxesTested", "PrimitivesTested";
 * and one tuple per scene object, indexed by ObjectId: "ObjectInput" (int,
 * the input index), "ObjectFlatIndex" (int, the leaf's flat index in its
 * composite input, -1 for a dataset input) and "ObjectName" (string, e.g.
 * "input 1 block 3 'wall'"). "Seconds": the wall-clock time of this update's
 * steps, one tuple of four: gathering the inputs from the other processes (0
 * on one process, and when no process's input changed), building the scene
 * (converting the inputs and building the structure; near 0 when only the
 * camera or settings changed), tracing (this process's share of the image),
 * and assembling the shares on process 0.
 *
 * Progress is reported per finished tile through UpdateProgress (ProgressEvent
 * observers run on the calling thread). Parameters are checked once per
 * update, before rendering: the render settings (size, Samples, MaxDepth,
 * MinContribution, MaxSamples, TargetError, Threads, Seed) by the core's
 * RenderSettings::validate(), whose named limits (rayscope/render_settings.h) the documentation
 * below quotes, the rest by ValidateParameters(). A bad value gives one vtkErrorMacro naming it and
 * an empty output.
 *
 * vtkRayScopeRayTreeSource and vtkRayScopeAccelSource take this algorithm as
 * their scene (SetSceneSource): they see the same scene, camera and sampling.
 * Or they share only the settings (SetSettings(GetSettings())), each with
 * its own inputs.
 */
#ifndef vtkRayScopeImageAlgorithm_h
#define vtkRayScopeImageAlgorithm_h

#include "RayScopeVTKModule.h"  // export macro
#include "vtkImageAlgorithm.h"
#include "vtkRayScopeSceneSettings.h"  // the settings and the shorthands for them

#include <string>  // std::string

class vtkCamera;
class vtkCompositeDataDisplayAttributes;
class vtkDataObject;
class vtkDataSet;
class vtkMultiProcessController;
class vtkRayScopeMaterial;
class vtkRayScopeMeshConverter;
class vtkRenderer;
class vtkScalarsToColors;

#ifndef __VTK_WRAP__
namespace rayscope {
class Scene;
struct RenderSettings;
struct Framebuffer;
struct RayCounters;
}  // namespace rayscope
#endif

class RAYSCOPEVTK_EXPORT vtkRayScopeImageAlgorithm : public vtkImageAlgorithm {
 public:
  static vtkRayScopeImageAlgorithm* New();
  vtkTypeMacro(vtkRayScopeImageAlgorithm, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The scene settings: image size and sampling, acceleration structure,
  /// camera, lights and the default material (never null; each algorithm
  /// starts with its own). SetSettings() shares one settings object between
  /// this algorithm and the ray-tree, structure and range-query filters, so
  /// that one change reaches all of them (null: a new default object).
  vtkRayScopeSceneSettings* GetSettings();
  void SetSettings(vtkRayScopeSceneSettings* settings);
  ///@}

  ///@{
  /// Shorthands for the settings' own methods, documented in
  /// vtkRayScopeSceneSettings: alg->SetSamples(4) is
  /// alg->GetSettings()->SetSamples(4), and the constants are the settings'.
  enum AccelKinds {
    ACCEL_BVH = vtkRayScopeSceneSettings::ACCEL_BVH,
    ACCEL_BINARY_BVH = vtkRayScopeSceneSettings::ACCEL_BINARY_BVH,
    ACCEL_NONE = vtkRayScopeSceneSettings::ACCEL_NONE,
    ACCEL_KDTREE = vtkRayScopeSceneSettings::ACCEL_KDTREE,
    ACCEL_GRID = vtkRayScopeSceneSettings::ACCEL_GRID,
    ACCEL_OCTREE = vtkRayScopeSceneSettings::ACCEL_OCTREE,
    ACCEL_BSP = vtkRayScopeSceneSettings::ACCEL_BSP,
    ACCEL_SPHERES = vtkRayScopeSceneSettings::ACCEL_SPHERES
  };
  enum StorageKinds {
    STORAGE_EVERY_CELL = vtkRayScopeSceneSettings::STORAGE_EVERY_CELL,
    STORAGE_SMALLEST_CELL = vtkRayScopeSceneSettings::STORAGE_SMALLEST_CELL,
    STORAGE_SPLIT = vtkRayScopeSceneSettings::STORAGE_SPLIT
  };
  enum KdSplitRules {
    KD_SPLIT_SAH = vtkRayScopeSceneSettings::KD_SPLIT_SAH,
    KD_SPLIT_MEDIAN = vtkRayScopeSceneSettings::KD_SPLIT_MEDIAN,
    KD_SPLIT_ALTERNATING_MEDIAN = vtkRayScopeSceneSettings::KD_SPLIT_ALTERNATING_MEDIAN
  };
  enum LightTypes {
    LIGHT_POINT = vtkRayScopeSceneSettings::LIGHT_POINT,
    LIGHT_DIRECTIONAL = vtkRayScopeSceneSettings::LIGHT_DIRECTIONAL
  };
  void SetWidth(int v) { this->GetSettings()->SetWidth(v); }
  int GetWidth() { return this->GetSettings()->GetWidth(); }
  void SetHeight(int v) { this->GetSettings()->SetHeight(v); }
  int GetHeight() { return this->GetSettings()->GetHeight(); }
  void SetSamples(int v) { this->GetSettings()->SetSamples(v); }
  int GetSamples() { return this->GetSettings()->GetSamples(); }
  void SetMaxDepth(int v) { this->GetSettings()->SetMaxDepth(v); }
  int GetMaxDepth() { return this->GetSettings()->GetMaxDepth(); }
  void SetMinContribution(double v) { this->GetSettings()->SetMinContribution(v); }
  double GetMinContribution() { return this->GetSettings()->GetMinContribution(); }
  void SetMaxSamples(int v) { this->GetSettings()->SetMaxSamples(v); }
  int GetMaxSamples() { return this->GetSettings()->GetMaxSamples(); }
  void SetTargetError(double v) { this->GetSettings()->SetTargetError(v); }
  double GetTargetError() { return this->GetSettings()->GetTargetError(); }
  void SetTextureFilter(vtkTypeBool v) { this->GetSettings()->SetTextureFilter(v); }
  vtkTypeBool GetTextureFilter() { return this->GetSettings()->GetTextureFilter(); }
  void TextureFilterOn() { this->GetSettings()->TextureFilterOn(); }
  void TextureFilterOff() { this->GetSettings()->TextureFilterOff(); }
  void SetThreads(int v) { this->GetSettings()->SetThreads(v); }
  int GetThreads() { return this->GetSettings()->GetThreads(); }
  void SetSeed(int v) { this->GetSettings()->SetSeed(v); }
  int GetSeed() { return this->GetSettings()->GetSeed(); }
  void SetAccel(int v) { this->GetSettings()->SetAccel(v); }
  int GetAccel() { return this->GetSettings()->GetAccel(); }
  void SetStorage(int v) { this->GetSettings()->SetStorage(v); }
  int GetStorage() { return this->GetSettings()->GetStorage(); }
  void SetLooseFactor(double v) { this->GetSettings()->SetLooseFactor(v); }
  double GetLooseFactor() { return this->GetSettings()->GetLooseFactor(); }
  void SetLineRadius(double v) { this->GetSettings()->SetLineRadius(v); }
  double GetLineRadius() { return this->GetSettings()->GetLineRadius(); }
  void SetPointRadius(double v) { this->GetSettings()->SetPointRadius(v); }
  double GetPointRadius() { return this->GetSettings()->GetPointRadius(); }
  void SetRadiusArray(const char* v) { this->GetSettings()->SetRadiusArray(v); }
  const char* GetRadiusArray() { return this->GetSettings()->GetRadiusArray(); }
  void SetKdSplit(int v) { this->GetSettings()->SetKdSplit(v); }
  int GetKdSplit() { return this->GetSettings()->GetKdSplit(); }
  void SetGridResolution(int x, int y, int z) { this->GetSettings()->SetGridResolution(x, y, z); }
  void SetGridResolution(const int v[3]) { this->GetSettings()->SetGridResolution(v); }
  int* GetGridResolution() VTK_SIZEHINT(3) { return this->GetSettings()->GetGridResolution(); }
  void GetGridResolution(int v[3]) { this->GetSettings()->GetGridResolution(v); }
  void SetComputeCost(vtkTypeBool v) { this->GetSettings()->SetComputeCost(v); }
  vtkTypeBool GetComputeCost() { return this->GetSettings()->GetComputeCost(); }
  void ComputeCostOn() { this->GetSettings()->ComputeCostOn(); }
  void ComputeCostOff() { this->GetSettings()->ComputeCostOff(); }
  void SetPosition(double x, double y, double z) { this->GetSettings()->SetPosition(x, y, z); }
  void SetPosition(const double v[3]) { this->GetSettings()->SetPosition(v); }
  double* GetPosition() VTK_SIZEHINT(3) { return this->GetSettings()->GetPosition(); }
  void GetPosition(double v[3]) { this->GetSettings()->GetPosition(v); }
  void SetFocalPoint(double x, double y, double z) { this->GetSettings()->SetFocalPoint(x, y, z); }
  void SetFocalPoint(const double v[3]) { this->GetSettings()->SetFocalPoint(v); }
  double* GetFocalPoint() VTK_SIZEHINT(3) { return this->GetSettings()->GetFocalPoint(); }
  void GetFocalPoint(double v[3]) { this->GetSettings()->GetFocalPoint(v); }
  void SetViewUp(double x, double y, double z) { this->GetSettings()->SetViewUp(x, y, z); }
  void SetViewUp(const double v[3]) { this->GetSettings()->SetViewUp(v); }
  double* GetViewUp() VTK_SIZEHINT(3) { return this->GetSettings()->GetViewUp(); }
  void GetViewUp(double v[3]) { this->GetSettings()->GetViewUp(v); }
  void SetViewAngle(double v) { this->GetSettings()->SetViewAngle(v); }
  double GetViewAngle() { return this->GetSettings()->GetViewAngle(); }
  void SetParallelProjection(vtkTypeBool v) { this->GetSettings()->SetParallelProjection(v); }
  vtkTypeBool GetParallelProjection() { return this->GetSettings()->GetParallelProjection(); }
  void ParallelProjectionOn() { this->GetSettings()->ParallelProjectionOn(); }
  void ParallelProjectionOff() { this->GetSettings()->ParallelProjectionOff(); }
  void SetParallelScale(double v) { this->GetSettings()->SetParallelScale(v); }
  double GetParallelScale() { return this->GetSettings()->GetParallelScale(); }
  void SetAutoCamera(vtkTypeBool v) { this->GetSettings()->SetAutoCamera(v); }
  vtkTypeBool GetAutoCamera() { return this->GetSettings()->GetAutoCamera(); }
  void AutoCameraOn() { this->GetSettings()->AutoCameraOn(); }
  void AutoCameraOff() { this->GetSettings()->AutoCameraOff(); }
  void SetBackground(double x, double y, double z) { this->GetSettings()->SetBackground(x, y, z); }
  void SetBackground(const double v[3]) { this->GetSettings()->SetBackground(v); }
  double* GetBackground() VTK_SIZEHINT(3) { return this->GetSettings()->GetBackground(); }
  void GetBackground(double v[3]) { this->GetSettings()->GetBackground(v); }
  void SetAmbientLight(double x, double y, double z) {
    this->GetSettings()->SetAmbientLight(x, y, z);
  }
  void SetAmbientLight(const double v[3]) { this->GetSettings()->SetAmbientLight(v); }
  double* GetAmbientLight() VTK_SIZEHINT(3) { return this->GetSettings()->GetAmbientLight(); }
  void GetAmbientLight(double v[3]) { this->GetSettings()->GetAmbientLight(v); }
  void SetHeadlight(vtkTypeBool v) { this->GetSettings()->SetHeadlight(v); }
  vtkTypeBool GetHeadlight() { return this->GetSettings()->GetHeadlight(); }
  void HeadlightOn() { this->GetSettings()->HeadlightOn(); }
  void HeadlightOff() { this->GetSettings()->HeadlightOff(); }
  void SetHeadlightIntensity(double v) { this->GetSettings()->SetHeadlightIntensity(v); }
  double GetHeadlightIntensity() { return this->GetSettings()->GetHeadlightIntensity(); }
  void SetShadows(vtkTypeBool v) { this->GetSettings()->SetShadows(v); }
  vtkTypeBool GetShadows() { return this->GetSettings()->GetShadows(); }
  void ShadowsOn() { this->GetSettings()->ShadowsOn(); }
  void ShadowsOff() { this->GetSettings()->ShadowsOff(); }
  void SetSize(int width, int height) { this->GetSettings()->SetSize(width, height); }
  void SetAccelToBvh() { this->GetSettings()->SetAccelToBvh(); }
  void SetAccelToBinaryBvh() { this->GetSettings()->SetAccelToBinaryBvh(); }
  void SetAccelToNone() { this->GetSettings()->SetAccelToNone(); }
  void SetAccelToKdTree() { this->GetSettings()->SetAccelToKdTree(); }
  void SetAccelToGrid() { this->GetSettings()->SetAccelToGrid(); }
  void SetAccelToOctree() { this->GetSettings()->SetAccelToOctree(); }
  void SetAccelToBsp() { this->GetSettings()->SetAccelToBsp(); }
  void SetAccelToSpheres() { this->GetSettings()->SetAccelToSpheres(); }
  void SetStorageToEveryCell() { this->GetSettings()->SetStorageToEveryCell(); }
  void SetStorageToSmallestCell() { this->GetSettings()->SetStorageToSmallestCell(); }
  void SetStorageToSplit() { this->GetSettings()->SetStorageToSplit(); }
  void SetKdSplitToSah() { this->GetSettings()->SetKdSplitToSah(); }
  void SetKdSplitToMedian() { this->GetSettings()->SetKdSplitToMedian(); }
  void SetKdSplitToAlternatingMedian() { this->GetSettings()->SetKdSplitToAlternatingMedian(); }
  void CopyCamera(vtkCamera* camera) { this->GetSettings()->CopyCamera(camera); }
  int AddPointLight(double x, double y, double z, double r, double g, double b, double intensity) {
    return this->GetSettings()->AddPointLight(x, y, z, r, g, b, intensity);
  }
  int AddDirectionalLight(double dx, double dy, double dz, double r, double g, double b,
                          double intensity) {
    return this->GetSettings()->AddDirectionalLight(dx, dy, dz, r, g, b, intensity);
  }
  int AddLight(double type, double x, double y, double z, double r, double g, double b,
               double intensity) {
    return this->GetSettings()->AddLight(type, x, y, z, r, g, b, intensity);
  }
  void RemoveAllLights() { this->GetSettings()->RemoveAllLights(); }
  int GetNumberOfLights() { return this->GetSettings()->GetNumberOfLights(); }
  void SetLightAttenuation(int index, double constant, double linear, double quadratic) {
    this->GetSettings()->SetLightAttenuation(index, constant, linear, quadratic);
  }
  vtkRayScopeMaterial* GetMaterial() { return this->GetSettings()->GetMaterial(); }
  void SetMaterial(vtkRayScopeMaterial* material) { this->GetSettings()->SetMaterial(material); }
  ///@}

  /// Points the camera at the bounds of all inputs, as vtkRenderer::ResetCamera
  /// does (looking down -z with +y up, or along the current view direction
  /// when the camera is valid). Updates the inputs. Returns 0 without inputs.
  int ResetCamera();
  /// Gives input `index` (>= 0; negative is an error) its own material (null:
  /// back to the default). An index with no input connected at RequestData is
  /// a warning there.
  void SetInputMaterial(int index, vtkRayScopeMaterial* material);
  vtkRayScopeMaterial* GetInputMaterial(int index);

  /// How datasets become triangles, normals and colors (never null).
  vtkRayScopeMeshConverter* GetConverter();
  /// Gives input `index` its own converter, e.g. with the mapper that colors it
  /// in a renderer (null: back to GetConverter()). Index rules as
  /// SetInputMaterial().
  void SetInputConverter(int index, vtkRayScopeMeshConverter* converter);
  vtkRayScopeMeshConverter* GetInputConverter(int index);

  /// Gives composite input `index` the block visibility, color and opacity of
  /// a composite mapper (vtkCompositeDataDisplayAttributes, as
  /// vtkCompositePolyDataMapper2 uses them: a block's setting applies to its
  /// sub-blocks unless they set their own). Hidden blocks are not in the
  /// scene; a block color replaces the material color, a block opacity the
  /// material's transparency (1 - opacity). Null: every block as its input.
  /// Index rules as SetInputMaterial().
  void SetInputBlockAttributes(int index, vtkCompositeDataDisplayAttributes* attributes);
  vtkCompositeDataDisplayAttributes* GetInputBlockAttributes(int index);

  ///@{
  /// How inputs without a converter of their own are colored:
  /// - COLOR_BY_MAPPER (default): as GetConverter()'s mapper colors them, i.e.
  ///   as a VTK mapper would (by default the active scalars through VTK's
  ///   default lookup table over [0, 1]);
  /// - COLOR_SOLID: the material color only, scalars ignored;
  /// - COLOR_BY_ARRAY: the array chosen with SetInputArrayToProcess(0, 0, 0,
  ///   association, name) (point or cell data) mapped through LookupTable
  ///   over the table's own range; without a table, through VTK's default
  ///   table over the array's range on all inputs (the magnitude's for
  ///   vectors). An input without that array gets its material color.
  /// GetConverter()'s normals settings apply in every mode.
  enum ScalarColorings { COLOR_BY_MAPPER = 0, COLOR_SOLID = 1, COLOR_BY_ARRAY = 2 };
  vtkSetClampMacro(ScalarColoring, int, COLOR_BY_MAPPER, COLOR_BY_ARRAY);
  vtkGetMacro(ScalarColoring, int);
  virtual void SetLookupTable(vtkScalarsToColors*);
  vtkGetObjectMacro(LookupTable, vtkScalarsToColors);
  ///@}

  /**
   * Makes this algorithm's scene the scene of a vtkRenderer, as VTK would draw
   * it:
   *
   * - Inputs: every visible vtkActor with a mapper that has an input, in the
   *   order of vtkRenderer::GetActors(); input k is the k-th such actor. A
   *   composite mapper's (vtkCompositePolyDataMapper2's) block visibility,
   *   colors and opacity come with it (SetInputBlockAttributes()). Its
   *   mapper's input connection is used, moved by the actor's matrix
   *   (position, orientation, scale, user matrix) through a vtkTransformFilter
   *   when that is not the identity. Each input gets its own converter, whose
   *   mapper is the actor's mapper (so scalars are colored as that mapper
   *   colors them), and its own material copied from the actor's vtkProperty
   *   (vtkRayScopeMaterial::CopyProperty(): diffuse color, ambient, diffuse,
   *   specular, specular color and power, 1 - opacity as transparency, and the
   *   REFLECTIVITY / INDEX_OF_REFRACTION keys). The converter settings
   *   (normals, feature angle, subdivision) are those of GetConverter(); the
   *   property's line width and point size scale the automatic radius of the
   *   tubes and spheres its lines and vertices become.
   * - Lights: every switched-on vtkLight. Headlights and camera lights are
   *   placed as vtkRenderer::UpdateLightsGeometryToFollowCamera() places them
   *   (this method calls it). Positional lights become point lights with
   *   their attenuation; the spot cone is not modelled (a spot light shines
   *   in every direction). Others are directional, shining from position to
   *   focal point. Light color is the vtkLight's diffuse color times its
   *   intensity. A renderer without lights gets the headlight VTK would
   *   create for it (AutomaticLightCreation). Non-positional headlights
   *   become a light at the eye, as the Headlight option's light
   *   (rayscope::headlight()), with their color and intensity; the Headlight
   *   option is switched off, since the renderer's own headlight is among its
   *   lights.
   * - Camera: the active vtkCamera (CopyCamera(), with a horizontal view
   *   angle converted to the vertical one); size: the renderer's size in
   *   pixels; Background: the renderer's background (not gradients or
   *   textures); AmbientLight: vtkRenderer::GetAmbient().
   *
   * Props that are not vtkActors (2D actors, volumes) are not drawn: a visible
   * vtkVolume gives one warning, the first time it is seen. Ignored too are
   * textures, representation (points/wireframe actors are ray-traced as
   * surfaces) and backface properties. Returns the number of inputs (actors),
   * or -1 for a null renderer. Calling it again reuses what did not change:
   * moving the camera does not rebuild the BVH.
   */
  int CopyRenderer(vtkRenderer* renderer);

  ///@{
  /// The processes that render together: by default the global controller
  /// (vtkMultiProcessController::GetGlobalController(): ParaView's MPI
  /// processes under pvbatch or pvserver; none in a plain VTK program). With
  /// more than one process, each holds a piece of every input (the pieces
  /// are requested as piece k of N) and the render is image-parallel over the
  /// whole scene: the pieces are gathered to every process when any changed
  /// (a camera move gathers nothing), each process builds the scene and traces
  /// its share of the image's tiles (SetBalanceTiles()), and process 0 assembles the
  /// image, which is the one process's image bit for bit when the pieces put
  /// together (polydata appended in process order, other datasets as one
  /// unstructured grid, composite data leaf by leaf) are the serial input.
  /// The output is the image on process 0 and empty on the others. Every
  /// update is then collective: all processes must update together. An error
  /// on any process (a bad parameter, input that cannot be drawn) ends the
  /// update on all of them with empty outputs; a problem every process finds
  /// alike is reported by process 0 only, so it is shown once.
  void SetController(vtkMultiProcessController* controller);
  vtkMultiProcessController* GetController();
  ///@}

  ///@{
  /// With more than one process: hand the image's tiles out by estimated
  /// cost (on, the default: each process traces a few pixels of its
  /// interleaved tiles, one sample each, the estimates are summed, and
  /// rayscope::balance_shares() gives every tile to the process with the least
  /// estimated work so far, so that a process whose tiles are cheap takes more
  /// of them), or off: tile t to process t % N. The image is the same either
  /// way; the "Process" array shows the handout.
  vtkSetMacro(BalanceTiles, bool);
  vtkGetMacro(BalanceTiles, bool);
  vtkBooleanMacro(BalanceTiles, bool);
  ///@}

  ///@{
  /// Progressive rendering (off by default): the image of Samples x Samples
  /// samples per pixel is traced in Samples^2 passes of one sample per pixel.
  /// An update asked for by Refine() adds the next pass to the last image when
  /// nothing that changes the image changed in between (inputs, camera,
  /// lights, materials, settings); any other update starts again from the
  /// first pass. The output is the mean of the passes so far with field data
  /// "ProgressivePasses" (passes traced, passes in all), and after the last
  /// pass the image of the whole render bit for bit (rayscope::ProgressiveImage).
  /// Not with adaptive sampling (MaxSamples), which renders as without it.
  vtkSetMacro(Progressive, bool);
  vtkGetMacro(Progressive, bool);
  vtkBooleanMacro(Progressive, bool);
  ///@}

  /// Asks the next update to go on with the last progressive image: to add
  /// its next pass, or with `to_the_end` all the passes it lacks (what a
  /// screenshot needs). Marks the algorithm modified, except when the image
  /// is complete and nothing changed (on one process: its output is final).
  void Refine(bool to_the_end = false);
  /// Passes in the last image, and in the whole render (both 1 without
  /// Progressive; equal once a progressive image is complete).
  int GetImagePasses();
  int GetImageTotalPasses();

  /// Includes the materials', converter's and mapper's modification times.
  vtkMTimeType GetMTime() override;

  /// Updates the inputs and builds (or reuses) the scene without rendering,
  /// preparing the camera for the image size. Returns 1 on success, 0 after an
  /// error. Used by the ray-tree and structure sources.
  int UpdateScene();

  /// The name of input k in messages and object names ("input k").
  std::string GetInputName(int input);
  /// The name of scene object k of the last update ("input 0", "input 1 block
  /// 3 'wall'"); empty when there is no such object.
  std::string GetObjectName(int object);

  /// The checks only VTK has (camera, background and ambient colors, lights,
  /// materials): empty when all pass, else the message of the first bad one.
  /// The render settings are checked by RenderSettings::validate() (see
  /// GetRenderSettings()).
  std::string ValidateParameters();

  ///@{
  /// How often the inputs were converted to triangles, and the scene committed
  /// (its BVH built), since construction. An update that changes only the
  /// camera, material values or light values reuses both; a changed input
  /// converts and commits again.
  vtkIdType GetNumberOfGeometryConversions();
  vtkIdType GetNumberOfSceneCommits();
  ///@}

#ifndef __VTK_WRAP__
  /// The scene built by the last successful UpdateScene() or render (null
  /// before). Owned by this algorithm; valid until the next update.
  rayscope::Scene* GetCoreScene();
  /// The core settings of a render with the current parameters (not
  /// validated: RenderSettings::validate() does that).
  rayscope::RenderSettings GetRenderSettings();
  /// The data objects the scene is made of: the inputs, or in a parallel
  /// render every process's pieces of them put together (see
  /// SetController()), as of the last update.
  int GetNumberOfSceneInputs();
  vtkDataObject* GetSceneInput(int index);
  /// The converter of input `index`: its own (SetInputConverter()), else the
  /// one ScalarColoring asks for (configured by the last update).
  vtkRayScopeMeshConverter* GetConverterOf(int index);

  /// Renders this committed core scene (a scene file's, as `rayscope view`
  /// loads it) instead of the inputs: its geometry, materials, lights,
  /// background and ambient light are used as they are, and inputs, materials,
  /// lights and colors set here are ignored. Its camera becomes Position,
  /// FocalPoint, ViewUp, ViewAngle, ParallelProjection and ParallelScale (so it
  /// moves like any other) and its walk becomes Accel.
  void SetCoreScene(const rayscope::Scene& scene);

  /// The output image of a core framebuffer: the arrays listed above, as
  /// RequestData makes them (for callers that run the core's frame loop
  /// themselves, such as vtkRayScopeViewer's progressive renders).
  static void FramebufferToImage(const rayscope::Framebuffer& fb,
                                 const rayscope::RayCounters& counters, vtkImageData* image);
#endif

 protected:
  vtkRayScopeImageAlgorithm();
  ~vtkRayScopeImageAlgorithm() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
                         vtkInformationVector* outputVector) override;
  int RequestUpdateExtent(vtkInformation* request, vtkInformationVector** inputVector,
                          vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  int ScalarColoring;
  vtkScalarsToColors* LookupTable;
  bool BalanceTiles;
  bool Progressive;

 private:
  vtkRayScopeImageAlgorithm(const vtkRayScopeImageAlgorithm&) = delete;
  void operator=(const vtkRayScopeImageAlgorithm&) = delete;

  struct Internals;
  Internals* Internal;

  int BuildScene();
  // BuildScene's checks and build; the caller agrees on the result with the
  // other processes.
  int BuildSceneHere();
  // The converter of inputs without their own, for ScalarColoring (after an
  // update of the inputs); 0 after an error.
  int ConfigureColoring();
  // A warning for each material, converter or block attributes set for an
  // input index that has no input connection.
  void WarnAboutUnconnectedInputs();
  // The field data arrays that say which input and block each object is.
  void AddObjectArrays(vtkImageData* image);
};

#endif
