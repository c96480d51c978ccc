// check_legacy_vtk_file() (mesh_checks.h): the structure of a legacy .vtk
// file, walked section by section as VTK's legacy readers walk it, before
// they run.
//
// The readers trust the file: a section with an unknown value type makes
// them go on with a null array and crash (vtkPolyDataReader after a FIELD
// array of type "floa"), short sections are read past, counts size buffers,
// and attribute data with fewer tuples than points or cells is indexed by
// the filters after them. So every section is checked here: its keyword, its
// value type, and that the file holds every value it declares (ASCII: as
// many numbers; binary: as many bytes), and point and cell data have one
// tuple per point or cell.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "check_util.h"
#include "rayscope_vtkio/mesh_checks.h"

namespace rayscope_vtkio {
namespace {

using namespace checks;
using u64 = std::uint64_t;

std::string lower(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = char(std::tolower(static_cast<unsigned char>(c)));
  return u;
}

/// Bytes of one binary value of a legacy type name (lower case), 0 if VTK's
/// legacy readers cannot read it as numbers; `is_integer` tells which ASCII
/// numbers it takes.
int type_size(std::string_view type, bool& is_integer) {
  struct Type {
    const char* name;
    int size;
    bool integer;
  };
  static constexpr Type kTypes[] = {
      {"unsigned_char", 1, true}, {"char", 1, true},           {"signed_char", 1, true},
      {"short", 2, true},         {"unsigned_short", 2, true}, {"int", 4, true},
      {"unsigned_int", 4, true},  {"long", 8, true},           {"unsigned_long", 8, true},
      {"vtkidtype", 4, true},     {"vtktypeint8", 1, true},    {"vtktypeuint8", 1, true},
      {"vtktypeint16", 2, true},  {"vtktypeuint16", 2, true},  {"vtktypeint32", 4, true},
      {"vtktypeuint32", 4, true}, {"vtktypeint64", 8, true},   {"vtktypeuint64", 8, true},
      {"float", 4, false},        {"double", 8, false},
  };
  for (const Type& t : kTypes)
    if (type == t.name) {
      is_integer = t.integer;
      return t.size;
    }
  return 0;
}

class LegacyFile {
 public:
  explicit LegacyFile(const fs::path& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) fail(path_, "cannot open the file");
    size_ = size_of(path_);
  }

  [[noreturn]] void error(const std::string& problem) const {
    fail(path_, "legacy VTK: " + problem);
  }

  std::string line() {
    std::string l;
    if (!std::getline(in_, l)) error("the file ends in its header");
    if (!l.empty() && l.back() == '\r') l.pop_back();
    return l;
  }
  /// The next word, or "" at the end of the file.
  std::string word() {
    std::string w;
    in_ >> w;
    line_pending_ = true;
    return w;
  }
  /// The next word as a count, at most `max`.
  u64 count(const std::string& what, u64 max = std::numeric_limits<long long>::max()) {
    const std::string w = word();
    const std::optional<long long> n = integer(w);
    if (!n || *n < 0 || u64(*n) > max)
      error(what + ": '" + rayscope::printable_text(w) + "' is not a valid count");
    return u64(*n);
  }
  /// The rest of the current line, as words.
  std::vector<std::string> rest_of_line() {
    std::string l;
    std::getline(in_, l);
    line_pending_ = false;
    std::vector<std::string> out;
    for (std::string_view w : words(l, Blanks::CSpace)) out.emplace_back(w);
    return out;
  }

