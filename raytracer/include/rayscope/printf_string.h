// printf into a std::string, for the text views (ray trees, packet replays)
// that lay out numbers in columns.
#pragma once

#include <string>

namespace rayscope {

/// `format` with `...` substituted as std::snprintf does, of any length.
std::string printf_string(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace rayscope
