// libFuzzer target for the mesh files the rayscope command reads:
// rayscope_vtkio::load_meshes (vtkplugin/vtkio), i.e. RayScope's checks of the
// file (mesh_checks.h), VTK's reader of the format, and the conversion to
// triangles, then Scene::commit().
//
// The first byte of an input picks the format (kFormats[byte % kNumFormats]);
// the rest is written to a temporary file with that extension, which
// load_meshes reads as a scene's mesh object would be. Formats whose files
// name other files (parallel pieces, composite blocks) get them from the same
// input: the rest is cut at each line "%%file NAME" (kFileMark), the part
// before the first one is the input file, each part after one the file NAME
// beside it (names of letters, digits, '.', '_' and '-' only). The contract
// under test (mesh_files.h): any file either is refused with a
// std::runtime_error (MeshOptionError is one) naming the file, or gives
// meshes, each with at least one triangle whose corners are valid indices,
// with normals and colors absent or one per position, that a scene commits.
// Everything else is a finding: a crash (in RayScope or inside VTK: RayScope
// hands the file to VTK, so it must refuse what VTK cannot read safely), a
// sanitizer report in RayScope's code, another exception type, a mesh
// breaking the contract, or a hang (libFuzzer -timeout).
//
// With the VTK module (RAYSCOPE_FUZZ_MESH_READER), the same file, if of one
// dataset, also goes through vtkRayScopeMeshReader, the module's reader that
// Python and ParaView users read files with. Its contract
// (vtkRayScopeMeshReader.h): either the update fails with exactly one error
// on the reader naming the file and an empty output, or it succeeds without
// an error and outputs a dataset with points whose cells name only those
// points and whose point and cell arrays hold a tuple per point and cell
// (vtkDataSet::CheckAttributes(), VTK's own check). A file load_meshes
// accepts must be read. Anything else, a crash or a hang included, is a
// finding.
//
// Built twice like fuzz_scene_parser.cpp: as a libFuzzer binary
// (RAYSCOPE_FUZZ=ON) and, with replay_main.cpp, as a program that replays the
// committed corpus and regressions in every build (tests/fuzz/CMakeLists.txt).
#include <unistd.h>

#include <cctype>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include <vtkLogger.h>
#include <vtkOutputWindow.h>

#include "rayscope/scene.h"
#include "rayscope_vtkio/mesh_files.h"

#ifdef RAYSCOPE_FUZZ_MESH_READER
#include <vtkCommand.h>
#include <vtkDataSet.h>
#include <vtkExecutive.h>
#include <vtkNew.h>

#include "rayscope_vtkio/mesh_checks.h"
#include "vtkRayScopeMeshReader.h"
#endif

namespace {

namespace fs = std::filesystem;

// The formats mesh_files.cpp reads (one extension per reader: .exo and .e
// are read as .ex2 is); the corpus files start with their index, so new
// formats go at the end.
constexpr const char* kFormats[] = {".obj",  ".stl",  ".ply",  ".vtk", ".vtp",  ".vtu", ".vti",
                                    ".pvtp", ".pvtu", ".pvti", ".vtm", ".vtpc", ".ex2"};
constexpr size_t kNumFormats = sizeof kFormats / sizeof kFormats[0];

// The line that starts each further file of an input (see the top).
constexpr std::string_view kFileMark = "\n%%file ";

[[noreturn]] void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_mesh_loader: FINDING: %s: %s\n", what, detail.c_str());
  std::fflush(stderr);
  std::abort();
}

// A private folder for the input's files, removed at exit. VTK's messages
// about bad files are expected by the thousand: silenced as in the rayscope
// command.
const fs::path& work_dir() {
  static const fs::path dir = [] {
    // Every format the fuzzer picks is one the loader reads.
    for (const char* ext : kFormats) {
      bool known = false;
      for (const rayscope_vtkio::MeshFileFormat& f : rayscope_vtkio::kMeshFileFormats)
        known = known || f.extension == ext;
      if (!known) finding("setup", std::string(ext) + " is not in kMeshFileFormats");
    }
    vtkOutputWindow::GetInstance()->SetDisplayModeToNever();
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
    fs::path d = fs::temp_directory_path() / ("rayscope_fuzz_mesh_" + std::to_string(getpid()));
    fs::create_directories(d);
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(work_dir(), ec);
    });
    return d;
  }();
  return dir;
}

#ifdef RAYSCOPE_FUZZ_MESH_READER
// Counts the ErrorEvents of the object it observes and keeps the last text.
class ErrorCount : public vtkCommand {
 public:
  static ErrorCount* New() { return new ErrorCount; }
  void Execute(vtkObject*, unsigned long, void* data) override {
    ++count;
    last = data ? static_cast<const char*>(data) : "";
  }
  int count = 0;
  std::string last;
};

