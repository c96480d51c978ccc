// The rayscope command's mesh files (rayscope_vtkio::load_meshes,
// vtkplugin/vtkio) against the VTK module's converter: the same file gives the
// same triangles, normals and colors, normals are computed smooth when the
// file has none, and a scene file's color_by reaches the loader and colors the
// mesh, one lookup table over every block of a composite file; STL, OBJ and
// legacy VTK files read as triangles (counts, closed meshes, "FILE: problem"
// errors), in scene files too.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCompositeDataSet.h>
#include <vtkCubeSource.h>
#include <vtkDataSetMapper.h>
#include <vtkFloatArray.h>
#include <vtkInformation.h>
#include <vtkLineSource.h>
#include <vtkLookupTable.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSTLWriter.h>
#include <vtkSmartPointer.h>
#include <vtkSphereSource.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLMultiBlockDataWriter.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <glm/gtc/matrix_transform.hpp>

#include "../obj_samples.h"
#include "rayscope/scene_io.h"
#include "rayscope_vtkio/mesh_files.h"
#include "vtkRayScopeMeshConverter.h"

namespace {

namespace fs = std::filesystem;
using rayscope::MeshColorBy;
using rayscope::MeshOptions;
using rayscope::TriangleMesh;
using rayscope::Vec3;

class VtkMeshFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rayscope_mesh_files_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  // A sphere without normals, as .vtp.
  fs::path sphere_vtp() {
    vtkNew<vtkSphereSource> s;
    s->SetRadius(1.0);
    s->SetThetaResolution(24);
    s->SetPhiResolution(12);
    s->Update();
    vtkNew<vtkPolyData> pd;
    pd->DeepCopy(s->GetOutput());
    pd->GetPointData()->SetNormals(nullptr);
    return write_vtp(pd, "sphere.vtp");
  }
  // `pd` written as dir_/name by VTK's XML writer.
  fs::path write_vtp(vtkPolyData* pd, const std::string& name) {
    const fs::path p = dir_ / name;
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetFileName(p.c_str());
    w->SetInputData(pd);
    EXPECT_EQ(w->Write(), 1);
    return p;
  }
  // A cube as binary STL (no normals; sharp edges).
  fs::path cube_stl() {
    vtkNew<vtkCubeSource> c;
    vtkNew<vtkTriangleFilter> t;
    t->SetInputConnection(c->GetOutputPort());
    fs::path p = dir_ / "cube.stl";
    vtkNew<vtkSTLWriter> w;
    w->SetFileName(p.c_str());
    w->SetInputConnection(t->GetOutputPort());
    EXPECT_EQ(w->Write(), 1);
    return p;
  }
  fs::path dir_;
};

// What the module makes of `file` read by VTK's `Reader`: its default
// converter, coloring with `mapper` when given.
template <class Reader>
TriangleMesh module_mesh(const fs::path& file, vtkMapper* mapper = nullptr) {
  vtkNew<Reader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkNew<vtkRayScopeMeshConverter> converter;
  if (mapper) converter->SetMapper(mapper);
  TriangleMesh m;
  EXPECT_TRUE(converter->ConvertToMesh(reader->GetOutput(), m));
  return m;
}

MeshOptions file_options(const fs::path& file) {
  MeshOptions o;
  o.file = file;
  return o;
}

void expect_same(const TriangleMesh& a, const TriangleMesh& b) {
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.colors, b.colors);
}

// A regular tetrahedron as an ASCII STL (4 facets).
const char* kTetraStl = R"(solid tetra
facet normal 0 0 -1
 outer loop
  vertex 0 0 0
  vertex 0 1 0
  vertex 1 0 0
 endloop
endfacet
facet normal 0 -1 0
 outer loop
  vertex 0 0 0
  vertex 1 0 0
  vertex 0 0 1
 endloop
endfacet
facet normal -1 0 0
 outer loop
  vertex 0 0 0
  vertex 0 0 1
  vertex 0 1 0
 endloop
