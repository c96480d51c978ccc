// read_plain_obj_file() (rayscope_vtkio/plain_obj.h), the one-pass reader of
// OBJ files made of vertices and faces only, against VTK's own vtkOBJReader:
// the same points bit for bit, the same polygons id for id, the same cell
// arrays, on the Stanford bunny, on files built to try its parsing, and on
// random files. Every file outside that subset is left to vtkOBJReader
// (null), and read_dataset_file() then reads it as before.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include "rayscope_vtkio/mesh_files.h"
#include "rayscope_vtkio/plain_obj.h"

namespace {

namespace fs = std::filesystem;
using rayscope_vtkio::read_plain_obj_file;

vtkSmartPointer<vtkPolyData> vtk_read(const fs::path& p) {
  vtkNew<vtkOBJReader> r;
  r->SetFileName(p.string().c_str());
  r->Update();
  return r->GetOutput();
}

// Every point coordinate, polygon id and cell array value equal.
void expect_same(vtkPolyData* ours, vtkPolyData* vtk, const std::string& what) {
  ASSERT_TRUE(ours) << what;
  ASSERT_EQ(ours->GetNumberOfPoints(), vtk->GetNumberOfPoints()) << what;
  ASSERT_EQ(ours->GetPoints()->GetDataType(), vtk->GetPoints()->GetDataType()) << what;
  EXPECT_EQ(std::string(ours->GetPoints()->GetData()->GetName()),
            std::string(vtk->GetPoints()->GetData()->GetName()));
  for (vtkIdType i = 0; i < vtk->GetNumberOfPoints(); ++i) {
    double a[3], b[3];
    ours->GetPoint(i, a);
    vtk->GetPoint(i, b);
    ASSERT_EQ(std::memcmp(a, b, sizeof a), 0)
        << what << ": point " << i << ": " << a[0] << " " << a[1] << " " << a[2] << " vs " << b[0]
        << " " << b[1] << " " << b[2];
  }
  EXPECT_EQ(ours->GetNumberOfVerts(), 0) << what;
  EXPECT_EQ(ours->GetNumberOfLines(), 0) << what;
  vtkCellArray* pa = ours->GetPolys();
  vtkCellArray* pb = vtk->GetPolys();
  ASSERT_EQ(pa->GetNumberOfCells(), pb->GetNumberOfCells()) << what;
  ASSERT_EQ(pa->IsStorage64Bit(), pb->IsStorage64Bit()) << what;
  for (vtkIdType c = 0; c < pb->GetNumberOfCells(); ++c) {
    vtkIdType na = 0, nb = 0;
    const vtkIdType *ia = nullptr, *ib = nullptr;
    vtkNew<vtkIdList> la, lb;
    pa->GetCellAtId(c, la);
    pb->GetCellAtId(c, lb);
    na = la->GetNumberOfIds();
    nb = lb->GetNumberOfIds();
    ia = la->GetPointer(0);
    ib = lb->GetPointer(0);
    ASSERT_EQ(na, nb) << what << ": polygon " << c;
    for (vtkIdType k = 0; k < na; ++k) ASSERT_EQ(ia[k], ib[k]) << what << ": polygon " << c;
  }
  EXPECT_EQ(ours->GetPointData()->GetNumberOfArrays(), vtk->GetPointData()->GetNumberOfArrays());
  EXPECT_EQ(ours->GetFieldData()->GetNumberOfArrays(), vtk->GetFieldData()->GetNumberOfArrays());
  vtkCellData* ca = ours->GetCellData();
  vtkCellData* cb = vtk->GetCellData();
  ASSERT_EQ(ca->GetNumberOfArrays(), cb->GetNumberOfArrays()) << what;
  for (int k = 0; k < cb->GetNumberOfArrays(); ++k) {
    vtkDataArray* b = cb->GetArray(k);
    vtkDataArray* a = ca->GetArray(b->GetName());
    ASSERT_TRUE(a) << what << ": cell array " << b->GetName();
    EXPECT_EQ(a->GetDataType(), b->GetDataType());
    EXPECT_EQ(ca->IsArrayAnAttribute(k), cb->IsArrayAnAttribute(k));
    ASSERT_EQ(a->GetNumberOfTuples(), b->GetNumberOfTuples());
    for (vtkIdType t = 0; t < b->GetNumberOfTuples(); ++t)
      ASSERT_EQ(a->GetComponent(t, 0), b->GetComponent(t, 0));
  }
}

class PlainObj : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rayscope_plain_obj_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  fs::path dir_;
};

TEST_F(PlainObj, TheBunnyAsVtkReadsIt) {
  const fs::path bunny = "/usr/share/glmark2/models/bunny.obj";
  if (!fs::exists(bunny)) GTEST_SKIP() << bunny << " is not installed (glmark2-data)";
  vtkSmartPointer<vtkPolyData> ours = read_plain_obj_file(bunny);
  vtkSmartPointer<vtkPolyData> vtk = vtk_read(bunny);
  ASSERT_EQ(vtk->GetNumberOfPolys(), 69666);
  expect_same(ours, vtk, "bunny");
}

