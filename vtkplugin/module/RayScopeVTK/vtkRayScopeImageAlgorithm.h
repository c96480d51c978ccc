/**
 * @class   vtkRayScopeImageAlgorithm
 * @brief   Ray-traces VTK datasets (Whitted: shadows, reflection, refraction)
 *          into vtkImageData.
 *
 * Input port 0 takes one or more vtkDataSet connections (AddInputConnection /
 * AddInputData). Input k becomes scene object k: its surface triangles as
 * vtkRayScopeMeshConverter makes them (colored through the converter's mapper
 * settings), with material k (SetInputMaterial) or the default material
 * (GetMaterial()).
 *
 * Input that cannot be rendered is an error (vtkErrorMacro) and leaves the
 * output empty: no input, an input whose cells name points it lacks, or
 * inputs that have no surface triangles at all (an empty dataset, a 1-D
 * image, a reader's output after it failed). An input without triangles next
 * to others that have some is a warning (vtkWarningMacro), as is a material or
 * converter set for an input index that is not connected when the image is
 * made (it is kept for when that input is connected, and unused until then).
 *
 * The camera follows vtkCamera (Position, FocalPoint, ViewUp, vertical
 * ViewAngle in degrees, ParallelProjection with ParallelScale = half the image
 * height in world units; CopyCamera() takes them from a vtkCamera). Lights are
 * a headlight (a white directional light shining from the camera along the
 * view direction, as VTK's headlight; on by default) plus any point and
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
 * - "ObjectId": int, the input index hit by sample 0, -1 on the background.
 * - "Cost": int, BVH nodes visited by every ray of the pixel (all samples,
 *   secondary and shadow rays included); with "CostRays", "CostBoxes",
 *   "CostPrimitives". Only when ComputeCost is on (default; it renders with the
 *   core's counting integrator, slightly slower).
 * - "Samples": int, the samples the pixel took. Only with adaptive sampling
 *   (MaxSamples > 0).
 *
 * Field data: "RayCounts" (primary, shadow, reflection, refraction rays),
 * "ShadowRaysOccluded", "NodesVisited", "BoxesTested", "PrimitivesTested".
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
 */
#ifndef vtkRayScopeImageAlgorithm_h
#define vtkRayScopeImageAlgorithm_h

#include "RayScopeVTKModule.h"  // export macro
#include "vtkImageAlgorithm.h"

#include <string>  // std::string