endfacet
facet normal 1 1 1
 outer loop
  vertex 1 0 0
  vertex 0 1 0
  vertex 0 0 1
 endloop
endfacet
endsolid tetra
)";

using rstest::kQuadObj;

// Legacy VTK unstructured grid with one hexahedron: its boundary is 6 quads,
// 12 triangles.
const char* kHexVtk = R"(# vtk DataFile Version 3.0
one hexahedron
ASCII
DATASET UNSTRUCTURED_GRID
POINTS 8 float
0 0 0  1 0 0  1 1 0  0 1 0
0 0 1  1 0 1  1 1 1  0 1 1
CELLS 1 9
8 0 1 2 3 4 5 6 7
CELL_TYPES 1
12
)";

TEST_F(VtkMeshFiles, MeshReaderTriangleCounts) {
  std::ofstream(dir_ / "tetra.stl") << kTetraStl;
  std::ofstream(dir_ / "quad.obj") << kQuadObj;
  std::ofstream(dir_ / "hex.vtk") << kHexVtk;
  std::ofstream(dir_ / "mesh.xyz") << "1 2 3\n";
  TriangleMesh tetra = rayscope_vtkio::read_mesh_file(dir_ / "tetra.stl");
  EXPECT_EQ(tetra.triangles.size(), 4u);
  EXPECT_EQ(tetra.positions.size(), 4u);  // the STL reader merges shared corners
  TriangleMesh quad = rayscope_vtkio::read_mesh_file(dir_ / "quad.obj");
  EXPECT_EQ(quad.triangles.size(), 3u);
  EXPECT_EQ(quad.positions.size(), 5u);
  TriangleMesh hex = rayscope_vtkio::read_mesh_file(dir_ / "hex.vtk");
  EXPECT_EQ(hex.triangles.size(), 12u);
  EXPECT_EQ(hex.positions.size(), 8u);
  for (const TriangleMesh* m : {&tetra, &quad, &hex})
    for (const glm::uvec3& t : m->triangles)
      EXPECT_TRUE(t.x < m->positions.size() && t.y < m->positions.size() &&
                  t.z < m->positions.size());
  // The closed meshes are closed: every edge is shared by exactly two triangles.
  for (const TriangleMesh* m : {&tetra, &hex}) {
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (const glm::uvec3& t : m->triangles)
      for (int e = 0; e < 3; ++e) edges[std::minmax(t[e], t[(e + 1) % 3])]++;
    for (const auto& [edge, n] : edges) EXPECT_EQ(n, 2);
  }
  // Errors: "FILE: problem".
  try {
    rayscope_vtkio::read_mesh_file(dir_ / "missing.obj");
    ADD_FAILURE() << "no error for a missing file";
  } catch (const std::exception& e) {
    EXPECT_EQ(std::string(e.what()), (dir_ / "missing.obj").string() + ": file not found");
  }
  try {
    rayscope_vtkio::read_mesh_file(dir_ / "mesh.xyz");
    ADD_FAILURE() << "no error for an unsupported format";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("unsupported mesh format '.xyz'"), std::string::npos)
        << e.what();
  }
}

