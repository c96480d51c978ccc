#include "rayscope_vtkio/mesh_checks.h"

#include "check_util.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <vtkCell.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkGenericCell.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtksys/SystemTools.hxx>

namespace rayscope_vtkio {
namespace {

namespace fs = std::filesystem;
using namespace checks;

// ---- STL ------------------------------------------------------------------

// ---- PLY ------------------------------------------------------------------

// VTK's PLY reader reads ASCII lines into a buffer of this many bytes
// (vtkPLY.cxx, BIG_STRING) and splits longer ones, which shifts every later
// item; such files are refused.
constexpr size_t kPlyMaxLine = 4096 - 2;

// VTK's PLY reader rewrites the first "vertex_index" of every line it reads,
// header or data, to "vertex_indices" and ends the line there (vtkPLY.cxx,
// get_words: meant for the face list's name). The checks see each line as
// the reader will; a line where the longer name would not fit its buffer is
// refused. Returns false for that line.
bool as_vtk_reads_ply_line(std::string& line) {
  static constexpr std::string_view kShort = "vertex_index", kLong = "vertex_indices";
  const size_t at = line.find(kShort);
  if (at == std::string::npos) return true;
  if (at + kLong.size() > kPlyMaxLine) return false;
  line.replace(at, std::string::npos, kLong);
  return true;
}

// A PLY scalar as VTK's reader takes it (atoi or strtod): a word that is not
// wholly a number would be read as 0 or as its leading digits.
bool is_ply_number(std::string_view word) {
  const std::string s(word);
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return !s.empty() && end == s.c_str() + s.size();
}

struct PlyProperty {
  std::string name;
  int size = 0;            // bytes of a scalar or of each list entry
  bool is_float = false;   // of a scalar or of each list entry
  bool is_signed = false;  // of a scalar or of each list entry
  int count_size = 0;      // list: bytes of the count; 0 for a scalar
  bool count_signed = false;
};

struct PlyElement {
  std::string name;
  std::uintmax_t count = 0;
  std::vector<PlyProperty> properties;
};

// The PLY type names VTK's reader knows (vtkPLY.cxx), with their sizes.
bool ply_type(std::string_view t, int& size, bool& is_float, bool& is_signed) {
  struct Type {
    const char* a;
    const char* b;
    int size;
    bool is_float, is_signed;
  };
  static constexpr Type kTypes[] = {
      {"char", "int8", 1, false, true},    {"uchar", "uint8", 1, false, false},
      {"short", "int16", 2, false, true},  {"ushort", "uint16", 2, false, false},
      {"int", "int32", 4, false, true},    {"uint", "uint32", 4, false, false},
      {"float", "float32", 4, true, true}, {"double", "float64", 8, true, true},
  };
  for (const Type& k : kTypes)
    if (t == k.a || t == k.b) {
      size = k.size;
      is_float = k.is_float;
      is_signed = k.is_signed;
      return true;
    }
  return false;
}

// Face corner lists are checked against the vertex count: VTK's reader copies
// them into the cells unchecked.
bool is_corner_list(const PlyElement& e, const PlyProperty& p) {
  return e.name == "face" && p.count_size > 0 && p.name == "vertex_indices";
}

// The layout VTK's PLY reader needs (vtkPLYReader.h): a "vertex" element
// with scalar x, y and z, and a "face" element with the list
// "vertex_indices". The reader asks for its properties by name, each as a
// scalar or a list, and the PLY library stores a property of the other kind,
// or an absent list, through the wrong pointer: so the vertex element may have
// no list at all and the face element lists only where the reader expects
// them (vertex_indices, texcoord).
void check_ply_layout(const fs::path& path, const std::vector<PlyElement>& elements) {
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex" && !vertex) vertex = &e;
    if (e.name == "face" && !face) face = &e;
    // VTK's reader reads the vertex and face elements where they are and
    // skips nothing: another element's data before them would be read as
    // theirs (then faces name points that do not exist). After them it is
    // never read.
    if (e.name != "vertex" && e.name != "face" && (!vertex || !face))
      fail(path, "PLY element '" + e.name +
                     "' comes before the vertex and face elements (VTK's reader cannot skip it)");
  }
  if (!vertex || !face)
    fail(path, "PLY without a 'vertex' and a 'face' element (VTK's reader needs both)");
  for (const char* axis : {"x", "y", "z"}) {
    bool found = false;
    for (const PlyProperty& p : vertex->properties) found |= p.name == axis && p.count_size == 0;
    if (!found) fail(path, std::string("PLY vertex element has no scalar property '") + axis + "'");
  }
  for (const PlyProperty& p : vertex->properties)
    if (p.count_size > 0) fail(path, "PLY vertex element has a list property '" + p.name + "'");
  bool indices = false;
  for (const PlyProperty& p : face->properties) {
    const bool may_be_list = p.name == "vertex_indices" || p.name == "texcoord";
    if (p.count_size > 0 && !may_be_list)
      fail(path, "PLY face element has an unexpected list property '" + p.name + "'");
    if (p.count_size == 0 && may_be_list)
      fail(path, "PLY face property '" + p.name + "' is not a list");
    indices |= p.name == "vertex_indices";
  }
  if (!indices) fail(path, "PLY face element has no list property 'vertex_indices'");
}

// Reads the binary body through a buffer, so that files of any size are
// walked in bounded memory.
class BodyReader {
 public:
  BodyReader(std::ifstream& in, std::uintmax_t start, std::uintmax_t end)
      : in_(in), pos_(start), end_(end) {
    in_.seekg(std::streamoff(start));
  }
  std::uintmax_t left() const { return end_ - pos_; }
  // `n` (<= 8) bytes, or null past the end.
  const unsigned char* take(int n) {
    if (left() < std::uintmax_t(n)) return nullptr;
    in_.read(reinterpret_cast<char*>(bytes_), n);
    if (in_.gcount() != n) return nullptr;
    pos_ += std::uintmax_t(n);
    return bytes_;
  }
  bool skip(std::uintmax_t n) {
    if (left() < n) return false;
    pos_ += n;
    in_.seekg(std::streamoff(pos_));
    return bool(in_);
  }

