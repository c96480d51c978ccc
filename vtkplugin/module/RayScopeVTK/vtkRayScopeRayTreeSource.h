/**
 * @class   vtkRayScopeRayTreeSource
 * @brief   The ray tree of one or more pixels as vtkPolyData.
 *
 * Replays pixels of the render of a vtkRayScopeImageAlgorithm (SetSceneSource:
 * same inputs, camera, lights, materials, size, samples and depth) with the
 * core's ray-tree recorder (rayscope::record_pixel), which is exact: the
 * replayed pixel has the very color of the full render.
 *
 * The scene's datasets come through input port 0 (AddInputConnection, one or
 * more vtkDataSets), like any filter's: they become the scene source's inputs
 * (replacing its own). Without a scene source, a default
 * vtkRayScopeImageAlgorithm with AutoCamera on is used (the camera fitted to
 * the data, looking down -z, the headlight, the default material). With no
 * input connected, the scene source's own inputs are used.
 *
 * Pixels are given in VTK image coordinates: pixel (0, 0) is the bottom-left
 * pixel (the VTK image convention, as in the image algorithm's output and in
 * display coordinates), unlike the rayscope command (--pixel, --rect), whose
 * (0, 0) is the top-left pixel. Pixel (i, j) here is the command's
 * (i, Height - 1 - j).
 *
 * Output:
 * - one line cell per ray, from its origin to where it ends: its hit point,
 *   for a miss a point MissLength beyond the origin (automatic by default:
 *   past the scene's bounds), for a shadow ray that reaches its light the
 *   light (point lights) or MissLength along it (directional lights), for an
 *   occluded shadow ray the nearest occluding surface along it; for a ray
 *   the integrator did not trace (skipped) the light (shadow rays skipped
 *   because N.L <= 0) or a short stub along its direction (reflection and
 *   refraction rays cut by the depth limit or the contribution cutoff);
 * - one vertex cell per closest hit (primary, reflection and refraction rays
 *   that hit), at the hit point.
 * As in any vtkPolyData the vertex cells come first, then the lines; each cell
 * carries the data of its ray:
 *   "RayId", "ParentId" (-1 for primary rays), "Pixel" (2 components, VTK
 *   image coordinates), "PixelIndex" (index in the pixel list), "Sample",
 *   "Kind" (0 primary, 1 shadow, 2 reflection, 3 refraction), "KindName",
 *   "Depth", "Hit" (1 if the ray hit a surface; for shadow rays: occluded),
 *   "Occluded", "ObjectId" (object hit, or the occluder the shadow query
 *   found, -1), "LightId" (-1), "T" (distance along the ray direction to its
 *   end), "EndKind" (0 miss, 1 hit, 2 light, 3 occluder, 4 skipped stub),
 *   "Skipped" (0 traced; not traced: 1 N.L <= 0, 2 depth limit, 3
 *   contribution cutoff: 1 + rayscope::SkipReason), "EndObjectId" (the
 *   object at the end point: for occluded shadow rays the nearest occluding
 *   surface, which may differ from the first occluder the any-hit query
 *   stopped at), "Weight" (RGB weight in the pixel),
 *   "Color" (the linear RGB it returned; for shadow rays the light arriving),
 *   "NodesVisited", "BoxesTested", "PrimitivesTested", "NodesCulled",
 *   "IsHitPoint" (1 for the vertex cells), "KindColor" (the kind's color,
 *   GetKindColor, as RGB bytes: shown as it is with MapScalars off).
 * Point data "Normals" holds the shading normal at hit points and
 * "GeometricNormals" the geometric normal (0 elsewhere). Field data
 * "PixelColor" holds each pixel's linear color.
 */
#ifndef vtkRayScopeRayTreeSource_h
#define vtkRayScopeRayTreeSource_h

#include "RayScopeVTKModule.h"  // export macro
#include "vtkRayScopeSceneFilter.h"

class vtkRayScopeImageAlgorithm;

class RAYSCOPEVTK_EXPORT vtkRayScopeRayTreeSource : public vtkRayScopeSceneFilter {
 public:
  static vtkRayScopeRayTreeSource* New();
  vtkTypeMacro(vtkRayScopeRayTreeSource, vtkRayScopeSceneFilter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Pixels to record, in VTK image coordinates ((0, 0) bottom-left). SetPixel
  /// replaces the list.
  void SetPixel(int i, int j);
  void AddPixel(int i, int j);
  void RemoveAllPixels();
  int GetNumberOfPixels();
  ///@}

  ///@{
  /// The sample to record (0 .. N*N-1), or -1 for every sample (default).
  vtkSetMacro(Sample, int);
  vtkGetMacro(Sample, int);
  ///@}

  ///@{
  /// Length drawn for rays that end nowhere (misses, directional shadow rays),
  /// in units of world length. <= 0 (default): past the scene's bounding box.
  vtkSetMacro(MissLength, double);
  vtkGetMacro(MissLength, double);
  ///@}

  /// The color of ray kind `kind` (the "Kind" array: 0 primary, 1 shadow,
  /// 2 reflection, 3 refraction) as RGB in [0, 1], black for another value:
  /// the one palette of RayScope's ray trees (the "KindColor" array, the
  /// viewer, the examples), readable on dark and light backgrounds alike.
  static void GetKindColor(int kind, double rgb[3]);

 protected:
  vtkRayScopeRayTreeSource();
  ~vtkRayScopeRayTreeSource() override;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  int Sample;
  double MissLength;

 private:
  vtkRayScopeRayTreeSource(const vtkRayScopeRayTreeSource&) = delete;
  void operator=(const vtkRayScopeRayTreeSource&) = delete;

  struct Internals;
  Internals* Internal;
};

#endif