// Scene files whose meshes the command's loader reads (STL, OBJ, legacy VTK):
// the triangles, the object's transform applied, and the loader's errors
// under the object's key.
TEST_F(VtkMeshFiles, SceneFilesReadTheirMeshesThroughTheLoader) {
  std::ofstream(dir_ / "tetra.stl") << kTetraStl;
  std::ofstream(dir_ / "quad.obj") << kQuadObj;
  std::ofstream(dir_ / "hex.vtk") << kHexVtk;
  std::ofstream(dir_ / "mesh.xyz") << "1 2 3\n";
  const rayscope::LoadedScene ls =
      rayscope::parse_scene(R"({"objects": [
      {"type": "mesh", "file": "tetra.stl", "transform": {"translate": [1, 0, 0], "scale": 2}},
      {"type": "mesh", "file": "quad.obj"}, {"type": "mesh", "file": "hex.vtk"}]})",
                            "scene", dir_, rayscope_vtkio::load_meshes);
  ASSERT_EQ(ls.scene.meshes.size(), 3u);
  EXPECT_EQ(ls.scene.meshes[0].triangles.size(), 4u);
  EXPECT_EQ(ls.scene.meshes[1].triangles.size(), 3u);
  EXPECT_EQ(ls.scene.meshes[2].triangles.size(), 12u);
  for (const rayscope::Vec3& w : {rayscope::Vec3(1, 0, 0), rayscope::Vec3(3, 0, 0),
                                  rayscope::Vec3(1, 2, 0), rayscope::Vec3(1, 0, 2)})
    EXPECT_NE(
        std::find(ls.scene.meshes[0].positions.begin(), ls.scene.meshes[0].positions.end(), w),
        ls.scene.meshes[0].positions.end());
  auto error = [&](const std::string& file) -> std::string {
    try {
      rayscope::parse_scene(R"({"objects": [{"type": "mesh", "file": ")" + file + R"("}]})",
                            "scene", dir_, rayscope_vtkio::load_meshes);
    } catch (const rayscope::SceneError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(error("nothere.obj"),
            "scene: objects[0].file: " + (dir_ / "nothere.obj").string() + ": file not found");
  EXPECT_NE(error("mesh.xyz").find("objects[0].file: "), std::string::npos);
  EXPECT_NE(error("mesh.xyz").find("unsupported mesh format '.xyz'"), std::string::npos);
}

}  // namespace

// A file without normals: the command's loader and the module (VTK's reader,
// then the default converter) give the same mesh, bit for bit, and it is
// smooth: every vertex of the sphere has its own unit normal, close to the
// radial direction (flat shading would have one normal per face).
TEST_F(VtkMeshFiles, CommandAndModuleGiveTheSameSmoothMesh) {
  const fs::path file = sphere_vtp();
  TriangleMesh cli = rayscope_vtkio::load_mesh(file_options(file));
  expect_same(cli, module_mesh<vtkXMLPolyDataReader>(file));

  ASSERT_EQ(cli.normals.size(), cli.positions.size());
  ASSERT_GT(cli.triangles.size(), 400u);
  for (size_t i = 0; i < cli.positions.size(); ++i) {
    EXPECT_NEAR(glm::length(cli.normals[i]), 1.0f, 1e-5f);
    EXPECT_GT(glm::dot(cli.normals[i], glm::normalize(cli.positions[i])), 0.98f) << i;
  }
  // "smooth": false: no normals at all.
  MeshOptions flat = file_options(file);
  flat.smooth = false;
  EXPECT_TRUE(rayscope_vtkio::load_mesh(flat).normals.empty());
}

// Sharp edges are split as in the module (vtkPolyDataNormals, feature angle
// 30 degrees): the cube's corners get one copy per face, with the face normal.
TEST_F(VtkMeshFiles, SharpEdgesSplitAsInTheModule) {
  const fs::path file = cube_stl();
  TriangleMesh cli = rayscope_vtkio::load_mesh(file_options(file));
  expect_same(cli, module_mesh<vtkSTLReader>(file));
  EXPECT_EQ(cli.triangles.size(), 12u);
  EXPECT_EQ(cli.positions.size(), 24u);
  for (const glm::uvec3& t : cli.triangles) {
    const glm::vec3 face = glm::normalize(glm::cross(cli.positions[t.y] - cli.positions[t.x],
                                                     cli.positions[t.z] - cli.positions[t.x]));
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(std::abs(glm::dot(cli.normals[t[k]], face)), 1.0f, 1e-5f);
  }
  // read_mesh_file: the file as stored (the STL reader merges the 8 corners).
  TriangleMesh stored = rayscope_vtkio::read_mesh_file(file);
  EXPECT_EQ(stored.positions.size(), 8u);
  EXPECT_TRUE(stored.normals.empty());
}