 private:
  std::ifstream& in_;
  std::uintmax_t pos_, end_;
  unsigned char bytes_[8];
};

}  // namespace

void check_stl_file(const fs::path& path) {
  const std::uintmax_t size = size_of(path);
  char head[kStlHeaderBytes] = {};
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file");
  in.read(head, std::streamsize(sizeof head));
  const size_t got = size_t(in.gcount());
  std::uintmax_t declared = 0, expected = 0;
  if (got == kStlHeaderBytes) {
    declared = std::uintmax_t(
        binary_integer(reinterpret_cast<const unsigned char*>(head) + 80, 4, false, false));
    expected = kStlHeaderBytes + declared * kStlTriangleBytes;
    if (size == expected) return;  // binary, complete
  }
  // ASCII or binary as VTK's reader decides (by the share of non-text bytes
  // at the start): ASCII is checked by the reader itself (its errors are
  // caught), binary must be what its header says.
  if (vtksys::SystemTools::DetectFileType(path.c_str()) == vtksys::SystemTools::FileTypeText)
    return;
  if (got < kStlHeaderBytes)
    fail(path, "not an STL file: " + std::to_string(size) +
                   " bytes of binary data, shorter than a binary STL header (84 bytes)");
  if (size < expected) {
    const std::uintmax_t room = (size - kStlHeaderBytes) / kStlTriangleBytes;
    fail(path, "truncated binary STL: the header declares " + std::to_string(declared) +
                   " triangles (" + std::to_string(expected) + " bytes) but the file has " +
                   std::to_string(size) + " bytes, " + std::to_string(declared - room) +
                   " triangles are missing");
  }
  fail(path, "damaged binary STL: the header declares " + std::to_string(declared) +
                 " triangles (" + std::to_string(expected) + " bytes) but the file has " +
                 std::to_string(size) + " bytes; the " + std::to_string(size - expected) +
                 " extra bytes would be read as triangles");
}

