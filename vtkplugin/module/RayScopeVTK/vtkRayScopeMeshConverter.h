/**
 * @class   vtkRayScopeMeshConverter
 * @brief   Any vtkDataSet to the triangles the ray tracer intersects, colored
 *          exactly as a VTK mapper colors them.
 *
 * Geometry: polydata polygons and strips are triangulated (vtkTriangleFilter);
 * every other dataset (unstructured and structured grids, image data, ...) is
 * reduced to its outer surface first (vtkDataSetSurfaceFilter, with non-linear
 * cells tessellated NonlinearSubdivisionLevel times). For an isosurface or a
 * slice of image data, put the contour or cutter filter of your choice
 * upstream.
 *
 * Lines and points: line and polyline cells become tubes (a capsule around
 * each segment) and vertex and polyvertex cells spheres, colored as the
 * surface is (ConvertLinesAndPoints(), rayscope_vtkio::convert_lines_and_points()),
 * as VTK's and ParaView's OSPRay ray tracing draws them. Their radius is the
 * scene settings' LineRadius and PointRadius in world units, or, where those
 * are 0 (the default), automatic: 1/1000 of the diagonal of what is rendered
 * times this converter's LineWidth or PointSize (CopyRenderer() copies those
 * from the actor's vtkProperty), as VTK's OSPRay pass sizes them; or, with
 * the settings' RadiusArray, the value of that point array at each point.
 *
 * Normals: point normals of the data are used when present. Otherwise, with
 * ComputeNormals on (default), vtkPolyDataNormals computes them (splitting
 * sharp edges at FeatureAngle when Splitting is on, as vtkPolyDataNormals
 * does); with it off the surface is shaded flat with its geometric normals,
 * which is what VTK's OpenGL mapper shows for data without normals.
 *
 * Colors: the scalars are mapped by a vtkMapper's own code. The Mapper (by
 * default a fresh vtkDataSetMapper, i.e. VTK's defaults: scalar visibility on,
 * default scalar mode, color mode default, scalar range [0, 1], the default
 * lookup table) is shallow-copied into a private vtkDataSetMapper whose
 * vtkMapper::MapScalars(surface, 1.0, cellFlag) produces the colors, so the
 * scalar mode, array selection, component, color mode, lookup table (or the
 * array's own lookup table), scalar range and UseLookupTableScalarRange all
 * behave as in the mapper that renders the same data. The bytes are
 * sRGB-encoded display values; they are decoded to linear RGB for the core.
 *
 * - Point scalars become per-vertex colors, interpolated across triangles by
 *   the tracer in linear RGB (OpenGL interpolates the encoded bytes, so the
 *   two agree exactly at vertices and on triangles of one color, and differ
 *   slightly inside triangles whose vertices differ).
 *   InterpolateScalarsBeforeMapping (texture coloring) is not reproduced:
 *   colors are always mapped at the vertices.
 * - Cell scalars (and cell field data) give each triangle the color of the
 *   cell it came from: a point shared by triangles of different colors is
 *   duplicated once per color, so every triangle is exactly its cell's color.
 * - Field data scalars (ScalarModeToUseFieldData) color the whole surface with
 *   the tuple FieldDataTupleId, as VTK does.
 * - The alpha channel (lookup table opacity) is ignored.
 *
 * Convert() returns the result as vtkPolyData (triangles only) for inspection;
 * ConvertToMesh() (C++ only) gives the core TriangleMesh directly.
 *
 * The conversion itself is rayscope_vtkio::convert_dataset() (library
 * rayscope_vtkio), which the rayscope command runs on mesh files with these
 * same default settings: a file gives the same triangles, normals and colors
 * in both.
 */
#ifndef vtkRayScopeMeshConverter_h
#define vtkRayScopeMeshConverter_h

#include "RayScopeVTKModule.h"  // export macro
#include "vtkObject.h"

#include <string>

class vtkDataSet;
class vtkMapper;
class vtkPolyData;

#ifndef __VTK_WRAP__
namespace rayscope {
struct PointSet;
struct TriangleMesh;
struct TubeSet;
}  // namespace rayscope
namespace rayscope_vtkio {
struct CurveRadii;
}
#endif