// color_by with a lookup table: the command's colors are those of the module
// converting the same data with a mapper set up the same way (cell scalars
// through a grayscale table over [0, 1]); the left cells are black, the right
// ones white.
TEST_F(VtkMeshFiles, ColorByMatchesTheModuleMapper) {
  vtkNew<vtkPlaneSource> plane;
  plane->SetXResolution(2);
  plane->Update();
  vtkNew<vtkPolyData> pd;
  pd->DeepCopy(plane->GetOutput());
  vtkNew<vtkFloatArray> half;
  half->SetName("Half");
  half->InsertNextValue(0.0f);
  half->InsertNextValue(1.0f);
  pd->GetCellData()->AddArray(half);
  const fs::path file = write_vtp(pd, "halves.vtp");

  MeshOptions o = file_options(file);
  o.color_by = MeshColorBy{};
  o.color_by->array = "Half";
  o.color_by->association = MeshColorBy::Association::Cell;
  o.color_by->map = rayscope::ColorMap::Grayscale;
  TriangleMesh cli = rayscope_vtkio::load_mesh(o);

  vtkNew<vtkLookupTable> gray;
  gray->SetSaturationRange(0.0, 0.0);
  gray->SetValueRange(0.0, 1.0);
  vtkNew<vtkDataSetMapper> mapper;
  mapper->SetScalarModeToUseCellFieldData();
  mapper->SelectColorArray("Half");
  mapper->SetColorModeToMapScalars();
  mapper->SetLookupTable(gray);
  mapper->SetScalarRange(0.0, 1.0);
  expect_same(cli, module_mesh<vtkXMLPolyDataReader>(file, mapper));

  ASSERT_EQ(cli.colors.size(), cli.positions.size());
  for (const glm::uvec3& t : cli.triangles) {
    const float x = (cli.positions[t.x].x + cli.positions[t.y].x + cli.positions[t.z].x) / 3.0f;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(cli.colors[t[k]], glm::vec3(x < 0.0f ? 0.0f : 1.0f));
  }
}

