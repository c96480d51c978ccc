// check_vtk_xml_parallel_file() and check_vtk_xml_composite_file()
// (mesh_checks.h): VTK XML files that name other files, checked with every
// file they name before VTK's readers open any of them.
//
// VTK's parallel readers (.pvtp .pvtu .pvti) allocate the arrays the parallel
// file declares for all pieces together and copy each piece's array into
// them by the piece's own sizes; its composite readers (.vtm .vtpc) size
// their lists of blocks by the "index" attributes. Both then run the
// serial XML reader on each named file. So the named files get the serial
// files' checks, and what the outer file declares is held against them.
#include <algorithm>
#include <array>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <vtkXMLDataElement.h>

#include "check_util.h"
#include "rayscope/input_file.h"
#include "rayscope_vtkio/mesh_checks.h"
#include "vtk_xml_check_parts.h"

namespace rayscope_vtkio {
namespace {

using namespace checks;

std::string quoted(const char* text) {
  std::string q = "'";
  q += rayscope::printable_text(text ? text : "", rayscope::kMaxQuotedBytes);
  q += '\'';
  return q;
}

/// The file a piece's Source or a block's file attribute names, as VTK's
/// readers resolve it: as written when absolute, else beside `owner`
/// (composite readers also take "X:..." as absolute, as on Windows).
fs::path named_file(const fs::path& owner, std::string_view name, bool drive_letters) {
  if (name.front() == '/' || (drive_letters && name.size() > 1 && name[1] == ':'))
    return fs::path(name);
  return owner.parent_path() / name;
}

/// A named file that must exist and be readable, and be named only once.
/// `what` says which ("piece", "block").
fs::path member_file(const fs::path& owner, const char* name, const char* what, bool drive_letters,
                     std::set<fs::path>& seen) {
  if (!name || !*name) fail(owner, std::string("a ") + what + " names no file");
  const fs::path file = named_file(owner, name, drive_letters);
  if (const std::string problem = rayscope::input_file_problem(file); !problem.empty())
    fail(owner,
         std::string(what) + " file " + quoted(name) + " (" + file.string() + "): " + problem);
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(file, ec);
  if (!seen.insert(ec ? file : canonical).second)
    fail(owner, std::string(what) + " file " + quoted(name) + " is named more than once");
  return file;
}

/// Runs `check` of a named file; its error ("FILE: problem") comes after the
/// owner's name and what names it, so that the line names both files.
template <class Check>
auto check_member(const fs::path& owner, const char* what, const char* name, Check&& check) {
  try {
    return check();
  } catch (const std::runtime_error& e) {
    fail(owner, std::string(what) + " file " + quoted(name) + ": " + e.what());
  }
}

// The children of a composite file's elements, as the readers walk them.
struct CompositeWalk {
  const fs::path& path;
  bool collection;  // .vtpc: Partitions of DataSets; else .vtm: Blocks, Pieces, DataSets
  std::set<fs::path> seen;

  void walk(vtkXMLDataElement* parent, int depth) {
    if (depth > kMaxCompositeDepth)
      fail(path, "its blocks nest more than " + std::to_string(kMaxCompositeDepth) + " deep");
    const std::string_view parent_name = parent->GetName();
    const int n = parent->GetNumberOfNestedElements();
    for (int i = 0; i < n; ++i) {
      vtkXMLDataElement* e = parent->GetNestedElement(i);
      const std::string_view name = e->GetName();
      if (const char* index = e->GetAttribute("index")) {
        int v = -1;
        if (!e->GetScalarAttribute("index", v) || v < 0 || v >= n)
          fail(path, std::string(e->GetName()) + " has index " + quoted(index) + " but " +
                         std::string(parent_name) + " has " + std::to_string(n) + " elements");
      }
      bool known = false;
      if (collection) {
        known = depth == 0 ? name == "Partitions" : name == "DataSet";
      } else {
        known = name == "DataSet" || name == "Piece" || (parent_name != "Piece" && name == "Block");
      }
      if (!known)
        fail(path,
             "unexpected element " + quoted(e->GetName()) + " in " + std::string(parent_name));
      if (name == "DataSet")
        dataset(e);
      else
        walk(e, depth + 1);
    }
  }

