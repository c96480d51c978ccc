// Bytes from a file as text an error message can carry: a damaged or hostile
// file must not put control characters (a terminal's escape sequences, NULs,
// line breaks) or kilobytes of itself into the one error line.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace rayscope {

/// Most bytes of a file an error message quotes.
inline constexpr size_t kMaxQuotedBytes = 64;
/// Most bytes of one whole error message (its quotes, paths and words).
inline constexpr size_t kMaxMessageBytes = 1024;

/// `bytes` with every byte that is not printable text escaped: control
/// characters and DEL as \xNN (\t, \n and \r too), and bytes that are not part
/// of valid UTF-8 as \xNN; printable ASCII and valid UTF-8 sequences (names in
/// any script) are kept. At most `max_bytes` bytes of the input are shown;
/// longer input ends in "... (N bytes)" with its real length.
inline std::string printable_text(std::string_view bytes, size_t max_bytes = kMaxQuotedBytes) {
  std::string out;
  const size_t n = bytes.size() < max_bytes ? bytes.size() : max_bytes;
  auto escape = [&](unsigned char c) {
    char buf[5];
    std::snprintf(buf, sizeof buf, "\\x%02X", c);
    out += buf;
  };
  for (size_t i = 0; i < n;) {
    const unsigned char c = static_cast<unsigned char>(bytes[i]);
    if (c >= 0x20 && c < 0x7F) {
      out += char(c);
      ++i;
      continue;
    }
    // The length of a UTF-8 sequence led by c (0: not a lead byte), then
    // whether its continuation bytes are there (and within the shown part).
    const size_t len = c >= 0xC2 && c <= 0xDF   ? 2
                       : c >= 0xE0 && c <= 0xEF ? 3
                       : c >= 0xF0 && c <= 0xF4 ? 4
                                                : 0;
    bool valid = len > 0 && i + len <= n;
    for (size_t k = 1; valid && k < len; ++k)
      valid = (static_cast<unsigned char>(bytes[i + k]) & 0xC0) == 0x80;
    if (valid) {
      out.append(bytes.substr(i, len));
      i += len;
    } else {
      escape(c);
      ++i;
    }
  }
  if (bytes.size() > n) out += "... (" + std::to_string(bytes.size()) + " bytes)";
  return out;
}

}  // namespace rayscope