// `file` through vtkRayScopeMeshReader, held to its contract (above);
// `loaded`: load_meshes accepted the file.
void check_reader(const fs::path& file, bool loaded) {
  vtkNew<vtkRayScopeMeshReader> reader;
  vtkNew<ErrorCount> errors, executive_errors;
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, executive_errors);
  reader->SetFileName(file.c_str());
  const int ok = reader->GetExecutive()->Update();
  vtkDataSet* out = reader->GetOutput();
  if (!out) finding("reader", "no output dataset");
  if (!ok) {
    if (errors->count != 1)
      finding("reader failed",
              std::to_string(errors->count) + " errors, the last: " + errors->last);
    if (errors->last.find(file.string()) == std::string::npos)
      finding("reader error without the file name", errors->last);
    if (out->GetNumberOfPoints() != 0 || out->GetNumberOfCells() != 0)
      finding("reader error with a non-empty output", errors->last);
    if (loaded) finding("reader refused a file load_meshes accepted", errors->last);
    return;
  }
  if (errors->count != 0) finding("reader succeeded with an error", errors->last);
  if (out->GetNumberOfPoints() == 0) finding("reader output", "a dataset without points");
  if (std::string e = rayscope_vtkio::check_cell_point_ids(out); !e.empty())
    finding("reader output", e);
  // (CheckAttributes' own message goes to the output window, silenced here.)
  if (out->CheckAttributes() != 0)
    finding("reader output", "an array with fewer tuples than points or cells");
}
#endif

// Writes `bytes` to `file`.
void write_file(const fs::path& file, std::string_view bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) finding("setup", "cannot write " + file.string());
}

// A further file's name: letters, digits, '.', '_', '-', not starting with
// '.', at most 64 bytes; else empty (the part is not written).
std::string file_name(std::string_view name) {
  if (name.empty() || name.size() > 64 || name[0] == '.') return {};
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') return {};
  return std::string(name);
}

// Writes the input's files (see the top) into an emptied work_dir() and
// returns the input file.
fs::path write_input(const uint8_t* data, size_t size) {
  const fs::path& dir = work_dir();
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) fs::remove_all(e.path());
  const fs::path file = dir / (std::string("input") + kFormats[data[0] % kNumFormats]);
  std::string_view rest(reinterpret_cast<const char*>(data + 1), size - 1);
  size_t mark = rest.find(kFileMark);
  write_file(file, rest.substr(0, mark));
  while (mark != std::string_view::npos) {
    rest.remove_prefix(mark + kFileMark.size());
    const size_t line_end = rest.find('\n');
    const std::string name = file_name(rest.substr(0, line_end));
    if (line_end == std::string_view::npos) break;
    rest.remove_prefix(line_end + 1);
    mark = rest.find(kFileMark);
    if (!name.empty() && dir / name != file) write_file(dir / name, rest.substr(0, mark));
  }
  return file;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const fs::path file = write_input(data, size);
  rayscope::MeshOptions options;
  options.file = file;
  rayscope::LoadedMeshFile meshes;
  bool loaded = false;
  try {
    meshes = rayscope_vtkio::load_meshes(options);
    loaded = true;
  } catch (const std::runtime_error& e) {
    // A refusal must name the file (the one error line the user sees).
    if (std::string(e.what()).find(file.string()) == std::string::npos)
      finding("error without the file name", e.what());
  } catch (const std::exception& e) {
    finding("unexpected exception type", e.what());
  }
#ifdef RAYSCOPE_FUZZ_MESH_READER
  // (The module's reader reads the files of one dataset.)
  if (rayscope_vtkio::has_dataset_file_extension(file)) check_reader(file, loaded);
#endif
  if (!loaded) return 0;
  if (meshes.meshes.empty() && meshes.tubes.empty() && meshes.points.empty())
    finding("accepted file", "no meshes, tubes or points");
  rayscope::Scene scene;
  for (rayscope::TriangleMesh& mesh : meshes.meshes) {
    const size_t n = mesh.positions.size();
    if (mesh.triangles.empty()) finding("accepted mesh", "no triangles");
    for (const glm::uvec3& t : mesh.triangles)
      if (t.x >= n || t.y >= n || t.z >= n) finding("accepted mesh", "corner index out of range");
    if (!mesh.normals.empty() && mesh.normals.size() != n)
      finding("accepted mesh", "normals are not one per position");
    if (!mesh.colors.empty() && mesh.colors.size() != n)
      finding("accepted mesh", "colors are not one per position");
    scene.meshes.push_back(std::move(mesh));
  }
  // Lines and vertices: indices in range, radii and colors one per position
  // or none, every one traced (finite, of a radius > 0).
  auto per_position = [](const auto& values, size_t n) {
    return values.empty() || values.size() == n;
  };
  for (rayscope::TubeSet& t : meshes.tubes) {
    const size_t n = t.positions.size();
    if (t.segments.empty()) finding("accepted tubes", "no segments");
    for (const glm::uvec2& e : t.segments)
      if (e.x >= n || e.y >= n) finding("accepted tubes", "segment index out of range");
    if (!per_position(t.radii, n) || !per_position(t.colors, n))
      finding("accepted tubes", "radii or colors are not one per position");
    scene.tubes.push_back(std::move(t));
  }
  for (rayscope::PointSet& p : meshes.points) {
    const size_t n = p.positions.size();
    if (n == 0) finding("accepted points", "no points");
    if (!per_position(p.radii, n) || !per_position(p.colors, n))
      finding("accepted points", "radii or colors are not one per position");
    scene.points.push_back(std::move(p));
  }
  scene.materials.emplace_back();
  try {
    scene.commit();
  } catch (const std::exception& e) {
    finding("commit of an accepted mesh", e.what());
  }
  return 0;
}