void check_ply_file(const fs::path& path) {
  const std::uintmax_t size = size_of(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file");

  // The header, line by line, as VTK's reader splits it into words.
  std::string line;
  auto next_line = [&](const char* what) {
    if (!std::getline(in, line)) fail(path, std::string("PLY header ends early: ") + what);
    if (line.size() > kPlyMaxLine)
      fail(path, "PLY header line longer than " + std::to_string(kPlyMaxLine) + " characters");
    if (line.find('\0') != std::string::npos) fail(path, "PLY header line with a NUL byte");
    if (!as_vtk_reads_ply_line(line))
      fail(path, "PLY header line with 'vertex_index' too near its end for VTK's reader");
    return words(line);
  };
  std::vector<std::string_view> w = next_line("no 'ply'");
  if (w.size() != 1 || w[0] != "ply") fail(path, "not a PLY file (no 'ply' on the first line)");
  enum class Format { None, Ascii, Little, Big } format = Format::None;
  std::vector<PlyElement> elements;
  for (;;) {
    w = next_line("no 'end_header'");
    if (w.empty()) continue;
    if (w[0] == "end_header") break;
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (w.size() != 3) fail(path, "PLY header: malformed 'format' line");
      if (format != Format::None) fail(path, "PLY header has two 'format' lines");
      if (w[1] == "ascii")
        format = Format::Ascii;
      else if (w[1] == "binary_little_endian")
        format = Format::Little;
      else if (w[1] == "binary_big_endian")
        format = Format::Big;
      else
        fail(path, "PLY header: unknown format '" + rayscope::printable_text(w[1]) + "'");
    } else if (w[0] == "element") {
      std::optional<long long> n = w.size() == 3 ? integer(w[2]) : std::nullopt;
      // VTK's reader keeps counts in an int.
      if (!n || *n < 0 || *n > INT_MAX)
        fail(path, "PLY header: malformed 'element' line '" + rayscope::printable_text(line) + "'");
      // VTK's reader finds elements and properties by name: the first of
      // two namesakes would be read with the layout of either.
      for (const PlyElement& e : elements)
        if (e.name == w[1]) fail(path, "PLY header declares element '" + e.name + "' twice");
      elements.push_back({std::string(w[1]), std::uintmax_t(*n), {}});
    } else if (w[0] == "property") {
      if (elements.empty()) fail(path, "PLY header: 'property' before any 'element'");
      PlyProperty p;
      bool ok = false;
      if (w.size() == 5 && w[1] == "list") {
        bool count_float = false;
        ok = ply_type(w[2], p.count_size, count_float, p.count_signed) && !count_float &&
             ply_type(w[3], p.size, p.is_float, p.is_signed);
        p.name = std::string(w[4]);
      } else if (w.size() == 3) {
        ok = ply_type(w[1], p.size, p.is_float, p.is_signed);
        p.name = std::string(w[2]);
      }
      if (!ok)
        fail(path,
             "PLY header: malformed or unknown property '" + rayscope::printable_text(line) + "'");
      for (const PlyProperty& q : elements.back().properties)
        if (q.name == p.name)
          fail(path, "PLY header declares property '" + p.name + "' of element '" +
                         elements.back().name + "' twice");
      elements.back().properties.push_back(p);
    } else {
      fail(path, "PLY header: unknown line '" + rayscope::printable_text(line) + "'");
    }
  }
  if (format == Format::None) fail(path, "PLY header has no 'format' line");
  check_ply_layout(path, elements);
  std::uintmax_t vertices = 0;
  for (const PlyElement& e : elements)
    if (e.name == "vertex") vertices = e.count;

  auto short_body = [&](const PlyElement& e, std::uintmax_t item) {
    fail(path, "truncated PLY: the header declares " + std::to_string(e.count) + " " + e.name +
                   " elements but the data ends at " + e.name + " " + std::to_string(item));
  };
  auto bad_corner = [&](const PlyElement& e, std::uintmax_t item, long long id) {
    fail(path, e.name + " " + std::to_string(item) + " refers to vertex " + std::to_string(id) +
                   " but the file has " + std::to_string(vertices) + " vertices");
  };

  if (format == Format::Ascii) {
    for (const PlyElement& e : elements) {
      for (std::uintmax_t item = 0; item < e.count; ++item) {
        if (!std::getline(in, line)) short_body(e, item);
        if (line.size() > kPlyMaxLine)
          fail(path, e.name + " " + std::to_string(item) + ": line longer than " +
                         std::to_string(kPlyMaxLine) + " characters");
        // VTK's reader splits C strings: a NUL byte ends the line early.
        if (line.find('\0') != std::string::npos)
          fail(path, e.name + " " + std::to_string(item) + ": line with a NUL byte");
        if (!as_vtk_reads_ply_line(line))
          fail(path, e.name + " " + std::to_string(item) +
                         ": 'vertex_index' too near the end of a long line for VTK's reader");
        w = words(line);
        // VTK's reader drops a line without its newline (the file ends in
        // it) and then frees what it never read: such a file is truncated.
        if (in.eof()) short_body(e, item);
        size_t at = 0;
        for (const PlyProperty& p : e.properties) {
          if (at >= w.size()) {
            fail(path, e.name + " " + std::to_string(item) + ": fewer values than its " +
                           std::to_string(e.properties.size()) + " properties");
          }
          if (p.count_size == 0) {
            if (!is_ply_number(w[at]))
              fail(path, e.name + " " + std::to_string(item) + ": property '" + p.name + "' is '" +
                             rayscope::printable_text(w[at]) + "', not a number");
            ++at;
            continue;
          }
          std::optional<long long> n = integer(w[at++]);
          if (!n || *n < 0 || std::uintmax_t(*n) > w.size() - at)
            fail(path, e.name + " " + std::to_string(item) + ": list '" + p.name +
                           "' has a bad count or fewer entries than its count");
          for (long long k = 0; k < *n; ++k, ++at)
            if (is_corner_list(e, p)) {
              std::optional<long long> id = integer(w[at]);
              if (!id || *id < 0 || std::uintmax_t(*id) >= vertices)
                bad_corner(e, item, id ? *id : -1);
            } else if (!is_ply_number(w[at])) {
              fail(path, e.name + " " + std::to_string(item) + ": list '" + p.name + "' holds '" +
                             rayscope::printable_text(w[at]) + "', not a number");
            }
        }
      }
    }
    return;
  }

  const bool big = format == Format::Big;
  BodyReader body(in, std::uintmax_t(in.tellg()), size);
  for (const PlyElement& e : elements) {
    bool has_list = false;
    std::uintmax_t fixed = 0;
    for (const PlyProperty& p : e.properties) {
      has_list |= p.count_size > 0;
      fixed += std::uintmax_t(p.size);
    }
    if (!has_list) {  // all items have the same size: no need to read them
      if (body.left() / (fixed ? fixed : 1) < e.count || !body.skip(fixed * e.count))
        short_body(e, body.left() / (fixed ? fixed : 1));
      continue;
    }
    for (std::uintmax_t item = 0; item < e.count; ++item) {
      for (const PlyProperty& p : e.properties) {
        if (p.count_size == 0) {
          if (!body.skip(std::uintmax_t(p.size))) short_body(e, item);
          continue;
        }
        const unsigned char* c = body.take(p.count_size);
        if (!c) short_body(e, item);
        const long long n = binary_integer(c, p.count_size, p.count_signed, big);
        if (n < 0)
          fail(path, e.name + " " + std::to_string(item) + ": list '" + p.name +
                         "' has a negative count");
        if (!is_corner_list(e, p) || p.is_float) {
          if (body.left() / std::uintmax_t(p.size) < std::uintmax_t(n) ||
              !body.skip(std::uintmax_t(n) * std::uintmax_t(p.size)))
            short_body(e, item);
          continue;
        }
        for (long long k = 0; k < n; ++k) {
          const unsigned char* v = body.take(p.size);
          if (!v) short_body(e, item);
          const long long id = binary_integer(v, p.size, p.is_signed, big);
          if (id < 0 || std::uintmax_t(id) >= vertices) bad_corner(e, item, id);
        }
      }
    }
  }
}

