// Huge pages for large arrays (huge_pages.h): an array reserved with
// reserve_huge() and then filled is backed by transparent huge pages where the
// system allows them (the kernel's "madvise" or "always" setting).
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rayscope/huge_pages.h"

namespace {

using namespace rayscope;

std::string thp_setting() {
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string s;
  std::getline(f, s);
  return s;
}

// AnonHugePages (kB) of the mapping in /proc/self/smaps that holds `p`.
long huge_kb_of_mapping(const void* p) {
  std::ifstream smaps("/proc/self/smaps");
  const uintptr_t a = reinterpret_cast<uintptr_t>(p);
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    unsigned long lo = 0, hi = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
      inside = lo <= a && a < hi;
      continue;
    }
    if (inside && line.rfind("AnonHugePages:", 0) == 0) return std::stol(line.substr(14));
  }
  return -1;
}

TEST(HugePages, ALargeArrayReservedHugeIsBackedByHugePages) {
  const std::string setting = thp_setting();
  if (setting.empty() || setting.find("[never]") != std::string::npos)
    GTEST_SKIP() << "transparent huge pages are off here: '" << setting << "'";
  std::vector<uint32_t> v;
  reserve_huge(v, (size_t(64) << 20) / sizeof(uint32_t));  // 64 MiB
  v.assign(v.capacity(), 7u);
  // The advice covers the 2 MiB-aligned middle of the array (the kernel then
  // maps it separately from the unaligned ends): look there.
  EXPECT_GT(huge_kb_of_mapping(v.data() + v.size() / 2), 0) << "THP setting: " << setting;
}

}  // namespace
