// vtkRayScopeMeshConverter: datasets to triangles, normals, and colors mapped
// by the mapper's own code.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCleanPolyData.h>
#include <vtkCubeSource.h>
#include <vtkDataSetMapper.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>
#include <vtkQuadraticTetra.h>
#include <vtkSphereSource.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include "rayscope/scene.h"
#include "vtkRayScopeMeshConverter.h"

namespace {

vtkIdType triangles(vtkPolyData* pd) {
  vtkIdType n = 0;
  vtkNew<vtkIdList> ids;
  for (pd->GetPolys()->InitTraversal(); pd->GetPolys()->GetNextCell(ids);) {
    EXPECT_EQ(ids->GetNumberOfIds(), 3);
    ++n;
  }
  return n;
}

// Polydata with one quad, one 5-point strip (3 triangles), a vertex and a line.
vtkSmartPointer<vtkPolyData> mixed_polydata() {
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  for (int i = 0; i < 5; ++i) {
    pts->InsertNextPoint(i, 0, 0);
    pts->InsertNextPoint(i, 1, 0);
  }
  pd->SetPoints(pts);
  vtkNew<vtkCellArray> polys, strips, verts, lines;
  vtkIdType quad[4] = {0, 2, 3, 1};
  polys->InsertNextCell(4, quad);
  vtkIdType strip[5] = {2, 3, 4, 5, 6};
  strips->InsertNextCell(5, strip);
  vtkIdType v = 9;
  verts->InsertNextCell(1, &v);
  vtkIdType line[2] = {8, 9};
  lines->InsertNextCell(2, line);
  pd->SetPolys(polys);
  pd->SetStrips(strips);
  pd->SetVerts(verts);
  pd->SetLines(lines);
  return pd;
}

}  // namespace

// Polygons and strips are triangulated, vertices and lines dropped.
TEST(VtkConverter, PolyDataTriangulated) {
  vtkNew<vtkRayScopeMeshConverter> conv;
  vtkNew<vtkPolyData> out;
  ASSERT_EQ(conv->Convert(mixed_polydata(), out), 1);
  EXPECT_EQ(triangles(out), 2 + 3);
  EXPECT_EQ(out->GetNumberOfVerts(), 0);
  EXPECT_EQ(out->GetNumberOfLines(), 0);
  EXPECT_EQ(out->GetNumberOfStrips(), 0);
  rayscope::TriangleMesh mesh;
  ASSERT_TRUE(conv->ConvertToMesh(mixed_polydata(), mesh));
  EXPECT_EQ(mesh.triangles.size(), 5u);
  EXPECT_EQ(mesh.normals.size(), mesh.positions.size());  // computed
}

