// vtkRayScopeMeshReader: damaged files that VTK's own readers crash on, hang
// on or read in part without a word give one error naming the file, an empty
// output and a quick return; good files give exactly what VTK's reader gives,
// as its own dataset type. Every damaged file is made here, from a good one
// written by VTK's writers. The crashing and hanging cases are never handed
// to VTK's plain readers; for the silent ones (STL) the test shows that the
// plain reader does read them without an error, part of the file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <vtkCellData.h>
#include <vtkDataSetReader.h>
#include <vtkDataSetSurfaceFilter.h>
#include <vtkDataSetWriter.h>
#include <vtkDoubleArray.h>
#include <vtkElevationFilter.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkOBJWriter.h>
#include <vtkPLYReader.h>
#include <vtkPLYWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkRectilinearGrid.h>
#include <vtkSTLReader.h>
#include <vtkSTLWriter.h>
#include <vtkSphereSource.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStructuredGrid.h>
#include <vtkTriangleFilter.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "vtkRayScopeMeshReader.h"
#include "vtk_test_util.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// A damaged file must be refused in well under this (VTK's PLY reader never
// finished the 1e8-vertex file).
constexpr double kQuickSeconds = 5.0;

std::vector<char> bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& p, const char* data, size_t n) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(data, std::streamsize(n));
  ASSERT_TRUE(out.good()) << p;
}

void write_text(const fs::path& p, const std::string& text) {
  write_bytes(p, text.data(), text.size());
}

// Triangulated sphere with a point array "Elevation", as every writer takes.
vtkSmartPointer<vtkPolyData> sphere() {
  vtkNew<vtkSphereSource> s;
  s->SetThetaResolution(16);
  s->SetPhiResolution(8);
  vtkNew<vtkElevationFilter> e;
  e->SetInputConnection(s->GetOutputPort());
  vtkNew<vtkTriangleFilter> t;
  t->SetInputConnection(e->GetOutputPort());
  t->Update();
  vtkSmartPointer<vtkPolyData> pd = vtkSmartPointer<vtkPolyData>::New();
  pd->DeepCopy(t->GetOutput());
  return pd;
}

// The same points, cells (types and point ids) and point and cell arrays
// (names, sizes, values), in the same order.
void expect_same_dataset(vtkDataSet* a, vtkDataSet* b) {
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  EXPECT_STREQ(a->GetClassName(), b->GetClassName());
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells());
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i) {
    double pa[3], pb[3];
    a->GetPoint(i, pa);
    b->GetPoint(i, pb);
    for (int k = 0; k < 3; ++k) ASSERT_EQ(pa[k], pb[k]) << "point " << i;
  }
  vtkNew<vtkIdList> ia, ib;
  for (vtkIdType c = 0; c < a->GetNumberOfCells(); ++c) {
    ASSERT_EQ(a->GetCellType(c), b->GetCellType(c)) << "cell " << c;
    a->GetCellPoints(c, ia);
    b->GetCellPoints(c, ib);
    ASSERT_EQ(ia->GetNumberOfIds(), ib->GetNumberOfIds()) << "cell " << c;
    for (vtkIdType k = 0; k < ia->GetNumberOfIds(); ++k)
      ASSERT_EQ(ia->GetId(k), ib->GetId(k)) << "cell " << c;
  }
  for (auto [fa, fb] :
       {std::pair<vtkFieldData*, vtkFieldData*>{a->GetPointData(), b->GetPointData()},
        {a->GetCellData(), b->GetCellData()}}) {
    ASSERT_EQ(fa->GetNumberOfArrays(), fb->GetNumberOfArrays());
    for (int k = 0; k < fa->GetNumberOfArrays(); ++k) {
      vtkDataArray* xa = fa->GetArray(k);
      vtkDataArray* xb = fb->GetArray(k);
      ASSERT_TRUE(xa && xb);
      EXPECT_STREQ(xa->GetName(), xb->GetName());
      ASSERT_EQ(xa->GetNumberOfValues(), xb->GetNumberOfValues());
      for (vtkIdType v = 0; v < xa->GetNumberOfValues(); ++v)
        ASSERT_EQ(xa->GetVariantValue(v), xb->GetVariantValue(v)) << xa->GetName();
    }
  }
}