class vtkCamera;
class vtkDataSet;
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
  /// Image size in pixels (default 300 x 300), each in 1..kMaxImageSide, at
  /// most kMaxPixels pixels.
  vtkSetMacro(Width, int);
  vtkGetMacro(Width, int);
  vtkSetMacro(Height, int);
  vtkGetMacro(Height, int);
  void SetSize(int width, int height);
  ///@}

  ///@{
  /// N: each pixel takes N x N stratified samples (1..kMaxSamples, default 1).
  vtkSetMacro(Samples, int);
  vtkGetMacro(Samples, int);
  ///@}

  ///@{
  /// Maximum recursion depth of reflection and refraction rays (0..kMaxDepth,
  /// default 5).
  vtkSetMacro(MaxDepth, int);
  vtkGetMacro(MaxDepth, int);
  ///@}

  ///@{
  /// Secondary rays whose weight within their sample is smaller are skipped
  /// (0..kMaxMinContribution, i.e. 0..1; default 1e-3).
  vtkSetMacro(MinContribution, double);
  vtkGetMacro(MinContribution, double);
  ///@}

  ///@{
  /// Adaptive sampling (RenderSettings::max_samples, target_error): 0 (off;
  /// default), or M, a multiple of Samples up to kMaxSamples: each pixel takes
  /// Samples x Samples samples at a time from an M x M grid until the standard
  /// error of its mean is below TargetError (0..kMaxTargetError, default 0:
  /// all M x M). TargetError > 0 needs MaxSamples > 0.
  vtkSetMacro(MaxSamples, int);
  vtkGetMacro(MaxSamples, int);
  vtkSetMacro(TargetError, double);
  vtkGetMacro(TargetError, double);
  ///@}

  ///@{
  /// Box-filter the checkerboard over each primary sample's footprint, from
  /// ray differentials (RenderSettings::texture_filter; default off).
  vtkSetMacro(TextureFilter, vtkTypeBool);
  vtkGetMacro(TextureFilter, vtkTypeBool);
  vtkBooleanMacro(TextureFilter, vtkTypeBool);
  ///@}

  ///@{
  /// Render threads (0..kMaxThreads; 0: all hardware threads) and the seed of
  /// the jitter (0..kMaxSeed, which is VTK_INT_MAX; clamped to that range).
  vtkSetMacro(Threads, int);
  vtkGetMacro(Threads, int);
  vtkSetClampMacro(Seed, int, 0, VTK_INT_MAX);
  vtkGetMacro(Seed, int);
  ///@}

  ///@{
  /// The structure rays walk (rayscope::AccelKind, docs/acceleration.md):
  /// ACCEL_BVH, the BVH in 8-wide nodes, what renders use (default);
  /// ACCEL_BINARY_BVH, the same BVH node by node, the lecture's binary walk,
  /// so that ray trees, the "Cost" arrays and vtkRayScopeAccelSource's visit
  /// counts show every binary node a ray enters; ACCEL_NONE, every primitive
  /// tested against every ray; ACCEL_KDTREE, the SAH kD-tree; ACCEL_GRID, the
  /// uniform grid; ACCEL_OCTREE, the octree, and ACCEL_BSP, the BSP tree
  /// (planes through the triangles), both stored as Storage says;
  /// ACCEL_SPHERES, the hierarchy of bounding spheres. Each walk
  /// names its own nodes or cells, and vtkRayScopeAccelSource draws the
  /// structure walked. The image is the same for all.
  enum AccelKinds {
    ACCEL_BVH = 0,
    ACCEL_BINARY_BVH = 1,
    ACCEL_NONE = 2,
    ACCEL_KDTREE = 3,
    ACCEL_GRID = 4,
    ACCEL_OCTREE = 5,
    ACCEL_BSP = 6,
    ACCEL_SPHERES = 7
  };
  vtkSetClampMacro(Accel, int, ACCEL_BVH, ACCEL_SPHERES);
  vtkGetMacro(Accel, int);
  void SetAccelToBvh() { this->SetAccel(ACCEL_BVH); }
  void SetAccelToBinaryBvh() { this->SetAccel(ACCEL_BINARY_BVH); }
  void SetAccelToNone() { this->SetAccel(ACCEL_NONE); }
  void SetAccelToKdTree() { this->SetAccel(ACCEL_KDTREE); }
  void SetAccelToGrid() { this->SetAccel(ACCEL_GRID); }
  void SetAccelToOctree() { this->SetAccel(ACCEL_OCTREE); }
  void SetAccelToBsp() { this->SetAccel(ACCEL_BSP); }
  void SetAccelToSpheres() { this->SetAccel(ACCEL_SPHERES); }
  ///@}

  ///@{
  /// How a spatial subdivision stores a primitive that straddles its cuts
  /// (rayscope::PrimStorage, docs/acceleration.md): STORAGE_EVERY_CELL, a
  /// reference in every cell it overlaps (default; every Accel takes it);
  /// STORAGE_SMALLEST_CELL, once, in its smallest loose cell (ACCEL_OCTREE)
  /// or in the node whose plane it straddles (ACCEL_BSP); STORAGE_SPLIT, cut
  /// into fragments (ACCEL_BSP only). A pair the structure cannot build is an
  /// error, with the core's message (rayscope::accel_storage_error, as the
  /// CLI's --storage).
  enum StorageKinds { STORAGE_EVERY_CELL = 0, STORAGE_SMALLEST_CELL = 1, STORAGE_SPLIT = 2 };
  vtkSetClampMacro(Storage, int, STORAGE_EVERY_CELL, STORAGE_SPLIT);
  vtkGetMacro(Storage, int);
  void SetStorageToEveryCell() { this->SetStorage(STORAGE_EVERY_CELL); }
  void SetStorageToSmallestCell() { this->SetStorage(STORAGE_SMALLEST_CELL); }
  void SetStorageToSplit() { this->SetStorage(STORAGE_SPLIT); }
  ///@}

  ///@{
  /// STORAGE_SMALLEST_CELL's loose factor for ACCEL_KDTREE, ACCEL_GRID and
  /// ACCEL_OCTREE: each cell enlarged by this fraction of its size on every
  /// side (default 0.1, the lecture's 10%; 0 .. 0.5). A value out of range is
  /// an error with the core's message (rayscope::loose_factor_error, as the
  /// CLI's --loose-factor).
  vtkSetMacro(LooseFactor, double);
  vtkGetMacro(LooseFactor, double);
  ///@}

  ///@{
  /// How ACCEL_KDTREE chooses its split planes (rayscope::KdSplitRule, as the
  /// CLI's --kd-split): KD_SPLIT_SAH, by the surface-area heuristic
  /// (default); KD_SPLIT_MEDIAN, at the median of the cell's primitive
  /// centers on its widest axis.
  enum KdSplitRules { KD_SPLIT_SAH = 0, KD_SPLIT_MEDIAN = 1 };
  vtkSetClampMacro(KdSplit, int, KD_SPLIT_SAH, KD_SPLIT_MEDIAN);
  vtkGetMacro(KdSplit, int);
  void SetKdSplitToSah() { this->SetKdSplit(KD_SPLIT_SAH); }
  void SetKdSplitToMedian() { this->SetKdSplit(KD_SPLIT_MEDIAN); }
  ///@}

  ///@{
  /// ACCEL_GRID's cells per axis (x, y, z; 0 on an axis, the default: chosen
  /// from the object count), as the CLI's --grid-resolution. More than
  /// rayscope::UniformGrid::kMaxResolution per axis or kMaxCells in all is an
  /// error with the core's message (rayscope::grid_resolution_error).
  vtkSetVector3Macro(GridResolution, int);
  vtkGetVector3Macro(GridResolution, int);
  ///@}

  ///@{
  /// Produce the "Cost" arrays (default on).
  vtkSetMacro(ComputeCost, vtkTypeBool);
  vtkGetMacro(ComputeCost, vtkTypeBool);
  vtkBooleanMacro(ComputeCost, vtkTypeBool);
  ///@}

  ///@{
  /// Camera, as vtkCamera (defaults: position (0, 0, 1), focal point 0, view
  /// up (0, 1, 0), view angle 30 degrees, perspective, parallel scale 1).
  vtkSetVector3Macro(Position, double);
  vtkGetVector3Macro(Position, double);
  vtkSetVector3Macro(FocalPoint, double);
  vtkGetVector3Macro(FocalPoint, double);
  vtkSetVector3Macro(ViewUp, double);
  vtkGetVector3Macro(ViewUp, double);
  vtkSetMacro(ViewAngle, double);
  vtkGetMacro(ViewAngle, double);
  vtkSetMacro(ParallelProjection, vtkTypeBool);
  vtkGetMacro(ParallelProjection, vtkTypeBool);
  vtkBooleanMacro(ParallelProjection, vtkTypeBool);
  vtkSetMacro(ParallelScale, double);
  vtkGetMacro(ParallelScale, double);
  ///@}

  /// Takes position, focal point, view up, view angle and the projection from
  /// a vtkCamera.
  void CopyCamera(vtkCamera* camera);

  /// Points the camera at the bounds of all inputs, as vtkRenderer::ResetCamera
  /// does (looking down -z with +y up, or along the current view direction
  /// when the camera is valid). Updates the inputs. Returns 0 without inputs.
  int ResetCamera();

  ///@{
  /// AutoCamera: every update points the camera at the bounds of the inputs
  /// as ResetCamera() does, without changing the settings above: the view
  /// direction (Position toward FocalPoint), ViewUp, ViewAngle and the
  /// projection are kept; the distance (and the parallel scale) are fitted.
  /// Default off; ParaView's filters turn it on.
  vtkSetMacro(AutoCamera, vtkTypeBool);
  vtkGetMacro(AutoCamera, vtkTypeBool);
  vtkBooleanMacro(AutoCamera, vtkTypeBool);
  ///@}

  ///@{
  /// Background color (sRGB, default black).
  vtkSetVector3Macro(Background, double);
  vtkGetVector3Macro(Background, double);
  ///@}

  ///@{
  /// Ambient light color (sRGB, default white); multiplies every material's
  /// ambient term.
  vtkSetVector3Macro(AmbientLight, double);
  vtkGetVector3Macro(AmbientLight, double);
  ///@}

  ///@{
  /// VTK-style headlight: directional, from the camera toward the focal point
  /// (default on, intensity 1).
  vtkSetMacro(Headlight, vtkTypeBool);
  vtkGetMacro(Headlight, vtkTypeBool);
  vtkBooleanMacro(Headlight, vtkTypeBool);
  vtkSetMacro(HeadlightIntensity, double);
  vtkGetMacro(HeadlightIntensity, double);
  ///@}

  ///@{
  /// Lights besides the headlight. Colors are sRGB, intensity >= 0. A point
  /// light is not attenuated (VTK's default). Directional lights give the
  /// direction the light travels. Each returns the light's index.
  int AddPointLight(double x, double y, double z, double r, double g, double b, double intensity);
  int AddDirectionalLight(double dx, double dy, double dz, double r, double g, double b,
                          double intensity);
  /// AddPointLight() (type LIGHT_POINT; x, y, z a position) or
  /// AddDirectionalLight() (LIGHT_DIRECTIONAL; the direction of travel) by
  /// type: one command for a list of lights of both kinds, whose values are
  /// all doubles (ParaView's "Lights" property); any other type is an error.
  enum LightTypes { LIGHT_POINT = 0, LIGHT_DIRECTIONAL = 1 };
  int AddLight(double type, double x, double y, double z, double r, double g, double b,
               double intensity);
  void RemoveAllLights();
  int GetNumberOfLights();
  /// Attenuation 1 / (constant + linear d + quadratic d^2) of point light
  /// `index` (vtkLight::SetAttenuationValues; default (1, 0, 0), none).
  void SetLightAttenuation(int index, double constant, double linear, double quadratic);
  ///@}

  ///@{
  /// Shadow rays toward every light (default on).
  vtkSetMacro(Shadows, vtkTypeBool);
  vtkGetMacro(Shadows, vtkTypeBool);
  vtkBooleanMacro(Shadows, vtkTypeBool);
  ///@}

  /// The material of inputs without their own (never null).
  vtkRayScopeMaterial* GetMaterial();
  /// Makes `material` the material of inputs without their own (null: a new
  /// default material).
  void SetMaterial(vtkRayScopeMaterial* material);
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
   *   order of vtkRenderer::GetActors(); input k is the k-th such actor. Its
   *   mapper's input connection is used, moved by the actor's matrix
   *   (position, orientation, scale, user matrix) through a vtkTransformFilter
   *   when that is not the identity. Each input gets its own converter, whose
   *   mapper is the actor's mapper (so scalars are colored as that mapper
   *   colors them), and its own material copied from the actor's vtkProperty
   *   (vtkRayScopeMaterial::CopyProperty(): diffuse color, ambient, diffuse,
   *   specular, specular color and power, 1 - opacity as transparency, and the
   *   REFLECTIVITY / INDEX_OF_REFRACTION keys). The converter settings
   *   (normals, feature angle, subdivision) are those of GetConverter().
   * - Lights: every switched-on vtkLight. Headlights and camera lights are
   *   placed as vtkRenderer::UpdateLightsGeometryToFollowCamera() places them
   *   (this method calls it). Positional lights become point lights with
   *   their attenuation; the spot cone is not modelled (a spot light shines
   *   in every direction). Others are directional, shining from position to
   *   focal point. Light color is the vtkLight's diffuse color times its
   *   intensity. A renderer without lights gets the headlight VTK would
   *   create for it (AutomaticLightCreation). The Headlight option is
   *   switched off, since the renderer's own headlight is among its lights.
   * - Camera: the active vtkCamera (CopyCamera(), with a horizontal view
   *   angle converted to the vertical one); size: the renderer's size in
   *   pixels; Background: the renderer's background (not gradients or
   *   textures); AmbientLight: vtkRenderer::GetAmbient().
   *
   * Props that are not vtkActors (2D actors, volumes) are ignored, and so are
   * textures, representation (points/wireframe actors are ray-traced as
   * surfaces) and backface properties. Returns the number of inputs (actors),
   * or -1 for a null renderer. Calling it again reuses what did not change:
   * moving the camera does not rebuild the BVH.
   */
  int CopyRenderer(vtkRenderer* renderer);

  /// Includes the materials', converter's and mapper's modification times.
  vtkMTimeType GetMTime() override;

  /// Updates the inputs and builds (or reuses) the scene without rendering,
  /// preparing the camera for the image size. Returns 1 on success, 0 after an
  /// error. Used by the ray-tree and structure sources.
  int UpdateScene();

  /// Name of scene object k (the input index, "input k").
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

  int Width;
  int Height;
  int Samples;
  int MaxDepth;
  double MinContribution;
  int MaxSamples;
  double TargetError;
  vtkTypeBool TextureFilter;
  int Threads;
  int Seed;
  vtkTypeBool ComputeCost;
  int Accel;
  int Storage;
  double LooseFactor;
  int KdSplit;
  int GridResolution[3];
  double Position[3];
  double FocalPoint[3];
  double ViewUp[3];
  double ViewAngle;
  vtkTypeBool ParallelProjection;
  double ParallelScale;
  double Background[3];
  double AmbientLight[3];
  vtkTypeBool Headlight;
  double HeadlightIntensity;
  vtkTypeBool Shadows;
  vtkTypeBool AutoCamera;
  int ScalarColoring;
  vtkScalarsToColors* LookupTable;

 private:
  vtkRayScopeImageAlgorithm(const vtkRayScopeImageAlgorithm&) = delete;
  void operator=(const vtkRayScopeImageAlgorithm&) = delete;

  struct Internals;
  Internals* Internal;

  int BuildScene();
  // The converter of inputs without their own, for ScalarColoring (after an
  // update of the inputs); 0 after an error.
  int ConfigureColoring();
  // A warning for each material or converter set for an input index that has
  // no input connection.
  void WarnAboutUnconnectedInputs();
};

#endif