// A composite file gives one mesh per block with triangles, named by flat
// index and name; color_by maps every block through one table over the
// array's range in all of them (a block of T = 0 black, one of T = 2 white,
// where each block's own range would make both black); a block without the array
// keeps the material's color and one without triangles is left out, each
// with a warning naming it. load_mesh() wants a file of one mesh.
TEST_F(VtkMeshFiles, CompositeFileBlocksShareOneColorRange) {
  auto plane = [](double x, float t) {
    vtkNew<vtkPlaneSource> p;
    p->SetCenter(x, 0.0, 0.0);
    p->Update();
    vtkSmartPointer<vtkPolyData> pd = vtkSmartPointer<vtkPolyData>::New();
    pd->DeepCopy(p->GetOutput());
    if (t >= 0.0f) {
      vtkNew<vtkFloatArray> a;
      a->SetName("T");
      a->InsertNextValue(t);
      pd->GetCellData()->AddArray(a);
    }
    return pd;
  };
  vtkNew<vtkLineSource> line;
  line->Update();
  vtkNew<vtkMultiBlockDataSet> blocks;
  blocks->SetNumberOfBlocks(4);
  blocks->SetBlock(0, plane(0.0, 0.0f));
  blocks->SetBlock(1, plane(2.0, 2.0f));
  blocks->SetBlock(2, plane(4.0, -1.0f));  // no array T
  blocks->SetBlock(3, line->GetOutput());
  blocks->GetMetaData(1u)->Set(vtkCompositeDataSet::NAME(), "hot");
  blocks->GetMetaData(3u)->Set(vtkCompositeDataSet::NAME(), "wire");
  const fs::path file = dir_ / "blocks.vtm";
  vtkNew<vtkXMLMultiBlockDataWriter> w;
  w->SetFileName(file.c_str());
  w->SetInputData(blocks);
  ASSERT_EQ(w->Write(), 1);

  MeshOptions o = file_options(file);
  o.color_by = MeshColorBy{};
  o.color_by->array = "T";
  o.color_by->association = MeshColorBy::Association::Cell;
  o.color_by->map = rayscope::ColorMap::Grayscale;
  const rayscope::LoadedMeshFile loaded = rayscope_vtkio::load_meshes(o);
  ASSERT_EQ(loaded.meshes.size(), 3u);
  EXPECT_EQ(loaded.meshes[0].name, "block 1");
  EXPECT_EQ(loaded.meshes[1].name, "block 2 (hot)");
  EXPECT_EQ(loaded.meshes[2].name, "block 3");
  for (const TriangleMesh& m : loaded.meshes) EXPECT_EQ(m.triangles.size(), 2u);
  ASSERT_EQ(loaded.meshes[0].colors.size(), loaded.meshes[0].positions.size());
  for (const glm::vec3& c : loaded.meshes[0].colors) EXPECT_EQ(c, glm::vec3(0.0f));
  ASSERT_EQ(loaded.meshes[1].colors.size(), loaded.meshes[1].positions.size());
  for (const glm::vec3& c : loaded.meshes[1].colors) EXPECT_EQ(c, glm::vec3(1.0f));
  EXPECT_TRUE(loaded.meshes[2].colors.empty());
  // The block of a line alone: a tube set, of the automatic radius.
  ASSERT_EQ(loaded.tubes.size(), 1u);
  EXPECT_EQ(loaded.tubes[0].name, "block 4 (wire) lines");
  EXPECT_EQ(loaded.tubes[0].segments.size(), 1u);
  EXPECT_TRUE(loaded.points.empty());
  ASSERT_EQ(loaded.warnings.size(), 2u);
  EXPECT_EQ(loaded.warnings[0],
            file.string() + ": block 3: has no cell array 'T', drawn in the material's color");
  EXPECT_EQ(loaded.warnings[1], file.string() +
                                    ": block 4 (wire): has no cell array 'T', drawn in the "
                                    "material's color");

  try {
    rayscope_vtkio::load_mesh(file_options(file));
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              file.string() + ": holds 3 meshes (a composite file), not one");
  }
}