class VtkMeshReader : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rayscope_mesh_reader_" + std::to_string(getpid()));
    fs::create_directories(dir_);
    reader_->AddObserver(vtkCommand::ErrorEvent, errors_);
    // The executive's own "returned failure" message, kept out of the log.
    reader_->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, executive_errors_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  // Reads `p` with the reader under test; its Update() result.
  int read(const fs::path& p) {
    reader_->SetFileName(p.c_str());
    return update(reader_);
  }

  // `p` is refused quickly with one error naming it and saying `problem`, and
  // the output is an empty dataset.
  void expect_refused(const fs::path& p, const std::string& problem) {
    const int before = errors_->count;
    const Clock::time_point start = Clock::now();
    EXPECT_EQ(read(p), 0) << p;
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    EXPECT_LT(seconds, kQuickSeconds) << p;
    EXPECT_EQ(errors_->count, before + 1) << p;
    EXPECT_NE(errors_->last.find(p.string() + ": "), std::string::npos) << errors_->last;
    EXPECT_NE(errors_->last.find(problem), std::string::npos) << errors_->last;
    vtkDataSet* out = reader_->GetOutput();
    ASSERT_NE(out, nullptr);
    EXPECT_EQ(out->GetNumberOfPoints(), 0);
    EXPECT_EQ(out->GetNumberOfCells(), 0);
    EXPECT_EQ(out->GetPointData()->GetNumberOfArrays(), 0);
  }

  // `p` reads without an error to what `plain` (VTK's reader) gives.
  void expect_same_as(const fs::path& p, vtkAlgorithm* plain) {
    const int before = errors_->count;
    vtkNew<ErrorCatcher> warnings;
    const unsigned long tag = reader_->AddObserver(vtkCommand::WarningEvent, warnings);
    ASSERT_EQ(read(p), 1) << errors_->last;
    reader_->RemoveObserver(tag);
    EXPECT_EQ(errors_->count, before);
    EXPECT_EQ(warnings->count, 0) << warnings->last;
    plain->Update();
    expect_same_dataset(reader_->GetOutput(),
                        vtkDataSet::SafeDownCast(plain->GetOutputDataObject(0)));
  }

  fs::path binary_stl() {
    fs::path p = dir_ / "sphere.stl";
    vtkNew<vtkSTLWriter> w;
    w->SetFileName(p.c_str());
    w->SetInputData(sphere());
    w->SetFileTypeToBinary();
    EXPECT_EQ(w->Write(), 1);
    return p;
  }

  fs::path ascii_ply() {
    fs::path p = dir_ / "sphere.ply";
    vtkNew<vtkPLYWriter> w;
    w->SetFileName(p.c_str());
    w->SetInputData(sphere());
    w->SetFileTypeToASCII();
    EXPECT_EQ(w->Write(), 1);
    return p;
  }

  // Triangles the plain STL reader gets from `p`, and whether it reported an
  // error.
  static std::pair<vtkIdType, int> plain_stl(const fs::path& p) {
    vtkNew<vtkSTLReader> r;
    vtkNew<ErrorCatcher> errors;
    r->AddObserver(vtkCommand::ErrorEvent, errors);
    r->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    r->SetFileName(p.c_str());
    update(r);
    return {r->GetOutput()->GetNumberOfPolys(), errors->count};
  }

  fs::path dir_;
  vtkNew<vtkRayScopeMeshReader> reader_;
  vtkNew<ErrorCatcher> errors_;
  vtkNew<ErrorCatcher> executive_errors_;
};

// --- damaged files --------------------------------------------------------

// vtkPLYReader aborts (a bad free() in glibc) on an ASCII body that ends early.
TEST_F(VtkMeshReader, TruncatedAsciiPly) {
  const std::vector<char> good = bytes_of(ascii_ply());
  const fs::path cut = dir_ / "truncated.ply";
  write_bytes(cut, good.data(), good.size() * 2 / 3);
  expect_refused(cut, "truncated PLY: the header declares");
}

