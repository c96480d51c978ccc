/**
 * @class   vtkRayScopeSceneSettings
 * @brief   The settings of a RayScope scene: image and sampling, acceleration
 *          structure, camera, lights and the default material.
 *
 * What a ray-traced image is made with, apart from its datasets: one object
 * that vtkRayScopeImageAlgorithm, vtkRayScopeRayTreeSource,
 * vtkRayScopeAccelSource and vtkRayScopeRangeQuery each hold (GetSettings())
 * and can share (SetSettings()): set the camera once, on a shared settings
 * object, and every filter holding it renders, records or draws from that
 * camera. The filters' GetMTime() includes the settings', so a change
 * re-executes each of them.
 *
 * Values are checked when a filter runs, not when set: Validate() returns the
 * first problem in words (the render settings by the core's
 * rayscope::RenderSettings::validate(), whose named limits in
 * rayscope/render_settings.h the documentation below quotes), and the filter
 * reports it with vtkErrorMacro and leaves its output empty. In ParaView this
 * is the "RayScope Scene" settings proxy that every RayScope filter follows.
 */
#ifndef vtkRayScopeSceneSettings_h
#define vtkRayScopeSceneSettings_h

#include "RayScopeVTKModule.h"  // export macro
#include "vtkObject.h"

#include <string>  // std::string

class vtkCamera;
class vtkRayScopeMaterial;

#ifndef __VTK_WRAP__
#include <vector>  // GetLights()
namespace rayscope {
struct RenderSettings;
}  // namespace rayscope
#endif

class RAYSCOPEVTK_EXPORT vtkRayScopeSceneSettings : public vtkObject {
 public:
  static vtkRayScopeSceneSettings* New();
  vtkTypeMacro(vtkRayScopeSceneSettings, vtkObject);
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
  /// Lines and points (vtkRayScopeMeshConverter): the radius of the tubes
  /// around line cells and of the spheres at vertex cells, in world units;
  /// 0 (default): automatic, rayscope_vtkio::kAutomaticRadiusFraction (1/1000)
  /// of the diagonal of all inputs (1 when they are all one point) times the
  /// converter's LineWidth or PointSize, as VTK's OSPRay pass sizes them. RadiusArray: a point
  /// array (one component) whose value is the radius at each point, for tubes and spheres alike
  /// (empty, default: none). A negative or non-finite radius is an error.
  vtkSetMacro(LineRadius, double);
  vtkGetMacro(LineRadius, double);
  vtkSetMacro(PointRadius, double);
  vtkGetMacro(PointRadius, double);
  vtkSetStdStringFromCharMacro(RadiusArray);
  vtkGetCharFromStdStringMacro(RadiusArray);
  ///@}

  ///@{
  /// How ACCEL_KDTREE chooses its split planes (rayscope::KdSplitRule, whose
  /// values these are, as the CLI's --kd-split): KD_SPLIT_SAH, by the
  /// surface-area heuristic (default); KD_SPLIT_MEDIAN, at the middle of the
  /// cell's longest axis (a spatial median); KD_SPLIT_ALTERNATING_MEDIAN, the
  /// lecture's rule: the axes x, y, z in turn with the depth, the plane at
  /// the median of the cell's primitive centers.
  enum KdSplitRules { KD_SPLIT_SAH = 0, KD_SPLIT_MEDIAN = 1, KD_SPLIT_ALTERNATING_MEDIAN = 2 };
  vtkSetClampMacro(KdSplit, int, KD_SPLIT_SAH, KD_SPLIT_ALTERNATING_MEDIAN);
  vtkGetMacro(KdSplit, int);
  void SetKdSplitToSah() { this->SetKdSplit(KD_SPLIT_SAH); }
  void SetKdSplitToMedian() { this->SetKdSplit(KD_SPLIT_MEDIAN); }
  void SetKdSplitToAlternatingMedian() { this->SetKdSplit(KD_SPLIT_ALTERNATING_MEDIAN); }
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
  /// Takes the structure settings of `other`: Accel, Storage, LooseFactor,
  /// KdSplit and GridResolution.
  void CopyStructure(vtkRayScopeSceneSettings* other);

  ///@{
  /// AutoCamera: every update points the camera at the bounds of the inputs
  /// as vtkRayScopeImageAlgorithm::ResetCamera() does, without changing the settings above: the
  /// view direction (Position toward FocalPoint), ViewUp, ViewAngle and the projection are kept;
  /// the distance (and the parallel scale) are fitted. Default off; ParaView's filters turn it on.
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
  /// The headlight: a white light at the eye (rayscope::headlight(): a point
  /// light at the camera's position, along the view for a parallel camera),
  /// which casts no shadow the eye can see (default on, intensity 1).
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

  /// Includes the default material's modification time.
  vtkMTimeType GetMTime() override;

  /// Every check of the values above: empty when all pass, else the first
  /// problem in words (the render settings by RenderSettings::validate(), the
  /// camera, colors, lights, structure and material here).
  std::string Validate();

#ifndef __VTK_WRAP__
  /// The core settings of a render with these values (not validated:
  /// Validate() does that).
  rayscope::RenderSettings GetRenderSettings();

  /// A light added with AddPointLight() or AddDirectionalLight(), or a
  /// renderer's headlight (vtkRayScopeImageAlgorithm::CopyRenderer()).
  struct Light {
    bool point = true;
    /// A light at the eye (rayscope::headlight()); `v` is not used.
    bool headlight = false;
    double v[3] = {0.0, 0.0, 0.0};  // position (point) or direction of travel (directional)
    double color[3] = {1.0, 1.0, 1.0};
    double intensity = 1.0;
    double attenuation[3] = {1.0, 0.0, 0.0};

    bool operator==(const Light& o) const;
  };
  const std::vector<Light>& GetLights();
  /// Replaces every light (Modified() only when the list differs).
  void SetLights(const std::vector<Light>& lights);
#endif

 protected:
  vtkRayScopeSceneSettings();
  ~vtkRayScopeSceneSettings() override;

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
  double LineRadius;
  double PointRadius;
  std::string RadiusArray;
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

 private:
  vtkRayScopeSceneSettings(const vtkRayScopeSceneSettings&) = delete;
  void operator=(const vtkRayScopeSceneSettings&) = delete;

  struct Internals;
  Internals* Internal;
};

#endif