// Volumetric datasets become their outer surface; non-linear cells are
// tessellated more finely at higher subdivision levels.
TEST(VtkConverter, VolumesBecomeSurfaces) {
  vtkNew<vtkRayScopeMeshConverter> conv;
  vtkNew<vtkPolyData> out;
  // 3 x 3 x 3 points of image data: a cube of 8 voxels, 6 faces of 4 quads.
  vtkNew<vtkImageData> img;
  img->SetDimensions(3, 3, 3);
  ASSERT_EQ(conv->Convert(img, out), 1);
  EXPECT_EQ(triangles(out), 6 * 4 * 2);

  vtkNew<vtkUnstructuredGrid> ug;
  vtkNew<vtkPoints> pts;
  const double corner[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (auto& c : corner) pts->InsertNextPoint(c);
  const int edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  for (auto& e : edges)
    pts->InsertNextPoint(0.5 * (corner[e[0]][0] + corner[e[1]][0]),
                         0.5 * (corner[e[0]][1] + corner[e[1]][1]) + 0.05,
                         0.5 * (corner[e[0]][2] + corner[e[1]][2]));
  ug->SetPoints(pts);
  vtkIdType ids[10] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  ug->InsertNextCell(VTK_QUADRATIC_TETRA, 10, ids);
  conv->SetNonlinearSubdivisionLevel(0);
  ASSERT_EQ(conv->Convert(ug, out), 1);
  const vtkIdType coarse = triangles(out);
  EXPECT_EQ(coarse, 4);
  conv->SetNonlinearSubdivisionLevel(2);
  ASSERT_EQ(conv->Convert(ug, out), 1);
  EXPECT_GT(triangles(out), 4 * coarse);
}

// Normals of the data are kept; missing normals are computed (split at sharp
// edges when Splitting is on) or left out.
TEST(VtkConverter, Normals) {
  vtkNew<vtkRayScopeMeshConverter> conv;
  vtkNew<vtkPolyData> out;
  vtkNew<vtkSphereSource> sphere;
  sphere->Update();
  ASSERT_EQ(conv->Convert(sphere->GetOutput(), out), 1);
  ASSERT_NE(out->GetPointData()->GetNormals(), nullptr);
  EXPECT_EQ(out->GetNumberOfPoints(), sphere->GetOutput()->GetNumberOfPoints());
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); i += 7) {
    const double* n = out->GetPointData()->GetNormals()->GetTuple3(i);
    const double* m = sphere->GetOutput()->GetPointData()->GetNormals()->GetTuple3(i);
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(n[k], m[k]);
  }

  // A cube with shared corners (8 points) and no normals.
  vtkNew<vtkCubeSource> cube;
  vtkNew<vtkCleanPolyData> clean;
  clean->SetInputConnection(cube->GetOutputPort());
  clean->Update();
  vtkNew<vtkPolyData> bare;
  bare->DeepCopy(clean->GetOutput());
  bare->GetPointData()->Initialize();
  ASSERT_EQ(bare->GetNumberOfPoints(), 8);
  ASSERT_EQ(conv->Convert(bare, out), 1);
  EXPECT_EQ(out->GetNumberOfPoints(), 24);  // split: each corner once per face
  ASSERT_NE(out->GetPointData()->GetNormals(), nullptr);
  conv->SplittingOff();
  ASSERT_EQ(conv->Convert(bare, out), 1);
  EXPECT_EQ(out->GetNumberOfPoints(), 8);
  conv->ComputeNormalsOff();
  ASSERT_EQ(conv->Convert(bare, out), 1);
  EXPECT_EQ(out->GetPointData()->GetNormals(), nullptr);
  rayscope::TriangleMesh mesh;
  conv->MeshFromPolyData(out, mesh);
  EXPECT_TRUE(mesh.normals.empty());  // the tracer then shades flat, as VTK does
}

namespace {

// What VTK's own filters give: vtkTriangleFilter, then vtkPolyDataNormals
// with its consistency pass on (the converter skips that pass only where it
// would change nothing).
vtkSmartPointer<vtkPolyData> vtk_normals(vtkPolyData* in) {
  vtkNew<vtkTriangleFilter> tf;
  tf->SetInputData(in);
  tf->PassVertsOff();
  tf->PassLinesOff();
  vtkNew<vtkPolyDataNormals> pn;
  pn->SetInputConnection(tf->GetOutputPort());
  pn->ConsistencyOn();
  pn->SplittingOn();
  pn->SetFeatureAngle(30.0);
  pn->ComputePointNormalsOn();
  pn->ComputeCellNormalsOff();
  pn->AutoOrientNormalsOff();
  pn->Update();
  return pn->GetOutput();
}

void expect_same_surface(vtkPolyData* ours, vtkPolyData* vtk, const char* what) {
  ASSERT_EQ(ours->GetNumberOfPoints(), vtk->GetNumberOfPoints()) << what;
  ASSERT_EQ(ours->GetNumberOfPolys(), vtk->GetNumberOfPolys()) << what;
  vtkDataArray* na = ours->GetPointData()->GetNormals();
  vtkDataArray* nb = vtk->GetPointData()->GetNormals();
  ASSERT_TRUE(na && nb) << what;
  for (vtkIdType i = 0; i < vtk->GetNumberOfPoints(); ++i)
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(ours->GetPoint(i)[k], vtk->GetPoint(i)[k]) << what << ": point " << i;
      ASSERT_EQ(na->GetComponent(i, k), nb->GetComponent(i, k)) << what << ": normal " << i;
    }
  vtkNew<vtkIdList> a, b;
  for (vtkIdType c = 0; c < vtk->GetNumberOfPolys(); ++c) {
    ours->GetPolys()->GetCellAtId(c, a);
    vtk->GetPolys()->GetCellAtId(c, b);
    ASSERT_EQ(a->GetNumberOfIds(), b->GetNumberOfIds()) << what << ": triangle " << c;
    for (vtkIdType k = 0; k < a->GetNumberOfIds(); ++k)
      ASSERT_EQ(a->GetId(k), b->GetId(k)) << what << ": triangle " << c;
  }
}

}  // namespace

