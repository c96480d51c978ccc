// Helpers shared by the file checks (mesh_checks.cpp, legacy_vtk_checks.cpp,
// vtk_xml_checks.cpp); internal to rayscope_vtkio.
#pragma once

#include <charconv>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "rayscope/printable_text.h"

namespace rayscope_vtkio::checks {

namespace fs = std::filesystem;

/// Throws the one-line error "FILE: problem". Problems quote the file's
/// words and lines: printable, within rayscope::kMaxMessageBytes (each quote
/// is best cut to rayscope::kMaxQuotedBytes where it is made).
[[noreturn]] inline void fail(const fs::path& path, const std::string& problem) {
  throw std::runtime_error(path.string() + ": " +
                           rayscope::printable_text(problem, rayscope::kMaxMessageBytes));
}

inline std::uintmax_t size_of(const fs::path& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) fail(path, "cannot read its size (" + ec.message() + ")");
  return size;
}

/// Where a reader's words end: at a space, tab or carriage return (VTK's PLY
/// reader), or at any C white space, vertical tab and form feed too
/// (`std::isspace`: istream >>, VTK's OBJ reader).
enum class Blanks { SpaceTabReturn, CSpace };

/// The words of a line, split as `blanks` says.
inline std::vector<std::string_view> words(std::string_view line,
                                           Blanks blanks = Blanks::SpaceTabReturn) {
  auto blank = [blanks](char c) {
    return c == ' ' || c == '\t' || c == '\r' ||
           (blanks == Blanks::CSpace && (c == '\n' || c == '\v' || c == '\f'));
  };
  std::vector<std::string_view> w;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && blank(line[i])) ++i;
    size_t j = i;
    while (j < line.size() && !blank(line[j])) ++j;
    if (j > i) w.push_back(line.substr(i, j - i));
    i = j;
  }
  return w;
}

/// `s` as a whole integer, or nullopt.
inline std::optional<long long> integer(std::string_view s) {
  long long v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

// A scalar of `size` bytes as an integer (the caller knows it is one).
inline long long binary_integer(const unsigned char* b, int size, bool is_signed, bool big_endian) {
  unsigned long long u = 0;
  for (int k = 0; k < size; ++k) {
    const int byte = big_endian ? k : size - 1 - k;
    u = (u << 8) | b[byte];
  }
  if (is_signed && size < 8 && (u >> (8 * size - 1)) != 0) u |= ~0ull << (8 * size);
  return static_cast<long long>(u);
}

}  // namespace rayscope_vtkio::checks
