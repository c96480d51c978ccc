// Input the VTK module cannot render, or renders only in part (issue 11): each
// case is reported through VTK's macros (ErrorEvent / WarningEvent on the
// algorithm or converter), never a crash; where nothing can be rendered the
// output image is empty.
//
// - cells naming points the dataset lacks (they used to reach
//   vtkPolyDataNormals unchecked and crash it)
// - inputs without surface triangles: empty polydata, a 1-D image, a reader
//   given a folder as its file name
// - a material or converter set for an input index that is not connected
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <limits>
#include <string>
#include <type_traits>

#include <vtkCellArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkSTLReader.h>
#include <vtkSphereSource.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>

#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeMaterial.h"
#include "vtkRayScopeMeshConverter.h"
#include "vtk_test_util.h"

namespace {

// Three points and one triangle (0, 1, bad): with bad = 7 a cell names a
// point the data does not have.
vtkSmartPointer<vtkPolyData> triangle_with_id(vtkIdType bad) {
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0, 0, 0);
  pts->InsertNextPoint(1, 0, 0);
  pts->InsertNextPoint(0, 1, 0);
  vtkNew<vtkCellArray> polys;
  const vtkIdType ids[3] = {0, 1, bad};
  polys->InsertNextCell(3, ids);
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  return pd;
}

// An algorithm with `inputs` as its data, a camera looking at the origin,
// and catchers for its errors and warnings.
struct Traced {
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  vtkNew<ErrorCatcher> errors, warnings;
  explicit Traced(std::initializer_list<vtkDataObject*> inputs) {
    for (vtkDataObject* d : inputs) alg->AddInputData(d);
    alg->SetSize(16, 12);
    alg->SetPosition(0.3, 0.3, 4.0);
    alg->SetFocalPoint(0.3, 0.3, 0.0);
    alg->AddObserver(vtkCommand::ErrorEvent, errors);
    alg->AddObserver(vtkCommand::WarningEvent, warnings);
  }
  // The error case: the update fails with one error containing `what`, and
  // the output image is empty.
  void expect_error(const std::string& what) {
    vtkNew<ErrorCatcher> pipeline;  // the executive's "algorithm failed" line
    alg->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline);
    EXPECT_EQ(update(alg), 0);
    ASSERT_GE(errors->count, 1);
    EXPECT_NE(errors->last.find(what), std::string::npos)
        << "expected '" << what << "' in: " << errors->last;
    EXPECT_EQ(alg->GetOutput()->GetNumberOfPoints(), 0);
  }
};

}  // namespace

// The converter refuses a cell with point id 7 in a 3-point dataset (and a
// negative id) before any VTK filter runs: an error naming the cell and the
// id, return value 0, empty output. A valid id still converts.
TEST(VtkBadInput, ConverterRefusesOutOfRangePointIds) {
  for (vtkIdType bad : {vtkIdType(7), vtkIdType(3), vtkIdType(-1)}) {
    vtkNew<vtkRayScopeMeshConverter> conv;
    vtkNew<ErrorCatcher> errors;
    conv->AddObserver(vtkCommand::ErrorEvent, errors);
    vtkNew<vtkPolyData> out;
    out->DeepCopy(triangle_with_id(2));  // not empty before: the error must empty it
    EXPECT_EQ(conv->Convert(triangle_with_id(bad), out), 0) << bad;
    EXPECT_EQ(errors->count, 1) << bad;
    const std::string expect =
        "cell 0 refers to point " + std::to_string(bad) + " but the data has 3 points";
    EXPECT_NE(errors->last.find(expect), std::string::npos) << errors->last;
    EXPECT_EQ(out->GetNumberOfPoints(), 0);
    EXPECT_EQ(out->GetNumberOfCells(), 0);
  }
  vtkNew<vtkRayScopeMeshConverter> conv;
  vtkNew<vtkPolyData> out;
  EXPECT_EQ(conv->Convert(triangle_with_id(2), out), 1);
  EXPECT_EQ(out->GetNumberOfPolys(), 1);
}

// The same check for unstructured grids, whose cells go through
// vtkDataSetSurfaceFilter.
TEST(VtkBadInput, ConverterRefusesOutOfRangeIdsInUnstructuredGrids) {
  vtkNew<vtkUnstructuredGrid> ug;
  ug->SetPoints(triangle_with_id(0)->GetPoints());
  const vtkIdType tet[4] = {0, 1, 2, 9};
  ug->InsertNextCell(VTK_TETRA, 4, tet);
  vtkNew<vtkRayScopeMeshConverter> conv;
  vtkNew<ErrorCatcher> errors;
  conv->AddObserver(vtkCommand::ErrorEvent, errors);
  vtkNew<vtkPolyData> out;
  EXPECT_EQ(conv->Convert(ug, out), 0);
  EXPECT_NE(errors->last.find("cell 0 refers to point 9 but the data has 3 points"),
            std::string::npos)
      << errors->last;
}