// Computed normals are vtkPolyDataNormals' with its consistency pass, on
// meshes already ordered consistently (where the converter skips the pass)
// and on meshes that are not (a triangle flipped, an edge shared by three
// triangles, a triangle naming a point twice): the same points, normals and
// triangles, id for id.
TEST(VtkConverter, NormalsAsVtkMakesThemWithConsistentOrder) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(40);
  sphere->SetPhiResolution(20);
  sphere->Update();
  auto consistent = vtkSmartPointer<vtkPolyData>::New();
  consistent->DeepCopy(sphere->GetOutput());
  consistent->GetPointData()->Initialize();

  auto flipped = vtkSmartPointer<vtkPolyData>::New();
  flipped->DeepCopy(consistent);
  for (vtkIdType c : {vtkIdType(5), vtkIdType(200), vtkIdType(333)}) flipped->ReverseCell(c);

  // Three triangles on the edge of points 0 and 1 of a fan: non-manifold.
  vtkNew<vtkPoints> fan_points;
  for (const std::array<double, 3>& p :
       {std::array<double, 3>{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}})
    fan_points->InsertNextPoint(p.data());
  vtkNew<vtkCellArray> fan_cells;
  for (std::array<vtkIdType, 3> t : {std::array<vtkIdType, 3>{0, 1, 2}, {1, 0, 3}, {1, 0, 4}})
    fan_cells->InsertNextCell(3, t.data());
  vtkNew<vtkPolyData> fan;
  fan->SetPoints(fan_points);
  fan->SetPolys(fan_cells);

  auto repeated = vtkSmartPointer<vtkPolyData>::New();
  repeated->DeepCopy(consistent);
  const vtkIdType twice[3] = {7, 7, 8};
  repeated->GetPolys()->InsertNextCell(3, twice);

  vtkNew<vtkRayScopeMeshConverter> conv;
  vtkNew<vtkPolyData> out;
  const std::pair<const char*, vtkPolyData*> cases[] = {
      {"consistent sphere", consistent},
      {"three triangles flipped", flipped},
      {"non-manifold fan", fan},
      {"a triangle naming a point twice", repeated}};
  for (const auto& [what, mesh] : cases) {
    ASSERT_EQ(conv->Convert(mesh, out), 1) << what;
    expect_same_surface(out, vtk_normals(mesh), what);
  }
  // The flipped triangles were turned back: the consistency pass ran.
  ASSERT_EQ(conv->Convert(flipped, out), 1);
  vtkNew<vtkIdList> a, b;
  out->GetPolys()->GetCellAtId(200, a);
  consistent->GetPolys()->GetCellAtId(200, b);
  EXPECT_EQ(a->GetId(0), b->GetId(0));
  EXPECT_EQ(a->GetId(1), b->GetId(1));
}