  /// `n` values of `type` (lower case) follow: ASCII numbers, or binary
  /// values after the end of the current line. Returns the integer values
  /// when `keep` (for cell offsets and counts), else nothing.
  std::vector<long long> values(const std::string& what, u64 n, const std::string& type,
                                bool keep = false, bool binary_big_endian = true) {
    bool is_integer = false;
    const int size = type_size(type, is_integer);
    if (!size)
      error(what + ": unknown or unsupported value type '" + rayscope::printable_text(type) + "'");
    std::vector<long long> kept;
    if (binary_) {
      // The reader reads binary values from the start of the next line.
      if (line_pending_) in_.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
      line_pending_ = false;
      const u64 at = u64(std::streamoff(in_.tellg()));
      if (!in_ || at > size_ || (size_ - at) / u64(size) < n)
        error(what + " declares " + std::to_string(n) + " values but the file ends first");
      if (keep) {
        kept.resize(size_t(n));
        std::vector<unsigned char> b(size_t(n) * size_t(size));
        in_.read(reinterpret_cast<char*>(b.data()), std::streamsize(b.size()));
        for (size_t i = 0; i < kept.size(); ++i)
          kept[i] = binary_integer(b.data() + i * size_t(size), size, true, binary_big_endian);
      } else {
        in_.seekg(std::streamoff(at + n * u64(size)));
      }
      return kept;
    }
    // ASCII: every value is at least one character and a separator.
    if (n > size_ / 2 + 1)
      error(what + " declares " + std::to_string(n) + " values but the file ends first");
    if (keep) kept.reserve(size_t(n));
    std::string w;
    for (u64 k = 0; k < n; ++k) {
      if (!(in_ >> w))
        error(what + " declares " + std::to_string(n) + " values but the file ends after " +
              std::to_string(k) + " of them");
      bool ok = false;
      if (is_integer) {
        const std::optional<long long> v = integer(w);
        ok = v.has_value();
        if (ok && keep) kept.push_back(*v);
      } else {
        char* end = nullptr;
        std::strtod(w.c_str(), &end);
        ok = end == w.c_str() + w.size();
      }
      if (!ok)
        error(what + " declares " + std::to_string(n) + " values but value " + std::to_string(k) +
              " ('" + rayscope::printable_text(w) + "') is not a number");
    }
    return kept;
  }

  void set_binary(bool binary) { binary_ = binary; }
  bool binary() const { return binary_; }