// A file of lines and vertices only (streamlines, a point cloud): tubes and
// spheres, colored like a surface, of the automatic radius (1/1000 of the
// diagonal of the file's bounds in the scene, transform included) or of the
// scene's radii; a radius array the file lacks, and non-finite points, are
// errors naming the file.
TEST_F(VtkMeshFiles, LinesAndVerticesBecomeTubesAndSpheres) {
  vtkNew<vtkPolyData> pd;
  vtkNew<vtkPoints> pts;
  for (double x : {0.0, 1.0, 2.0, 3.0, 4.0}) pts->InsertNextPoint(x, 0.0, 0.0);
  pd->SetPoints(pts);
  vtkNew<vtkCellArray> lines, verts;
  const vtkIdType polyline[] = {0, 1, 2};
  lines->InsertNextCell(3, polyline);
  for (vtkIdType i : {3, 4}) verts->InsertNextCell(1, &i);
  pd->SetLines(lines);
  pd->SetVerts(verts);
  vtkNew<vtkUnsignedCharArray> rgb;
  rgb->SetName("rgb");
  rgb->SetNumberOfComponents(3);
  for (int i = 0; i < 5; ++i) rgb->InsertNextTuple3(255, 0, 0);
  pd->GetPointData()->SetScalars(rgb);
  vtkNew<vtkFloatArray> r;
  r->SetName("r");
  for (int i = 0; i < 5; ++i) r->InsertNextValue(0.1f * float(i + 1));
  pd->GetPointData()->AddArray(r);
  const fs::path file = write_vtp(pd, "curves.vtp");

  MeshOptions o = file_options(file);
  o.to_scene = glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));
  const rayscope::LoadedMeshFile loaded = rayscope_vtkio::load_meshes(o);
  EXPECT_TRUE(loaded.meshes.empty());
  EXPECT_TRUE(loaded.warnings.empty());
  ASSERT_EQ(loaded.tubes.size(), 1u);
  ASSERT_EQ(loaded.points.size(), 1u);
  const rayscope::TubeSet& t = loaded.tubes[0];
  const rayscope::PointSet& v = loaded.points[0];
  EXPECT_EQ(t.name, "lines");
  EXPECT_EQ(v.name, "vertices");
  EXPECT_EQ(t.segments.size(), 2u);
  EXPECT_EQ(v.positions.size(), 2u);
  EXPECT_EQ(v.positions[1], Vec3(8.0f, 0.0f, 0.0f));  // scaled by to_scene
  // The bounds are 4 long along x, 8 in the scene.
  EXPECT_FLOAT_EQ(t.radius, 8e-3f);
  EXPECT_FLOAT_EQ(v.radius, 8e-3f);
  ASSERT_EQ(t.colors.size(), t.positions.size());
  EXPECT_EQ(t.colors[0], glm::vec3(1.0f, 0.0f, 0.0f));
  ASSERT_EQ(v.colors.size(), 2u);

  o.line_radius = 0.5;
  o.point_radius = 0.25;
  rayscope::LoadedMeshFile given = rayscope_vtkio::load_meshes(o);
  EXPECT_EQ(given.tubes[0].radius, 0.5f);
  EXPECT_EQ(given.points[0].radius, 0.25f);
  o.radius_array = "r";
  given = rayscope_vtkio::load_meshes(o);
  EXPECT_EQ(given.points[0].radii, (std::vector<float>{0.4f, 0.5f}));

  o.radius_array = "nope";
  try {
    rayscope_vtkio::load_meshes(o);
    ADD_FAILURE() << "no error";
  } catch (const rayscope::MeshOptionError& e) {
    EXPECT_EQ(std::string(e.what()),
              "radius_array: " + file.string() + ": has no point array 'nope' of one component");
  }

  // A file whose vertices are one point: radius 1 (automatic_radius()).
  {
    vtkNew<vtkPolyData> one;
    vtkNew<vtkPoints> p1;
    p1->InsertNextPoint(2.0, 3.0, 4.0);
    one->SetPoints(p1);
    vtkNew<vtkCellArray> v1;
    const vtkIdType id0 = 0;
    v1->InsertNextCell(1, &id0);
    one->SetVerts(v1);
    const rayscope::LoadedMeshFile one_point =
        rayscope_vtkio::load_meshes(file_options(write_vtp(one, "one_vertex.vtp")));
    ASSERT_EQ(one_point.points.size(), 1u);
    EXPECT_EQ(one_point.points[0].radius, 1.0f);
  }

  pts->SetPoint(4, std::nan(""), 0.0, 0.0);
  const fs::path bad = write_vtp(pd, "nan_curves.vtp");
  try {
    rayscope_vtkio::load_meshes(file_options(bad));
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              bad.string() + ": 1 of 2 vertices have non-finite (NaN or infinite) coordinates");
  }
}