// The image algorithm with that polydata: an error through vtkErrorMacro and
// an empty image (it crashed inside vtkPolyDataNormals).
TEST(VtkBadInput, ImageOfOutOfRangePointIdsIsAnError) {
  vtkSmartPointer<vtkPolyData> pd = triangle_with_id(7);
  Traced t({pd});
  t.expect_error("cell 0 refers to point 7 but the data has 3 points");
}

// Nothing to render: one input without surface triangles is an error, and
// the image is empty, whatever the reason.
TEST(VtkBadInput, InputWithoutTrianglesIsAnError) {
  vtkNew<vtkPolyData> empty;
  {
    Traced t({empty});
    t.expect_error(
        "nothing to render: input 0 (vtkPolyData with 0 points, 0 cells) has no "
        "surface triangles");
  }
  // Points without cells: nothing to draw (a 1-D image's lines would be
  // tubes, a vertex a sphere).
  vtkNew<vtkPolyData> cloud;
  vtkNew<vtkPoints> cloud_points;
  for (int i = 0; i < 4; ++i) cloud_points->InsertNextPoint(i, 0.0, 0.0);
  cloud->SetPoints(cloud_points);
  {
    Traced t({cloud});
    t.expect_error(
        "input 0 (vtkPolyData with 4 points, 0 cells) has no surface triangles, lines or "
        "vertices");
  }
  // Readers given a folder as their file name: some fail (the pipeline
  // reports that the reader returned failure), others produce an empty
  // output, which the algorithm reports. Either way: an error, no image.
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("rayscope_folder_" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  auto read_folder = [&](vtkAlgorithm* reader, const char* name) {
    SCOPED_TRACE(name);
    vtkNew<ErrorCatcher> reader_errors;  // the reader's own messages, if any
    reader->AddObserver(vtkCommand::ErrorEvent, reader_errors);
    reader->AddObserver(vtkCommand::WarningEvent, reader_errors);
    reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, reader_errors);
    vtkNew<vtkRayScopeImageAlgorithm> alg;
    alg->SetInputConnection(reader->GetOutputPort());
    alg->SetSize(8, 8);
    vtkNew<ErrorCatcher> errors, pipeline;
    alg->AddObserver(vtkCommand::ErrorEvent, errors);
    alg->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline);
    EXPECT_EQ(update(alg), 0);
    if (errors->count == 0) {
      // The reader failed: the pipeline said so, and the algorithm never ran.
      EXPECT_NE(reader_errors->last.find("returned failure"), std::string::npos)
          << reader_errors->last;
    } else {
      EXPECT_NE(errors->last.find("has no surface triangles"), std::string::npos) << errors->last;
    }
    EXPECT_EQ(alg->GetOutput()->GetNumberOfPoints(), 0);
  };
  // Each reader class, given the folder.
  auto read_folder_with = [&](auto reader_type) {
    using Reader = typename decltype(reader_type)::type;
    vtkNew<Reader> r;
    r->SetFileName(folder.c_str());
    read_folder(r, r->GetClassName());
  };
  read_folder_with(std::type_identity<vtkSTLReader>());
  read_folder_with(std::type_identity<vtkPLYReader>());
  read_folder_with(std::type_identity<vtkOBJReader>());
  read_folder_with(std::type_identity<vtkXMLPolyDataReader>());
  read_folder_with(std::type_identity<vtkPolyDataReader>());
  std::filesystem::remove_all(folder);
}

// Next to one that has triangles: an input of points without cells is named
// in one warning; an empty input (no points: an empty block, a placeholder
// actor) is left out quietly. The image is made.
TEST(VtkBadInput, InputWithNothingToDrawBesideOthersIsAWarning) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 0.3, 0.3, 0, 0.5, 16);
  s->Update();
  vtkNew<vtkPolyData> empty;
  vtkNew<vtkPolyData> bare;  // points, no cells
  bare->SetPoints(s->GetOutput()->GetPoints());
  Traced t({s->GetOutput(), empty, bare});
  ASSERT_EQ(update(t.alg), 1);
  EXPECT_EQ(t.errors->count, 0);
  ASSERT_EQ(t.warnings->count, 1);
  EXPECT_NE(t.warnings->last.find("input 2 (vtkPolyData with " +
                                  std::to_string(bare->GetNumberOfPoints()) +
                                  " points, 0 cells) has no surface triangles, lines or "
                                  "vertices: it is not shown"),
            std::string::npos)
      << t.warnings->last;
  EXPECT_GT(count_object(t.alg->GetOutput(), 0), 0);
}