 private:
  const fs::path& path_;
  std::ifstream in_;
  u64 size_ = 0;
  bool binary_ = false;
  bool line_pending_ = false;  // the last read was a word: its line goes on
};

/// A METADATA block after an array (component names, information keys): VTK
/// reads it up to its blank line; nothing in it is sized by the file.
void skip_metadata(LegacyFile& f) {
  f.rest_of_line();
  for (;;) {
    std::vector<std::string> w = f.rest_of_line();
    if (w.empty()) return;
  }
}

struct Counts {
  u64 points = 0, cells = 0;
  bool points_known = false;
};

/// The attribute sections after POINT_DATA n or CELL_DATA n, up to the next
/// dataset keyword (returned, lower case; "" at the end of the file).
std::string attributes(LegacyFile& f, u64 n, const char* of) {
  const std::string where = std::string(of) + " data";
  for (;;) {
    const std::string key = lower(f.word());
    if (key.empty() || key == "point_data" || key == "cell_data") return key;
    if (key == "scalars") {
      const std::vector<std::string> w = f.rest_of_line();  // name type [components]
      if (w.size() < 2 || w.size() > 3) f.error(where + ": malformed SCALARS line");
      u64 components = 1;
      if (w.size() == 3) {
        const std::optional<long long> c = integer(w[2]);
        if (!c || *c < 1 || *c > 4) f.error(where + ": SCALARS with an invalid component count");
        components = u64(*c);
      }
      if (lower(f.word()) != "lookup_table")
        f.error(where + ": SCALARS without its LOOKUP_TABLE line");
      f.rest_of_line();  // the table's name
      f.values(where + " SCALARS " + w[0], n * components, lower(w[1]));
    } else if (key == "color_scalars") {
      const std::vector<std::string> w = f.rest_of_line();  // name components
      const std::optional<long long> c = w.size() == 2 ? integer(w[1]) : std::nullopt;
      if (!c || *c < 1 || *c > 4) f.error(where + ": malformed COLOR_SCALARS line");
      f.values(where + " COLOR_SCALARS", n * u64(*c), f.binary() ? "unsigned_char" : "float");
    } else if (key == "lookup_table") {
      f.word();  // name
      const u64 size = f.count(where + " LOOKUP_TABLE", std::numeric_limits<int>::max());
      f.values(where + " LOOKUP_TABLE", 4 * size, f.binary() ? "unsigned_char" : "float");
    } else if (key == "vectors" || key == "normals" || key == "tensors" || key == "tensors6") {
      const std::vector<std::string> w = f.rest_of_line();  // name type
      if (w.size() != 2) f.error(where + ": malformed " + key + " line");
      const u64 per = key == "tensors" ? 9 : key == "tensors6" ? 6 : 3;
      f.values(where + " " + key, n * per, lower(w[1]));
    } else if (key == "texture_coordinates") {
      const std::vector<std::string> w = f.rest_of_line();  // name dim type
      const std::optional<long long> d = w.size() == 3 ? integer(w[1]) : std::nullopt;
      if (!d || *d < 1 || *d > 3) f.error(where + ": malformed TEXTURE_COORDINATES line");
      f.values(where + " TEXTURE_COORDINATES", n * u64(*d), lower(w[2]));
    } else if (key == "global_ids" || key == "pedigree_ids" || key == "edge_flags") {
      const std::vector<std::string> w = f.rest_of_line();  // name type
      if (w.size() != 2) f.error(where + ": malformed " + key + " line");
      f.values(where + " " + key, n, lower(w[1]));
    } else if (key == "field") {
      f.word();  // name
      const u64 arrays = f.count(where + " FIELD");
      for (u64 a = 0; a < arrays; ++a) {
        const std::string name = f.word();
        if (name == "NULL_ARRAY") continue;
        const u64 components =
            f.count("FIELD array '" + rayscope::printable_text(name) + "' components", 1 << 16);
        const u64 tuples = f.count("FIELD array '" + rayscope::printable_text(name) + "' tuples");
        const std::string type = lower(f.word());
        if (components == 0 || tuples != n)
          f.error("FIELD array '" + rayscope::printable_text(name) + "' in " + where +
                  " declares " + std::to_string(tuples) + " tuples, not one per " + of + " (" +
                  std::to_string(n) + ")");
        f.values("FIELD array '" + rayscope::printable_text(name) + "'", components * tuples, type);
      }
    } else if (key == "metadata") {
      skip_metadata(f);
    } else {
      f.error(where + ": unknown section '" + rayscope::printable_text(key) + "'");
    }
  }
}

/// A cell section: "KEY n size". Version 5 files follow it with OFFSETS (n
/// values) and CONNECTIVITY (size values); older ones with `size` values
/// listing each cell's point count, then its ids. Returns the cell count.
u64 cells_section(LegacyFile& f, const std::string& key, bool offsets_format) {
  const u64 n = f.count(key + " cell count");
  const u64 size = f.count(key + " size");
  if (!offsets_format) {
    const std::vector<long long> v = f.values(key, size, "int", true);
    u64 at = 0, found = 0;
    while (at < v.size()) {
      const long long npts = v[size_t(at)];
      if (npts < 0 || u64(npts) > v.size() - at - 1)
        f.error(key + ": cell " + std::to_string(found) + " has a bad point count or runs past " +
                "the " + std::to_string(size) + " values the section declares");
      at += u64(npts) + 1;
      ++found;
    }
    if (found != n)
      f.error(key + " declares " + std::to_string(n) + " cells but its " + std::to_string(size) +
              " values hold " + std::to_string(found));
    return n;
  }
  if (n == 0) return 0;
  if (lower(f.word()) != "offsets") f.error(key + ": no OFFSETS array");
  const std::vector<long long> offsets = f.values(key + " OFFSETS", n, lower(f.word()), true);
  if (offsets.front() != 0 || u64(offsets.back()) != size ||
      !std::is_sorted(offsets.begin(), offsets.end()))
    f.error(key + ": the OFFSETS do not run from 0 up to the " + std::to_string(size) +
            " connectivity values");
  if (lower(f.word()) != "connectivity") f.error(key + ": no CONNECTIVITY array");
  f.values(key + " CONNECTIVITY", size, lower(f.word()));
  return n - 1;
}

}  // namespace