// The scene parser passes color_by to the loader as parsed; the defaults are
// point association, the array's range and the cool-warm map.
TEST_F(VtkMeshFiles, SceneFileColorByReachesTheLoader) {
  std::vector<MeshOptions> seen;
  rayscope::MeshLoader capture = [&](const MeshOptions& o) {
    seen.push_back(o);
    TriangleMesh m;
    m.positions = {glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)};
    m.triangles = {glm::uvec3(0, 1, 2)};
    rayscope::LoadedMeshFile f;
    f.meshes.push_back(m);
    return f;
  };
  rayscope::parse_scene(R"({"objects": [
      {"type": "mesh", "file": "a.vtp", "smooth": false,
       "color_by": {"array": "T", "association": "cell", "range": [-1, 2.5], "map": "rainbow"}},
      {"type": "mesh", "file": "b.vtu", "color_by": {"array": "Elevation"}},
      {"type": "mesh", "file": "c.stl", "line_radius": 0.5, "point_radius": 2,
       "radius_array": "R"}]})",
                        "inline", dir_, capture);
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen[0].file, dir_ / "a.vtp");
  EXPECT_FALSE(seen[0].smooth);
  ASSERT_TRUE(seen[0].color_by);
  EXPECT_EQ(seen[0].color_by->array, "T");
  EXPECT_EQ(seen[0].color_by->association, MeshColorBy::Association::Cell);
  ASSERT_TRUE(seen[0].color_by->range);
  EXPECT_EQ((*seen[0].color_by->range)[0], -1.0);
  EXPECT_EQ((*seen[0].color_by->range)[1], 2.5);
  EXPECT_EQ(seen[0].color_by->map, rayscope::ColorMap::Rainbow);
  ASSERT_TRUE(seen[1].color_by);
  EXPECT_TRUE(seen[1].smooth);
  EXPECT_EQ(seen[1].color_by->association, MeshColorBy::Association::Point);
  EXPECT_FALSE(seen[1].color_by->range);
  EXPECT_EQ(seen[1].color_by->map, rayscope::ColorMap::CoolWarm);
  EXPECT_FALSE(seen[2].color_by);
  EXPECT_EQ(seen[0].line_radius, 0.0);  // automatic
  EXPECT_EQ(seen[0].point_radius, 0.0);
  EXPECT_TRUE(seen[0].radius_array.empty());
  EXPECT_EQ(seen[2].line_radius, 0.5);
  EXPECT_EQ(seen[2].point_radius, 2.0);
  EXPECT_EQ(seen[2].radius_array, "R");
}

// Bad color_by values and arrays the file lacks: one SceneError line naming
// the scene, the key and the problem.
TEST_F(VtkMeshFiles, ColorByErrorsNameTheFileAndKey) {
  const fs::path file = sphere_vtp();
  struct Case {
    std::string color_by, problem;
  };
  const Case cases[] = {
      {R"("oops")", "objects[0].color_by: expected an object"},
      {R"({"array": "A", "colour": 1})", "objects[0].color_by: unknown key 'colour'"},
      {R"({"array": ""})", "objects[0].color_by.array: must not be empty"},
      {R"({"array": "A", "range": [0]})", "objects[0].color_by.range: expected [lo, hi]"},
      {R"({"array": "A", "range": [0, 1e999]})", "malformed JSON"},
      {R"({"array": "A", "range": [2, 2]})", "objects[0].color_by.range: lo must be less than hi"},
      {R"({"array": "Nope"})", "objects[0].color_by.array: " + file.string() +
                                   " has no point array 'Nope' (it has no point arrays)"},
      {R"({"array": "Nope", "association": "cell"})",
       "objects[0].color_by.array: " + file.string() +
           " has no cell array 'Nope' (it has no cell arrays)"},
  };
  for (const Case& c : cases) {
    const std::string text = R"({"objects": [{"type": "mesh", "file": ")" + file.string() +
                             R"(", "color_by": )" + c.color_by + "}]}";
    try {
      rayscope::parse_scene(text, "scene.json", dir_, rayscope_vtkio::load_meshes);
      ADD_FAILURE() << c.color_by << ": no error";
    } catch (const rayscope::SceneError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      EXPECT_EQ(msg.rfind("scene.json: ", 0), 0u) << msg;
      EXPECT_NE(msg.find(c.problem), std::string::npos) << msg << "\nexpected: " << c.problem;
    }
  }
}
