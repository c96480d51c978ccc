// Huge pages for large arrays (huge_pages.h): an array reserved with
// reserve_huge() and then filled is backed by transparent huge pages where the
// system allows them (the kernel's "madvise" or "always" setting).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
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

// use_huge_pages_for_heap() (what the rayscope program calls first): an
// allocation of a few MiB, which glibc would otherwise map on its own with
// 4 KiB pages, comes from the advised heap and is backed by huge pages. This
// test changes the process's malloc settings, so it runs in this program only.
TEST(HugePages, TheProgramsHeapIsBackedByHugePages) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "not glibc: use_huge_pages_for_heap() does nothing here";
#endif
  const std::string setting = thp_setting();
  if (setting.empty() || setting.find("[never]") != std::string::npos)
    GTEST_SKIP() << "transparent huge pages are off here: '" << setting << "'";
  const size_t advised = use_huge_pages_for_heap();
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "the sanitizer's allocator replaces malloc";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  GTEST_SKIP() << "the sanitizer's allocator replaces malloc";
#endif
#endif
  ASSERT_GE(advised, kHugePageMinBytes);
  EXPECT_LE(advised, kHugeHeapBytes + (size_t(2) << 20));
  const size_t bytes = size_t(16) << 20;  // above glibc's default mmap threshold
  char* p = static_cast<char*>(std::malloc(bytes));
  ASSERT_NE(p, nullptr);
  std::memset(p, 1, bytes);
  EXPECT_GT(huge_kb_of_mapping(p + bytes / 2), 0) << "THP setting: " << setting;
  std::free(p);
}

}  // namespace