TEST_F(PlainObj, ParsingCasesAsVtkReadsThem) {
  const char* cases[][2] = {
      {"comments_blank_lines",
       "# made by hand\n\nv 0 0 0\n#v 9 9 9\nv 1 0 0\nv 0 1 0\n\nf 1 2 3\n"},
      {"crlf", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n"},
      {"tabs_and_spaces", "v\t0  0\t0\nv 1 0 0   \n  v 0 1 0\nf\t1 2\t3  \n"},
      {"w_coordinate", "v 0 0 0 1\nv 1 0 0 1.0\nv 0 1 0 0.5\nf 1 2 3\n"},
      {"negative_indices", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf -3 -1 -2\n"},
      {"quads_and_ngons",
       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\nf 1 2 3 4\nf 1 4 5\n"
       "f 1 2 3 4 5\n"},
      {"number_forms",
       "v 1e-3 -2.5E+2 .5\nv -0 3.40282347e+38 1.17549435e-38\nv "
       "0.1000000000000000055511151231257827"
       " 1.00000005960464477539 1.0000000596046447753907\nv 1.4e-45 -3e-44 "
       "123456789012345678901234567890\n"
       "f 1 2 3\nf 2 3 4\n"},
      {"no_final_newline", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3"},
  };
  for (const auto& c : cases) {
    const fs::path p = write(std::string(c[0]) + ".obj", c[1]);
    expect_same(read_plain_obj_file(p), vtk_read(p), c[0]);
  }
}

// Random plain files: coordinates in several notations and precisions, faces
// of 3 to 6 corners named by positive or negative indices, random blanks.
TEST_F(PlainObj, RandomFilesAsVtkReadsThem) {
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> coord(-1e3, 1e3);
  std::uniform_int_distribution<int> pick(0, 1 << 20);
  const char* formats[] = {"%.17g", "%.9g", "%.6f", "%.3e", "%g", "%.12E"};
  const char* blanks[] = {" ", "  ", "\t", " \t"};
  for (int file = 0; file < 40; ++file) {
    std::string text;
    int vertices = 0;
    for (int line = 0; line < 300; ++line) {
      if (vertices < 3 || pick(rng) % 3 == 0) {
        text += "v";
        for (int k = 0; k < 3; ++k) {
          char buf[64];
          double x = coord(rng);
          if (pick(rng) % 5 == 0) x *= 1e-30;
          std::snprintf(buf, sizeof buf, formats[pick(rng) % 6], x);
          text += blanks[pick(rng) % 4];
          text += buf;
        }
        ++vertices;
      } else {
        text += "f";
        const int n = 3 + pick(rng) % 4;
        for (int k = 0; k < n; ++k) {
          const int i = 1 + pick(rng) % vertices;
          text += blanks[pick(rng) % 4];
          text += std::to_string(pick(rng) % 2 ? i : i - vertices - 1);
        }
      }
      text += pick(rng) % 7 == 0 ? "\r\n" : "\n";
    }
    const fs::path p = write("random" + std::to_string(file) + ".obj", text);
    expect_same(read_plain_obj_file(p), vtk_read(p), p.filename().string());
  }
}

// Files outside the subset are vtkOBJReader's: null here, and
// read_dataset_file() reads them as before (texture coordinates, normals and
// groups kept; a bad index is check_obj_file()'s one error line).
TEST_F(PlainObj, OtherFilesAreLeftToVtk) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const char* cases[][2] = {
      {"texture", "vt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n"},
      {"normals", "vn 0 0 1\nf 1//1 2//1 3//1\n"},
      {"group", "g bunny\nf 1 2 3\n"},
      {"object", "o thing\nf 1 2 3\n"},
      {"smoothing", "s off\nf 1 2 3\n"},
      {"material", "mtllib a.mtl\nusemtl red\nf 1 2 3\n"},
      {"line", "l 1 2\n"},
      {"point", "p 1\n"},
      {"two_corners", "f 1 2\n"},
      {"trailing_comment", "f 1 2 3 # a triangle\n"},
      {"plus_sign", "v +1 0 0\nf 1 2 3\n"},
      {"two_coordinates", "v 1 0\nf 1 2 3\n"},
      {"colors", "v 1 0 0 0.5 0.5 0.5\nf 1 2 3\n"},
      {"index_zero", "f 0 1 2\n"},
      {"index_too_large", "f 1 2 4\n"},
      {"index_too_negative", "f -4 1 2\n"},
      {"no_faces", ""},
      {"underflow", "v 1e-46 0 0\nf 1 2 3\n"},
      {"overflow", "v 1e39 0 0\nf 1 2 3\n"},
  };
  for (const auto& c : cases) {
    const fs::path p = write(std::string(c[0]) + ".obj", tri + c[1]);
    EXPECT_FALSE(read_plain_obj_file(p)) << c[0];
  }
  EXPECT_FALSE(read_plain_obj_file(dir_ / "missing.obj"));
  EXPECT_FALSE(read_plain_obj_file(write("empty.obj", "")));

  // Through read_dataset_file(): normals kept as VTK reads them...
  const fs::path normals = write("normals2.obj", tri + "vn 0 0 1\nf 1//1 2//1 3//1\n");
  vtkSmartPointer<vtkDataSet> d = rayscope_vtkio::read_dataset_file(normals);
  ASSERT_TRUE(d);
  ASSERT_TRUE(d->GetPointData()->GetNormals());
  EXPECT_EQ(d->GetNumberOfCells(), 1);
  // ... and a bad index is the checker's error naming the file and the line.
  const fs::path bad = write("bad.obj", tri + "f 1 2 4\n");
  try {
    rayscope_vtkio::read_dataset_file(bad);
    FAIL() << "no error for an index out of range";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(bad.string()), std::string::npos) << m;
    EXPECT_NE(m.find("line 4"), std::string::npos) << m;
  }
  // A plain file goes the one-pass way and reads as VTK reads it.
  const fs::path plain = write("plain.obj", tri + "f 1 2 3\n");
  d = rayscope_vtkio::read_dataset_file(plain);
  expect_same(vtkPolyData::SafeDownCast(d), vtk_read(plain), "read_dataset_file");
}

}  // namespace