// vtkPLYReader: loops "unexpected end of file" for 1e8 vertices, never ends.
TEST_F(VtkMeshReader, PlyDeclaringHundredMillionVertices) {
  const fs::path p = dir_ / "huge.ply";
  write_text(p,
             "ply\nformat ascii 1.0\nelement vertex 100000000\n"
             "property float x\nproperty float y\nproperty float z\n"
             "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expect_refused(p, "truncated PLY: the header declares 100000000 vertex elements");
}

// vtkSTLReader reads the triangles that are there and says nothing.
TEST_F(VtkMeshReader, TruncatedBinaryStl) {
  const fs::path good = binary_stl();
  const std::vector<char> b = bytes_of(good);
  const fs::path cut = dir_ / "truncated.stl";
  write_bytes(cut, b.data(), b.size() - 75);  // one and a half triangles short
  const auto [triangles, plain_errors] = plain_stl(cut);
  EXPECT_EQ(plain_errors, 0);  // what issue 31 is about: silent
  EXPECT_EQ(triangles, plain_stl(good).first - 2);
  expect_refused(cut, "truncated binary STL");
}

// A header declaring more triangles than the body has: the same silent loss.
TEST_F(VtkMeshReader, OverDeclaredBinaryStl) {
  std::vector<char> b = bytes_of(binary_stl());
  uint32_t count = 0;
  std::memcpy(&count, b.data() + 80, 4);
  count += 5;
  std::memcpy(b.data() + 80, &count, 4);
  const fs::path p = dir_ / "overdeclared.stl";
  write_bytes(p, b.data(), b.size());
  const auto [triangles, plain_errors] = plain_stl(p);
  EXPECT_EQ(plain_errors, 0);
  EXPECT_EQ(triangles, vtkIdType(count) - 5);
  expect_refused(p, "the header declares " + std::to_string(count) + " triangles");
}

TEST_F(VtkMeshReader, MissingFile) {
  expect_refused(dir_ / "nowhere.stl", "file not found");
}

TEST_F(VtkMeshReader, NoFileName) {
  EXPECT_EQ(update(reader_), 0);
  EXPECT_EQ(errors_->count, 1);
  EXPECT_NE(errors_->last.find("FileName is not set"), std::string::npos) << errors_->last;
}

TEST_F(VtkMeshReader, UnsupportedExtension) {
  const fs::path p = dir_ / "mesh.txt";
  write_text(p, "not a mesh\n");
  expect_refused(p, "unsupported mesh format '.txt'");
}

// VTK's readers read these as empty datasets without an error.
TEST_F(VtkMeshReader, FilesWithoutPoints) {
  const fs::path obj = dir_ / "comments.obj";
  write_text(obj, "# an OBJ file cut off before its first vertex\n");
  expect_refused(obj, "holds no points");
  const fs::path stl = dir_ / "empty.stl";
  write_text(stl, "solid empty\nendsolid empty\n");
  expect_refused(stl, "holds no points");
}

// The legacy reader copies point ids unchecked; VTK's filters then index the
// points with them.
TEST_F(VtkMeshReader, LegacyPointIdOutOfRange) {
  const fs::path p = dir_ / "bad_id.vtk";
  write_text(p,
             "# vtk DataFile Version 3.0\nbad id\nASCII\nDATASET POLYDATA\n"
             "POINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 7\n");
  expect_refused(p, "cell 0 refers to point 7 but the data has 3 points");
}

// A valid OBJ whose one 'vn' line no face names: vtkOBJReader attaches it as
// a "Normals" array of 1 tuple for 4 points, which VTK's filters read past
// its end. The reader reads the file and removes that array with a warning.
TEST_F(VtkMeshReader, ObjNormalsNoFaceNames) {
  const fs::path p = dir_ / "unused_normal.obj";
  write_text(p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nf 1 2 3\nf 2 4 3\n");
  vtkNew<vtkOBJReader> plain;
  plain->SetFileName(p.c_str());
  plain->Update();
  vtkPolyData* vtk_data = plain->GetOutput();
  ASSERT_NE(vtk_data->GetPointData()->GetNormals(), nullptr);
  EXPECT_EQ(vtk_data->GetPointData()->GetNormals()->GetNumberOfTuples(), 1);
  EXPECT_EQ(vtk_data->GetNumberOfPoints(), 4);

  vtkNew<ErrorCatcher> warnings;
  reader_->AddObserver(vtkCommand::WarningEvent, warnings);
  ASSERT_EQ(read(p), 1) << errors_->last;
  EXPECT_EQ(errors_->count, 0);
  EXPECT_EQ(warnings->count, 1);
  EXPECT_NE(warnings->last.find(p.string() +
                                ": removed point array 'Normals' has 1 tuple but the data has 4 "
                                "points"),
            std::string::npos)
      << warnings->last;
  vtkDataSet* out = reader_->GetOutput();
  EXPECT_EQ(out->GetNumberOfPoints(), 4);
  EXPECT_EQ(out->GetNumberOfCells(), 2);
  EXPECT_EQ(out->GetPointData()->GetNumberOfArrays(), 0);
}

// A good file after a damaged one reads; a damaged one after a good one
// leaves no stale data.
TEST_F(VtkMeshReader, RecoversAndLeavesNoStaleData) {
  const fs::path good = binary_stl();
  const fs::path missing = dir_ / "missing.stl";
  expect_refused(missing, "file not found");
  ASSERT_EQ(read(good), 1) << errors_->last;
  EXPECT_GT(reader_->GetOutput()->GetNumberOfCells(), 0);
  expect_refused(missing, "file not found");
}

// --- good files: what VTK's reader gives, as its own type ------------------

TEST_F(VtkMeshReader, SameAsVtkReaders) {
  vtkSmartPointer<vtkPolyData> pd = sphere();
  {
    vtkNew<vtkSTLReader> plain;
    plain->SetFileName(binary_stl().c_str());
    expect_same_as(plain->GetFileName(), plain);
  }
  {
    vtkNew<vtkPLYReader> plain;
    plain->SetFileName(ascii_ply().c_str());
    expect_same_as(plain->GetFileName(), plain);
  }
  {
    const fs::path p = dir_ / "sphere.vtp";
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetFileName(p.c_str());
    w->SetInputData(pd);
    ASSERT_EQ(w->Write(), 1);
    vtkNew<vtkXMLPolyDataReader> plain;
    plain->SetFileName(p.c_str());
    expect_same_as(p, plain);
  }
  {
    vtkNew<vtkUnstructuredGrid> ug;
    ug->SetPoints(pd->GetPoints());
    ug->GetPointData()->ShallowCopy(pd->GetPointData());
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c) {
      pd->GetCellPoints(c, ids);
      ug->InsertNextCell(VTK_TRIANGLE, ids);
    }
    const fs::path p = dir_ / "sphere.vtu";
    vtkNew<vtkXMLUnstructuredGridWriter> w;
    w->SetFileName(p.c_str());
    w->SetInputData(ug);
    ASSERT_EQ(w->Write(), 1);
    vtkNew<vtkXMLUnstructuredGridReader> plain;
    plain->SetFileName(p.c_str());
    expect_same_as(p, plain);
    EXPECT_TRUE(reader_->GetOutput()->IsA("vtkUnstructuredGrid"));
  }
  {
    const fs::path p = dir_ / "sphere.obj";
    vtkNew<vtkOBJWriter> w;
    w->SetFileName(p.c_str());
    w->SetInputData(pd);
    ASSERT_EQ(w->Write(), 1);
    vtkNew<vtkOBJReader> plain;
    plain->SetFileName(p.c_str());
    expect_same_as(p, plain);
  }
  {
    const fs::path p = dir_ / "sphere_legacy.VTK";  // any letter case
    vtkNew<vtkDataSetWriter> w;
    w->SetFileName(p.c_str());
    w->SetInputData(pd);
    ASSERT_EQ(w->Write(), 1);
    vtkNew<vtkDataSetReader> plain;
    plain->SetFileName(p.c_str());
    expect_same_as(p, plain);
  }
}

// A legacy file of image data gives image data with its extent, origin and
// spacing, announced before the data is read (RequestInformation).
TEST_F(VtkMeshReader, LegacyImageData) {
  vtkNew<vtkImageData> image;
  image->SetExtent(0, 3, 0, 2, 0, 1);
  image->SetOrigin(1.0, 2.0, 3.0);
  image->SetSpacing(0.5, 0.25, 2.0);
  image->AllocateScalars(VTK_FLOAT, 1);
  for (vtkIdType i = 0; i < image->GetNumberOfPoints(); ++i)
    image->GetPointData()->GetScalars()->SetTuple1(i, double(i));
  const fs::path p = dir_ / "image.vtk";
  vtkNew<vtkDataSetWriter> w;
  w->SetFileName(p.c_str());
  w->SetInputData(image);
  ASSERT_EQ(w->Write(), 1);

  reader_->SetFileName(p.c_str());
  reader_->UpdateInformation();
  int whole[6];
  reader_->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  EXPECT_EQ(std::vector<int>(whole, whole + 6), (std::vector<int>{0, 3, 0, 2, 0, 1}));

  vtkNew<vtkDataSetReader> plain;
  plain->SetFileName(p.c_str());
  expect_same_as(p, plain);
  auto* out = vtkImageData::SafeDownCast(reader_->GetOutput());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(out->GetSpacing()[1], 0.25);
  EXPECT_EQ(out->GetOrigin()[2], 3.0);
}

// Legacy structured and rectilinear grids: their own types, their extents
// announced, and VTK's filters take them (the surface of a 3 x 2 x 2 grid).
TEST_F(VtkMeshReader, LegacyGrids) {
  vtkNew<vtkRectilinearGrid> rgrid;
  rgrid->SetDimensions(3, 2, 2);
  vtkNew<vtkDoubleArray> x, yz;
  for (double v : {0.0, 0.5, 1.0}) x->InsertNextValue(v);
  for (double v : {0.0, 2.0}) yz->InsertNextValue(v);
  rgrid->SetXCoordinates(x);
  rgrid->SetYCoordinates(yz);
  rgrid->SetZCoordinates(yz);
  vtkNew<vtkStructuredGrid> sgrid;
  sgrid->SetDimensions(3, 2, 2);
  vtkNew<vtkPoints> points;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) points->InsertNextPoint(i, j, k * 0.5);
  sgrid->SetPoints(points);
  for (vtkDataSet* grid : {static_cast<vtkDataSet*>(rgrid), static_cast<vtkDataSet*>(sgrid)}) {
    const fs::path p = dir_ / (std::string(grid->GetClassName()) + ".vtk");
    vtkNew<vtkDataSetWriter> w;
    w->SetFileName(p.c_str());
    w->SetInputData(grid);
    ASSERT_EQ(w->Write(), 1);
    vtkNew<vtkDataSetReader> plain;
    plain->SetFileName(p.c_str());
    expect_same_as(p, plain);
    int whole[6];
    reader_->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
    EXPECT_EQ(std::vector<int>(whole, whole + 6), (std::vector<int>{0, 2, 0, 1, 0, 1}));
    vtkNew<vtkDataSetSurfaceFilter> surface;
    surface->SetInputConnection(reader_->GetOutputPort());
    surface->Update();
    EXPECT_EQ(surface->GetOutput()->GetNumberOfCells(), 10) << p;  // 2 + 2 + 4 + 2 quads
  }
}