  void dataset(vtkXMLDataElement* e) {
    const char* name = e->GetAttribute("file");
    if (!name) return;  // an empty block
    const fs::path file = member_file(path, name, "block", true, seen);
    // The reader picks the block's reader by its extension, as written.
    const std::string ext = file.extension().string();
    const char* type = ext == ".vtp"   ? "PolyData"
                       : ext == ".vtu" ? "UnstructuredGrid"
                       : ext == ".vti" ? "ImageData"
                                       : nullptr;
    if (!type)
      fail(path, "block file " + quoted(name) +
                     ": not a .vtp, .vtu or .vti file (the block formats RayScope reads)");
    check_member(path, "block", name, [&] { check_vtk_xml_file(file, type); });
  }
};

}  // namespace

std::vector<fs::path> check_vtk_xml_parallel_file(const fs::path& path, const char* dataset_type) {
  const std::string type = std::string("P") + dataset_type;
  XmlDocumentPtr doc = parse_vtk_xml(path, type);
  vtkXMLDataElement* primary = root_of(*doc)->FindNestedElementWithName(type.c_str());
  if (!primary) fail(path, "no " + type + " element");
  const bool image = std::string_view(dataset_type) == "ImageData";
  std::array<long long, 6> whole{};
  if (image) {
    int w[6];
    if (primary->GetVectorAttribute("WholeExtent", 6, w) != 6)
      fail(path, type + " has no valid WholeExtent");
    std::copy(w, w + 6, whole.begin());
    for (int a = 0; a < 3; ++a)
      if (whole[2 * a + 1] < whole[2 * a] - 1) fail(path, type + " has an invalid WholeExtent");
    if (extent_points(whole) > kMaxStructuredPoints)
      fail(path, type + "'s WholeExtent has more than " + std::to_string(kMaxStructuredPoints) +
                     " points");
  }
  std::vector<XmlArray> declared;
  note_arrays(primary->FindNestedElementWithName("PPoints"), "PDataArray", "Points", declared);
  note_arrays(primary->FindNestedElementWithName("PPointData"), "PDataArray", "PointData",
              declared);
  note_arrays(primary->FindNestedElementWithName("PCellData"), "PDataArray", "CellData", declared);
  // VTK's parallel readers of point sets copy each piece's points into the
  // array PPoints declares, unchecked: without one (a misspelt element
  // name) they copied into nothing.
  if (!image) {
    const auto is_points = [](const XmlArray& a) { return a.section == "Points"; };
    const auto points_arrays = std::count_if(declared.begin(), declared.end(), is_points);
    const auto it = std::find_if(declared.begin(), declared.end(), is_points);
    if (points_arrays != 1 || it->components != 3)
      fail(path, "PPoints does not declare the one point array (a PDataArray of 3 components)");
  }

  std::set<fs::path> seen;
  unsigned long long points = 0;
  std::vector<fs::path> pieces;
  for (int i = 0; i < primary->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* piece = primary->GetNestedElement(i);
    if (std::string_view(piece->GetName()) != "Piece") continue;
    const char* source = piece->GetAttribute("Source");
    const fs::path file = member_file(path, source, "piece", false, seen);
    pieces.push_back(file);
    const XmlDatasetSummary summary = check_member(
        path, "piece", source, [&] { return check_vtk_xml_dataset(file, dataset_type); });
    for (const XmlArray& a : declared) {
      const auto it = std::find_if(
          summary.arrays.begin(), summary.arrays.end(),
          [&](const XmlArray& b) { return a.section == b.section && a.name == b.name; });
      if (it == summary.arrays.end() || !(*it == a))
        fail(path, "piece file " + quoted(source) + " has no " + a.section + " array " +
                       quoted(a.name.c_str()) + " of type " + a.type + " with " +
                       std::to_string(a.components) + " components, as this file declares");
    }
    if (image) {
      int e[6];
      if (piece->GetVectorAttribute("Extent", 6, e) != 6)
        fail(path, "piece " + quoted(source) + " has no valid Extent");
      const std::array<long long, 6> extent = {e[0], e[1], e[2], e[3], e[4], e[5]};
      if (summary.extents.size() != 1 || summary.extents[0] != extent)
        fail(path, "piece file " + quoted(source) +
                       " does not hold the one piece of the Extent this file gives it");
      for (int a = 0; a < 3; ++a)
        if (extent_points(extent) > 0 &&
            (extent[2 * a] < whole[2 * a] || extent[2 * a + 1] > whole[2 * a + 1]))
          fail(path, "piece " + quoted(source) + "'s Extent lies outside the WholeExtent");
      points += extent_points(extent);
    }
  }
  if (pieces.empty()) fail(path, "names no piece files");
  if (image && points < extent_points(whole))
    fail(path, "its pieces hold " + std::to_string(points) + " points but its WholeExtent has " +
                   std::to_string(extent_points(whole)));
  return pieces;
}

void check_vtk_xml_composite_file(const fs::path& path, const char* composite_type) {
  XmlDocumentPtr doc = parse_vtk_xml(path, composite_type);
  vtkXMLDataElement* root = root_of(*doc);
  // Version 0 files (DataSet "group" and "dataset" numbers) are read another way.
  int version[2] = {0, 0};
  if (!root->GetAttribute("version") || root->GetVectorAttribute("version", 2, version) < 1 ||
      version[0] < 1)
    fail(path, "a composite file of format version " + quoted(root->GetAttribute("version")) +
                   " (RayScope reads version 1 and later)");
  check_field_data(*doc, root->FindNestedElementWithName("FieldData"));
  vtkXMLDataElement* primary = root->FindNestedElementWithName(composite_type);
  if (!primary) fail(path, std::string("no ") + composite_type + " element");
  CompositeWalk walk{
      path, std::string_view(composite_type) == "vtkPartitionedDataSetCollection", {}};
  walk.walk(primary, 0);
}

}  // namespace rayscope_vtkio