void check_obj_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file");
  // Vertices, texture coordinates and normals defined so far: what a face
  // corner "v/vt/vn" (1-based, or negative: counted back from the last) may
  // name.
  long long counts[3] = {0, 0, 0};
  int face_kinds = -1;  // which of them the faces name (bits 0..2), -1 before the first
  static constexpr const char* kKinds[3] = {"vertex", "texture coordinate", "normal"};
  std::string line;
  for (long long number = 1; std::getline(in, line); ++number) {
    // OBJ is text: a control byte (a binary or random file) would reach VTK's
    // reader, which reports such a file as a line "longer than 262144" and
    // quotes its bytes.
    const auto control = std::find_if(line.begin(), line.end(), [](char ch) {
      const auto c = static_cast<unsigned char>(ch);
      return (c < 0x20 && c != '\t' && c != '\r' && c != '\v' && c != '\f') || c == 0x7F;
    });
    if (control != line.end()) {
      char byte[8];
      std::snprintf(byte, sizeof byte, "0x%02X", unsigned(static_cast<unsigned char>(*control)));
      fail(path, "line " + std::to_string(number) + ", column " +
                     std::to_string(control - line.begin() + 1) + ": control byte " + byte +
                     ": not a text file");
    }
    const std::vector<std::string_view> w = words(line, Blanks::CSpace);
    if (w.empty()) continue;
    if (w[0] == "v") ++counts[0];
    if (w[0] == "vt") ++counts[1];
    if (w[0] == "vn") ++counts[2];
    if (w[0] != "f" && w[0] != "l" && w[0] != "p") continue;
    // VTK's reader takes texture coordinates and normals for every corner
    // once one corner has them: a corner without crashes it, and a face
    // naming other kinds than the faces before it is dropped without a word.
    // So the corners of an element, and all faces, name the same kinds.
    int first_kinds = w[0] == "f" ? face_kinds : -1;
    for (size_t c = 1; c < w.size(); ++c) {
      std::string_view corner = w[c];
      // "v", "v/vt", "v//vn" or "v/vt/vn". VTK's reader reads on past white
      // space after a slash ("1/ 2" as "1/2"), so nothing may end in one.
      const size_t slashes = size_t(std::count(corner.begin(), corner.end(), '/'));
      if (corner.front() == '/' || corner.back() == '/' || slashes > 2 ||
          (slashes == 1 && corner.find("//") != std::string_view::npos))
        fail(path, "line " + std::to_string(number) + ": malformed corner '" +
                       rayscope::printable_text(corner) + "' (use v, v/vt, v//vn or v/vt/vn)");
      int corner_kinds = 0;
      for (int kind = 0; kind < 3 && !corner.empty(); ++kind) {
        const size_t slash = corner.find('/');
        const std::string_view part = corner.substr(0, slash);
        if (!part.empty()) {
          corner_kinds |= 1 << kind;
          const std::optional<long long> i = integer(part);
          if (!i || *i == 0 || *i > counts[kind] || *i < -counts[kind])
            fail(path, "line " + std::to_string(number) + ": '" + rayscope::printable_text(w[c]) +
                           "' names " + kKinds[kind] + " " + rayscope::printable_text(part) +
                           " of " + std::to_string(counts[kind]) + " defined before it");
        }
        corner = slash == std::string_view::npos ? std::string_view() : corner.substr(slash + 1);
      }
      if (first_kinds < 0) first_kinds = corner_kinds;
      if (corner_kinds != first_kinds)
        fail(path, "line " + std::to_string(number) + ": corner '" +
                       rayscope::printable_text(w[c]) + "' differs from " +
                       (c == 1 ? "the faces before it" : "the corners before it") +
                       " in naming texture coordinates or normals");
    }
    if (w[0] == "f") face_kinds = first_kinds;
  }
}