void check_legacy_vtk_file(const fs::path& path) {
  LegacyFile f(path);
  // "# vtk DataFile Version M.m"; VTK reads a version without both numbers as
  // 0.0, an old version. From version 5 on, cells are offsets and
  // connectivity arrays; before, counts and ids.
  const std::string version = f.line();
  if (version.rfind("# vtk DataFile Version", 0) != 0)
    f.error("not a legacy VTK file (no '# vtk DataFile Version' line)");
  int major = 0, minor = 0;
  if (std::sscanf(version.c_str(), "# vtk DataFile Version %d.%d", &major, &minor) != 2) major = 0;
  f.line();  // title
  const std::string format = lower(f.line());
  if (format.rfind("binary", 0) == 0)
    f.set_binary(true);
  else if (format.rfind("ascii", 0) != 0)
    f.error("the third line must say ASCII or BINARY");
  if (lower(f.word()) != "dataset") f.error("no DATASET line (only datasets are read)");
  const std::string type = lower(f.word());
  const bool poly = type == "polydata", grid = type == "unstructured_grid";
  const bool structured =
      type == "structured_points" || type == "structured_grid" || type == "rectilinear_grid";
  if (!poly && !grid && !structured)
    f.error("unsupported DATASET type '" + rayscope::printable_text(type) + "'");

  Counts c;
  u64 dims[3] = {0, 0, 0};
  std::string key = lower(f.word());
  while (!key.empty()) {
    if (key == "points") {
      const u64 n = f.count("POINTS");
      if (structured && c.points_known && n != c.points)
        f.error("POINTS declares " + std::to_string(n) + " points but DIMENSIONS " +
                std::to_string(c.points));
      f.values("POINTS", 3 * n, lower(f.word()));
      c.points = n;
      c.points_known = true;
    } else if (structured && key == "dimensions") {
      u64 points = 1, cells = 1;
      for (u64& d : dims) {
        d = f.count("DIMENSIONS", kMaxStructuredPoints);
        points *= d;
        if (points > kMaxStructuredPoints)
          f.error("DIMENSIONS declare more than " + std::to_string(kMaxStructuredPoints) +
                  " points");
        cells *= d > 1 ? d - 1 : d;
      }
      c.points = points;
      c.cells = cells;
      c.points_known = true;
    } else if (structured && (key == "spacing" || key == "aspect_ratio" || key == "origin")) {
      // Written as text in binary files too.
      const bool binary = f.binary();
      f.set_binary(false);
      f.values(key, 3, "double");
      f.set_binary(binary);
    } else if (structured &&
               (key == "x_coordinates" || key == "y_coordinates" || key == "z_coordinates")) {
      const u64 n = f.count(key);
      const u64 axis = u64(key[0] - 'x');
      if (!c.points_known || n != dims[axis])
        f.error(key + " declares " + std::to_string(n) + " values, not its DIMENSIONS");
      f.values(key, n, lower(f.word()));
    } else if ((poly && (key == "vertices" || key == "lines" || key == "polygons" ||
                         key == "triangle_strips")) ||
               (grid && key == "cells")) {
      c.cells += cells_section(f, key, major >= 5);
    } else if (grid && key == "cell_types") {
      const u64 n = f.count("CELL_TYPES");
      if (n != c.cells)
        f.error("CELL_TYPES declares " + std::to_string(n) + " types for " +
                std::to_string(c.cells) + " cells");
      f.values("CELL_TYPES", n, "int");
    } else if (key == "point_data" || key == "cell_data") {
      const bool points = key == "point_data";
      const u64 n = f.count(key);
      if (n != (points ? c.points : c.cells))
        f.error(std::string(points ? "POINT_DATA" : "CELL_DATA") + " declares " +
                std::to_string(n) + " tuples but the dataset has " +
                std::to_string(points ? c.points : c.cells) + (points ? " points" : " cells"));
      key = attributes(f, n, points ? "point" : "cell");
      continue;
    } else if (key == "field") {
      // Field data of the whole dataset: arrays of any length.
      f.word();  // name
      const u64 arrays = f.count("FIELD");
      for (u64 a = 0; a < arrays; ++a) {
        const std::string name = f.word();
        if (name == "NULL_ARRAY") continue;
        const u64 components =
            f.count("FIELD array '" + rayscope::printable_text(name) + "' components", 1 << 16);
        const u64 tuples = f.count("FIELD array '" + rayscope::printable_text(name) + "' tuples");
        f.values("FIELD array '" + rayscope::printable_text(name) + "'", components * tuples,
                 lower(f.word()));
      }
    } else if (key == "metadata") {
      skip_metadata(f);
    } else {
      f.error("unknown section '" + rayscope::printable_text(key) + "' in a " + type + " dataset");
    }
    key = lower(f.word());
  }
}

}  // namespace rayscope_vtkio