// The output's type follows the file: an unstructured grid, then polydata.
TEST_F(VtkMeshReader, OutputTypeFollowsTheFile) {
  vtkSmartPointer<vtkPolyData> pd = sphere();
  vtkNew<vtkUnstructuredGrid> ug;
  ug->SetPoints(pd->GetPoints());
  const fs::path vtu = dir_ / "points.vtu";
  vtkNew<vtkXMLUnstructuredGridWriter> w;
  w->SetFileName(vtu.c_str());
  w->SetInputData(ug);
  ASSERT_EQ(w->Write(), 1);
  ASSERT_EQ(read(vtu), 1) << errors_->last;
  EXPECT_STREQ(reader_->GetOutput()->GetClassName(), "vtkUnstructuredGrid");
  ASSERT_EQ(read(binary_stl()), 1) << errors_->last;
  EXPECT_STREQ(reader_->GetOutput()->GetClassName(), "vtkPolyData");
  EXPECT_GT(reader_->GetOutput()->GetNumberOfCells(), 0);
}

TEST_F(VtkMeshReader, CanReadFile) {
  const fs::path stl = binary_stl();
  EXPECT_EQ(reader_->CanReadFile(stl.c_str()), 1);
  const fs::path upper = dir_ / "MESH.PLY";
  write_text(upper, "ply\n");  // damaged, still offered: the read explains
  EXPECT_EQ(reader_->CanReadFile(upper.c_str()), 1);
  const fs::path txt = dir_ / "mesh.txt";
  write_text(txt, "");
  EXPECT_EQ(reader_->CanReadFile(txt.c_str()), 0);
  EXPECT_EQ(reader_->CanReadFile((dir_ / "missing.obj").c_str()), 0);
  fs::create_directories(dir_ / "folder.vtp");
  EXPECT_EQ(reader_->CanReadFile((dir_ / "folder.vtp").c_str()), 0);
  EXPECT_EQ(reader_->CanReadFile(nullptr), 0);
}

}  // namespace