namespace {

// A 4 x 4 quad plane with point scalars spanning [-0.5, 1.5] and cell scalars
// 0 .. 15.
vtkSmartPointer<vtkPolyData> scalar_plane() {
  vtkNew<vtkPlaneSource> plane;
  plane->SetResolution(4, 4);
  plane->Update();
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->DeepCopy(plane->GetOutput());
  pd->GetPointData()->Initialize();
  vtkNew<vtkDoubleArray> ps;
  ps->SetName("temperature");
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
    ps->InsertNextValue(-0.5 + 2.0 * double(i) / double(pd->GetNumberOfPoints() - 1));
  pd->GetPointData()->SetScalars(ps);
  vtkNew<vtkDoubleArray> cs;
  cs->SetName("region");
  for (vtkIdType i = 0; i < pd->GetNumberOfCells(); ++i) cs->InsertNextValue(double(i));
  pd->GetCellData()->SetScalars(cs);
  return pd;
}

vtkSmartPointer<vtkLookupTable> test_lut() {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetNumberOfTableValues(16);
  lut->SetHueRange(0.6, 0.0);
  lut->SetValueRange(0.4, 1.0);
  lut->Build();
  return lut;
}

// The RGBA bytes vtkLookupTable::MapValue gives for v with range [lo, hi].
std::array<unsigned char, 4> lut_color(vtkLookupTable* lut, double lo, double hi, double v) {
  vtkNew<vtkLookupTable> copy;
  copy->DeepCopy(lut);
  copy->SetRange(lo, hi);
  const unsigned char* c = copy->MapValue(v);
  return {c[0], c[1], c[2], c[3]};
}

float decode(unsigned char b) {
  float s = float(b) / 255.0f;
  return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

// Point scalars: every point gets exactly the lookup table's color for its value
// with the mapper's scalar range (clamped outside it), and its linear decoding.
TEST(VtkConverter, PointScalarsThroughLookupTable) {
  auto pd = scalar_plane();
  auto lut = test_lut();
  lut->SetRange(5.0, 6.0);
  vtkNew<vtkRayScopeMeshConverter> conv;
  conv->GetMapper()->SetLookupTable(lut);
  conv->GetMapper()->SetScalarRange(0.0, 1.0);
  const vtkMTimeType before = conv->GetMTime();
  vtkNew<vtkPolyData> out;
  ASSERT_EQ(conv->Convert(pd, out), 1);
  EXPECT_EQ(conv->GetLastColorSource(), vtkRayScopeMeshConverter::POINT_COLORS);
  // The user's table is left as it was (the converter maps with a copy), so
  // converting does not make the converter look modified.
  EXPECT_EQ(lut->GetRange()[0], 5.0);
  EXPECT_EQ(conv->GetMTime(), before);
  auto* colors = vtkUnsignedCharArray::SafeDownCast(out->GetPointData()->GetArray("Colors"));
  auto* linear = vtkFloatArray::SafeDownCast(out->GetPointData()->GetArray("LinearColors"));
  ASSERT_NE(colors, nullptr);
  ASSERT_NE(linear, nullptr);
  ASSERT_EQ(out->GetNumberOfPoints(), pd->GetNumberOfPoints());
  auto* s = pd->GetPointData()->GetScalars();
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
    auto e = lut_color(lut, 0.0, 1.0, s->GetTuple1(i));
    for (int k = 0; k < 4; ++k) EXPECT_EQ(colors->GetTypedComponent(i, k), e[k]) << i;
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(linear->GetTypedComponent(i, k), decode(e[k]));
  }

  // UseLookupTableScalarRange: the table's own range.
  lut->SetRange(-0.5, 1.5);
  conv->GetMapper()->UseLookupTableScalarRangeOn();
  ASSERT_EQ(conv->Convert(pd, out), 1);
  colors = vtkUnsignedCharArray::SafeDownCast(out->GetPointData()->GetArray("Colors"));
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
    auto e = lut_color(lut, -0.5, 1.5, s->GetTuple1(i));
    for (int k = 0; k < 3; ++k) EXPECT_EQ(colors->GetTypedComponent(i, k), e[k]) << i;
  }

