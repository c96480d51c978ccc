#include "rayscope_vtkio/plain_obj.h"

#include <charconv>
#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkTypeInt64Array.h>

namespace rayscope_vtkio {
namespace {

bool blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// The words of one line, one at a time.
class Words {
 public:
  explicit Words(std::string_view line) : rest_(line) {}
  std::string_view next() {
    size_t b = 0;
    while (b < rest_.size() && blank(rest_[b])) ++b;
    size_t e = b;
    while (e < rest_.size() && !blank(rest_[e])) ++e;
    std::string_view w = rest_.substr(b, e - b);
    rest_ = rest_.substr(e);
    return w;
  }

 private:
  std::string_view rest_;
};

template <class T>
bool parse_whole(std::string_view w, T& value) {
  if (w.empty()) return false;
  const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), value);
  return ec == std::errc() && end == w.data() + w.size();
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::string s;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size <= 0) return {};
  s.resize(size_t(size));
  in.seekg(0);
  if (!in.read(s.data(), size)) return {};
  return s;
}

}  // namespace

vtkSmartPointer<vtkPolyData> read_plain_obj_file(const std::filesystem::path& path) {
  const std::string text = read_file(path);
  if (text.empty()) return nullptr;
  // About 30 bytes a vertex line and 20 a face line in files like the bunny.
  std::vector<float> xyz;
  std::vector<std::int64_t> offsets{0};
  std::vector<std::int64_t> corners;
  xyz.reserve(text.size() / 20);
  corners.reserve(text.size() / 8);
  std::string_view all(text);
  while (!all.empty()) {
    const size_t eol = all.find('\n');
    const std::string_view line = all.substr(0, eol);
    all = eol == std::string_view::npos ? std::string_view() : all.substr(eol + 1);
    Words words(line);
    const std::string_view key = words.next();
    if (key.empty() || key[0] == '#') continue;
    if (key == "v") {
      // x y z and an optional w, which VTK's reader ignores. It reads them
      // as floats, each rounded once from its decimal: so does this.
      float v[4];
      int n = 0;
      for (std::string_view w = words.next(); !w.empty(); w = words.next()) {
        if (n == 4 || !parse_whole(w, v[n])) return nullptr;
        ++n;
      }
      if (n < 3) return nullptr;
      xyz.insert(xyz.end(), v, v + 3);
    } else if (key == "f") {
      const long long defined = (long long)(xyz.size() / 3);
      size_t count = 0;
      for (std::string_view w = words.next(); !w.empty(); w = words.next()) {
        long long i = 0;
        if (!parse_whole(w, i) || i == 0 || i > defined || i < -defined) return nullptr;
        corners.push_back(i > 0 ? i - 1 : defined + i);
        ++count;
      }
      if (count < 3) return nullptr;
      offsets.push_back(std::int64_t(corners.size()));
    } else {
      return nullptr;
    }
  }
  if (xyz.empty() || corners.empty()) return nullptr;

  vtkNew<vtkFloatArray> coords;
  coords->SetName("Points");
  coords->SetNumberOfComponents(3);
  coords->SetNumberOfTuples(vtkIdType(xyz.size() / 3));
  std::copy(xyz.begin(), xyz.end(), coords->GetPointer(0));
  vtkNew<vtkPoints> points;
  points->SetData(coords);
  // The 64-bit storage vtkOBJReader's cell array has.
  vtkNew<vtkTypeInt64Array> offset_array;
  offset_array->SetNumberOfTuples(vtkIdType(offsets.size()));
  std::copy(offsets.begin(), offsets.end(), offset_array->GetPointer(0));
  vtkNew<vtkTypeInt64Array> connectivity;
  connectivity->SetNumberOfTuples(vtkIdType(corners.size()));
  std::copy(corners.begin(), corners.end(), connectivity->GetPointer(0));
  vtkNew<vtkCellArray> polys;
  polys->SetData(offset_array, connectivity);
  vtkNew<vtkFloatArray> groups;
  groups->SetName("GroupIds");
  groups->SetNumberOfTuples(vtkIdType(offsets.size() - 1));
  groups->FillValue(0.0f);

  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->SetPoints(points);
  out->SetPolys(polys);
  out->GetCellData()->AddArray(groups);
  return out;
}

}  // namespace rayscope_vtkio