std::string check_cell_point_ids(vtkDataSet* data) {
  if (!data) return {};
  const vtkIdType points = data->GetNumberOfPoints();
  auto describe = [&](vtkIdType cell, vtkIdType id) {
    std::ostringstream s;
    s << "cell " << cell << " refers to point " << id << " but the data has " << points
      << (points == 1 ? " point" : " points");
    return s.str();
  };
  // The first cell of `cells` (numbered from `first`) with an id outside
  // 0..points-1, if any. The range of the connectivity array answers for
  // valid data without a walk over the cells.
  auto check = [&](vtkCellArray* cells, vtkIdType first) -> std::string {
    if (!cells) return {};
    // Offsets that start past 0, decrease, or end elsewhere than the
    // connectivity's end make cells of absurd sizes (a damaged legacy file).
    if (!cells->IsValid())
      return "the offsets of the cells from cell " + std::to_string(first) +
             " on do not match their point ids (a damaged cell array)";
    if (cells->GetNumberOfConnectivityIds() == 0) return {};
    double range[2];
    cells->GetConnectivityArray()->GetRange(range, 0);
    if (range[0] >= 0.0 && range[1] < double(points)) return {};
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < cells->GetNumberOfCells(); ++c) {
      cells->GetCellAtId(c, ids);
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
        if (ids->GetId(k) < 0 || ids->GetId(k) >= points) return describe(first + c, ids->GetId(k));
    }
    return {};
  };
  if (auto* pd = vtkPolyData::SafeDownCast(data)) {
    // Cell ids of polydata count verts, then lines, polys, strips.
    vtkIdType first = 0;
    for (vtkCellArray* cells : {pd->GetVerts(), pd->GetLines(), pd->GetPolys(), pd->GetStrips()}) {
      if (std::string e = check(cells, first); !e.empty()) return e;
      if (cells) first += cells->GetNumberOfCells();
    }
    return {};
  }
  if (auto* ug = vtkUnstructuredGrid::SafeDownCast(data)) {
    if (std::string e = check(ug->GetCells(), 0); !e.empty()) return e;
    // Each cell's type must be one VTK knows, and a type of fixed size (a
    // pyramid has 5 points) must have that many points: VTK's filters read a
    // cell's points by its type (a 4-point "pyramid" crashed the surface filter).
    std::map<int, vtkIdType> fixed_size;  // per type seen: its points, 0 if variable
    vtkCellArray* cells = ug->GetCells();
    for (vtkIdType c = 0; cells && c < ug->GetNumberOfCells(); ++c) {
      const int type = ug->GetCellType(c);
      auto it = fixed_size.find(type);
      if (it == fixed_size.end()) {
        vtkSmartPointer<vtkCell> cell =
            vtkSmartPointer<vtkCell>::Take(vtkGenericCell::InstantiateCell(type));
        if (!cell || type == VTK_EMPTY_CELL)
          return "cell " + std::to_string(c) + " has an unknown cell type " + std::to_string(type);
        it = fixed_size.emplace(type, cell->GetPointIds()->GetNumberOfIds()).first;
      }
      const vtkIdType size = cells->GetCellSize(c);
      if (it->second > 0 ? size != it->second : size < 1)
        return "cell " + std::to_string(c) + " of type " + std::to_string(type) + " has " +
               std::to_string(size) + " points" +
               (it->second > 0 ? " instead of " + std::to_string(it->second) : "");
    }
    // Polyhedra list their faces in a separate stream: per cell, the number
    // of faces, then per face the number of points and the point ids. A
    // polyhedron without a place in that stream (no stream, or a negative
    // location; a file whose 'faceoffsets' say no cell has faces) crashed
    // VTK's surface filter, which reads its faces unchecked.
    vtkIdTypeArray* faces = ug->GetFaces();
    vtkIdTypeArray* locations = ug->GetFaceLocations();
    for (vtkIdType c = 0; cells && c < ug->GetNumberOfCells(); ++c)
      if (ug->GetCellType(c) == VTK_POLYHEDRON &&
          (!faces || !locations || c >= locations->GetNumberOfValues() ||
           locations->GetValue(c) < 0))
        return "cell " + std::to_string(c) + " is a polyhedron without faces";
    if (faces && locations) {
      const vtkIdType n = faces->GetNumberOfValues();
      for (vtkIdType c = 0; c < locations->GetNumberOfValues(); ++c) {
        vtkIdType at = locations->GetValue(c);
        if (at < 0) continue;  // not a polyhedron
        const std::string malformed = "cell " + std::to_string(c) + ": malformed polyhedron faces";
        if (at >= n) return malformed;
        const vtkIdType nfaces = faces->GetValue(at++);
        for (vtkIdType f = 0; f < nfaces; ++f) {
          if (at >= n) return malformed;
          const vtkIdType npts = faces->GetValue(at++);
          if (npts < 0 || npts > n - at) return malformed;
          for (vtkIdType k = 0; k < npts; ++k, ++at)
            if (faces->GetValue(at) < 0 || faces->GetValue(at) >= points)
              return describe(c, faces->GetValue(at));
        }
      }
    }
  }
  return {};
}