  // An array with its own lookup table is mapped through that one.
  conv->GetMapper()->UseLookupTableScalarRangeOff();
  vtkNew<vtkLookupTable> own;
  own->SetHueRange(0.0, 0.3);
  own->Build();
  pd->GetPointData()->GetScalars()->SetLookupTable(own);
  ASSERT_EQ(conv->Convert(pd, out), 1);
  colors = vtkUnsignedCharArray::SafeDownCast(out->GetPointData()->GetArray("Colors"));
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
    auto e = lut_color(own, 0.0, 1.0, s->GetTuple1(i));
    for (int k = 0; k < 3; ++k) EXPECT_EQ(colors->GetTypedComponent(i, k), e[k]) << i;
  }

  // No scalar colors without scalar visibility.
  conv->GetMapper()->ScalarVisibilityOff();
  ASSERT_EQ(conv->Convert(pd, out), 1);
  EXPECT_EQ(out->GetPointData()->GetArray("Colors"), nullptr);
  EXPECT_EQ(conv->GetLastColorSource(), vtkRayScopeMeshConverter::NO_COLORS);
}

// Cell scalars: each triangle is exactly its cell's color; points shared by
// cells of different colors are duplicated, once per color.
TEST(VtkConverter, CellScalarsDuplicateSharedPoints) {
  auto pd = scalar_plane();
  auto lut = test_lut();
  vtkNew<vtkRayScopeMeshConverter> conv;
  conv->GetMapper()->SetLookupTable(lut);
  conv->GetMapper()->SetScalarModeToUseCellData();
  conv->GetMapper()->SetScalarRange(0.0, 15.0);
  vtkNew<vtkPolyData> out;
  ASSERT_EQ(conv->Convert(pd, out), 1);
  EXPECT_EQ(conv->GetLastColorSource(), vtkRayScopeMeshConverter::CELL_COLORS);
  // 16 cells of distinct colors: every cell has its own 4 corners.
  EXPECT_EQ(out->GetNumberOfPoints(), 16 * 4);
  auto* colors = vtkUnsignedCharArray::SafeDownCast(out->GetPointData()->GetArray("Colors"));
  ASSERT_NE(colors, nullptr);
  vtkNew<vtkIdList> ids;
  vtkIdType tri = 0;
  for (out->GetPolys()->InitTraversal(); out->GetPolys()->GetNextCell(ids); ++tri) {
    const vtkIdType cell = tri / 2;  // each quad became two triangles, in order
    auto e = lut_color(lut, 0.0, 15.0, double(cell));
    for (vtkIdType v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(colors->GetTypedComponent(ids->GetId(v), k), e[k]) << tri;
  }
  EXPECT_EQ(tri, 32);

  // Equal neighbors share their points: two colors in halves of the plane.
  auto* cs = pd->GetCellData()->GetScalars();
  for (vtkIdType i = 0; i < cs->GetNumberOfTuples(); ++i) cs->SetTuple1(i, i < 8 ? 0.0 : 15.0);
  cs->Modified();
  ASSERT_EQ(conv->Convert(pd, out), 1);
  EXPECT_EQ(out->GetNumberOfPoints(), 25 + 5);  // the middle row of 5 points twice
}

// Unsigned char RGB scalars are colors already (color mode default).
TEST(VtkConverter, DirectColors) {
  auto pd = scalar_plane();
  vtkNew<vtkUnsignedCharArray> rgb;
  rgb->SetName("rgb");
  rgb->SetNumberOfComponents(3);
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
    rgb->InsertNextTuple3(double(10 * i), 255 - double(10 * i), 7);
  pd->GetPointData()->SetScalars(rgb);
  vtkNew<vtkRayScopeMeshConverter> conv;
  vtkNew<vtkPolyData> out;
  ASSERT_EQ(conv->Convert(pd, out), 1);
  auto* colors = vtkUnsignedCharArray::SafeDownCast(out->GetPointData()->GetArray("Colors"));
  ASSERT_NE(colors, nullptr);
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
    EXPECT_EQ(colors->GetTypedComponent(i, 0), 10 * i);
    EXPECT_EQ(colors->GetTypedComponent(i, 1), 255 - 10 * i);
    EXPECT_EQ(colors->GetTypedComponent(i, 2), 7);
    EXPECT_EQ(colors->GetTypedComponent(i, 3), 255);
  }
}