// Non-finite points (docs/scene-format.md, "Non-finite coordinates"): data
// whose every triangle has a NaN or infinite corner is an error with an empty
// image (it gave a warning and a blank image); data with some is drawn
// without those triangles, with one warning that counts them, and the camera
// fitted to its finite part (an infinite point made the bounds infinite).
TEST(VtkBadInput, NonFinitePoints) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 0.3, 0.3, 0, 0.5, 16);
  s->Update();
  {
    vtkNew<vtkPolyData> all;
    all->DeepCopy(s->GetOutput());
    for (vtkIdType i = 0; i < all->GetNumberOfPoints(); ++i)
      all->GetPoints()->SetPoint(i, nan, nan, nan);
    Traced t({all});
    t.expect_error("triangles have non-finite (NaN or infinite) vertex coordinates");
  }
  for (bool auto_camera : {false, true}) {
    SCOPED_TRACE(auto_camera ? "AutoCamera" : "fixed camera");
    vtkNew<vtkPolyData> some;
    some->DeepCopy(s->GetOutput());
    some->GetPoints()->SetPoint(3, nan, 0, 0);
    some->GetPoints()->SetPoint(40, 0, inf, 0);
    some->GetPoints()->SetPoint(41, -inf, 0, nan);
    Traced t({some});
    t.alg->SetAutoCamera(auto_camera);
    ASSERT_EQ(update(t.alg), 1) << t.errors->last;
    EXPECT_EQ(t.errors->count, 0);
    ASSERT_EQ(t.warnings->count, 1);
    EXPECT_NE(t.warnings->last.find("triangles with non-finite vertex coordinates skipped"),
              std::string::npos)
        << t.warnings->last;
    // Most of the sphere is still there, framed (AutoCamera) as without the
    // bad points.
    Traced clean({s->GetOutput()});
    clean.alg->SetAutoCamera(auto_camera);
    ASSERT_EQ(update(clean.alg), 1);
    const int covered = count_object(clean.alg->GetOutput(), 0);
    EXPECT_GT(count_object(t.alg->GetOutput(), 0), covered * 8 / 10);
  }
}

// Points no cell uses are not converted: a polydata of one triangle and
// 2,000,000 unused points gives the converter a 3-point mesh, and the image
// is the one of the triangle alone (the converter spent ~80 bytes and
// 0.4 us on each unused point).
TEST(VtkBadInput, UnusedPointsAreNotConverted) {
  vtkSmartPointer<vtkPolyData> one = triangle_with_id(2);
  vtkNew<vtkPolyData> padded;
  vtkNew<vtkPoints> pts;
  constexpr vtkIdType kUnused = 2000000;
  pts->SetNumberOfPoints(kUnused + 3);
  for (vtkIdType i = 0; i < kUnused; ++i) pts->SetPoint(i, 5.0 + double(i), -7.0, 3.0);
  for (vtkIdType k = 0; k < 3; ++k) pts->SetPoint(kUnused + k, one->GetPoint(k));
  vtkNew<vtkCellArray> polys;
  const vtkIdType ids[3] = {kUnused, kUnused + 1, kUnused + 2};
  polys->InsertNextCell(3, ids);
  padded->SetPoints(pts);
  padded->SetPolys(polys);
  vtkNew<vtkRayScopeMeshConverter> converter;
  vtkNew<vtkPolyData> converted;
  ASSERT_TRUE(converter->Convert(padded, converted));
  EXPECT_EQ(converted->GetNumberOfPoints(), 3);
  EXPECT_EQ(converted->GetNumberOfPolys(), 1);
  // The same picture as the triangle alone.
  Traced alone({one}), with({padded});
  ASSERT_EQ(update(alone.alg), 1);
  ASSERT_EQ(update(with.alg), 1);
  EXPECT_GT(count_object(alone.alg->GetOutput(), 0), 0);
  EXPECT_EQ(count_object(with.alg->GetOutput(), 0), count_object(alone.alg->GetOutput(), 0));
}

// SetInputMaterial / SetInputConverter for input 5 with one input connected:
// a warning when the image is made (the setting may precede the connection,
// so it is not an error at set time), naming the index and the number of
// inputs; the image is still made. A negative index is an error at once and
// is not stored.
TEST(VtkBadInput, SettingsForUnconnectedInputsAreReported) {
  vtkNew<vtkSphereSource> s;
  configure_sphere(s, 0.3, 0.3, 0, 0.5, 16);
  s->Update();
  Traced t({s->GetOutput()});
  vtkNew<vtkRayScopeMaterial> m;
  t.alg->SetInputMaterial(5, m);
  EXPECT_EQ(t.warnings->count, 0);
  ASSERT_EQ(update(t.alg), 1);
  EXPECT_EQ(t.errors->count, 0);
  ASSERT_EQ(t.warnings->count, 1);
  EXPECT_NE(t.warnings->last.find("a material (SetInputMaterial) is set for input 5, but only 1 "
                                  "input is connected: it is not used"),
            std::string::npos)
      << t.warnings->last;
  EXPECT_GT(count_object(t.alg->GetOutput(), 0), 0);

  // The converter too; with the material removed, only its warning remains.
  t.alg->SetInputMaterial(5, nullptr);
  vtkNew<vtkRayScopeMeshConverter> c;
  t.alg->SetInputConverter(2, c);
  ASSERT_EQ(update(t.alg), 1);
  ASSERT_EQ(t.warnings->count, 2);
  EXPECT_NE(t.warnings->last.find("a converter (SetInputConverter) is set for input 2"),
            std::string::npos)
      << t.warnings->last;

  t.alg->SetInputMaterial(-1, m);
  EXPECT_EQ(t.errors->count, 1);
  EXPECT_NE(t.errors->last.find("SetInputMaterial: input index -1 is negative"), std::string::npos)
      << t.errors->last;
  EXPECT_EQ(t.alg->GetInputMaterial(-1), nullptr);
}
