#include "rayscope/printf_string.h"

#include <cstdarg>
#include <cstdio>

namespace rayscope {

std::string printf_string(const char* format, ...) {
  va_list args, again;
  va_start(args, format);
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  std::string s;
  if (n > 0) {
    s.resize(size_t(n));
    std::vsnprintf(s.data(), size_t(n) + 1, format, again);
  }
  va_end(again);
  return s;
}

}  // namespace rayscope