std::vector<std::string> remove_short_attribute_arrays(vtkDataSet* data) {
  std::vector<std::string> removed;
  if (!data) return removed;
  // Point arrays first, then cell arrays, each in array order. Removed from
  // the last, so that the indices of those still to look at do not move.
  auto remove_short = [&](vtkFieldData* fd, vtkIdType n, const char* kind) {
    std::vector<std::string> of_kind;
    for (int i = fd->GetNumberOfArrays() - 1; i >= 0; --i) {
      vtkAbstractArray* a = fd->GetAbstractArray(i);
      if (!a || a->GetNumberOfTuples() >= n) continue;
      const vtkIdType tuples = a->GetNumberOfTuples();
      of_kind.push_back(std::string(kind) + " array '" + (a->GetName() ? a->GetName() : "") +
                        "' has " + std::to_string(tuples) + (tuples == 1 ? " tuple" : " tuples") +
                        " but the data has " + std::to_string(n) + " " + kind +
                        (n == 1 ? "" : "s"));
      fd->RemoveArray(i);
    }
    removed.insert(removed.end(), of_kind.rbegin(), of_kind.rend());
  };
  remove_short(data->GetPointData(), data->GetNumberOfPoints(), "point");
  remove_short(data->GetCellData(), data->GetNumberOfCells(), "cell");
  return removed;
}

}  // namespace rayscope_vtkio