class RAYSCOPEVTK_EXPORT vtkRayScopeMeshConverter : public vtkObject {
 public:
  static vtkRayScopeMeshConverter* New();
  vtkTypeMacro(vtkRayScopeMeshConverter, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Compute point normals when the data has none (default on).
  vtkSetMacro(ComputeNormals, vtkTypeBool);
  vtkGetMacro(ComputeNormals, vtkTypeBool);
  vtkBooleanMacro(ComputeNormals, vtkTypeBool);
  ///@}

  ///@{
  /// vtkPolyDataNormals settings for computed normals: split sharp edges
  /// (default on) whose dihedral angle exceeds FeatureAngle degrees (default 30).
  vtkSetMacro(Splitting, vtkTypeBool);
  vtkGetMacro(Splitting, vtkTypeBool);
  vtkBooleanMacro(Splitting, vtkTypeBool);
  vtkSetClampMacro(FeatureAngle, double, 0.0, 180.0);
  vtkGetMacro(FeatureAngle, double);
  ///@}

  ///@{
  /// Tessellation level of non-linear cells (vtkDataSetSurfaceFilter), default 1.
  vtkSetClampMacro(NonlinearSubdivisionLevel, int, 0, 8);
  vtkGetMacro(NonlinearSubdivisionLevel, int);
  ///@}

  ///@{
  /// The mapper whose coloring settings are used. Never null: setting null
  /// restores a fresh vtkDataSetMapper. The mapper itself is not modified.
  void SetMapper(vtkMapper* mapper);
  vtkGetObjectMacro(Mapper, vtkMapper);
  ///@}

  ///@{
  /// The line width and point size of the data (default 1; CopyRenderer()
  /// copies the actor's vtkProperty values): the automatic radius of tubes and
  /// spheres is this many times rayscope_vtkio::kAutomaticRadiusFraction of
  /// the diagonal of what is rendered (vtkRayScopeSceneSettings::LineRadius
  /// and PointRadius, when set, replace it). Negative values count as 0.
  vtkSetMacro(LineWidth, double);
  vtkGetMacro(LineWidth, double);
  vtkSetMacro(PointSize, double);
  vtkGetMacro(PointSize, double);
  ///@}

  /// Includes the mapper's (and its lookup table's) modification time.
  vtkMTimeType GetMTime() override;

  /// Triangulated surface of `input` in `output`: float points, triangles,
  /// point data "Normals" (when present or computed), "Colors" (RGBA unsigned
  /// char, the mapper's sRGB bytes, per point; absent without scalar colors) and
  /// "LinearColors" (float RGB). Returns 1 on success, 0 with an error
  /// (vtkErrorMacro) and an empty `output` if the input is null or a cell names
  /// a point the input lacks (checked before any VTK filter runs).
  int Convert(vtkDataSet* input, vtkPolyData* output);

  /// Where the colors of the last conversion came from.
  enum ColorSource { NO_COLORS = 0, POINT_COLORS = 1, CELL_COLORS = 2, FIELD_COLORS = 3 };
  vtkGetMacro(LastColorSource, int);

#ifndef __VTK_WRAP__
  /// Convert() straight to a core mesh (linear colors, unit normals). With
  /// `why`, a failure is not reported by this converter but explained in
  /// `*why` for the caller to report (the image algorithm names the input).
  /// With `origin` (the scene's local origin, rayscope::Scene::origin),
  /// positions are relative to it, subtracted in double precision.
  bool ConvertToMesh(vtkDataSet* input, rayscope::TriangleMesh& mesh, std::string* why = nullptr,
                     const double origin[3] = nullptr);
  /// A core mesh from polydata made by Convert().
  static void MeshFromPolyData(vtkPolyData* converted, rayscope::TriangleMesh& mesh);

  /// The lines of `input` as tubes and its vertices as spheres of `radii`,
  /// colored by the mapper (see above; rayscope_vtkio::convert_lines_and_points()).
  /// Empty sets when the input has neither. `why` and `origin` as
  /// ConvertToMesh(); false (with `why`) when a cell names a point the input
  /// lacks or the radius array is not a one-component point array.
  bool ConvertLinesAndPoints(vtkDataSet* input, const rayscope_vtkio::CurveRadii& radii,
                             rayscope::TubeSet& tubes, rayscope::PointSet& points, std::string& why,
                             const double origin[3] = nullptr);
#endif

 protected:
  vtkRayScopeMeshConverter();
  ~vtkRayScopeMeshConverter() override;

  vtkTypeBool ComputeNormals;
  vtkTypeBool Splitting;
  double FeatureAngle;
  int NonlinearSubdivisionLevel;
  vtkMapper* Mapper;
  int LastColorSource;
  double LineWidth;
  double PointSize;

 private:
  // The conversion; false with the reason in `why` (not reported) on failure.
  bool ConvertOrExplain(vtkDataSet* input, vtkPolyData* output, std::string& why);

  vtkRayScopeMeshConverter(const vtkRayScopeMeshConverter&) = delete;
  void operator=(const vtkRayScopeMeshConverter&) = delete;
};

#endif
