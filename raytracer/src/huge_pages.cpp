#include "rayscope/huge_pages.h"

#include <cstdint>
#include <cstdlib>

#include <sys/mman.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace rayscope {
namespace {

constexpr uintptr_t kHugePage = uintptr_t(2) << 20;

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitizerAllocator = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer)
constexpr bool kSanitizerAllocator = true;
#else
constexpr bool kSanitizerAllocator = false;
#endif
#else
constexpr bool kSanitizerAllocator = false;
#endif

}  // namespace

void advise_huge_pages(const void* p, size_t bytes) {
#if defined(MADV_HUGEPAGE)
  if (p == nullptr || bytes < kHugePageMinBytes) return;
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(p) + kHugePage - 1) & ~(kHugePage - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(p) + bytes) & ~(kHugePage - 1);
  if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

size_t use_huge_pages_for_heap(size_t bytes) {
#if defined(__GLIBC__) && defined(MADV_HUGEPAGE)
  constexpr int kHeapAllocationMax = 32 << 20;  // glibc's largest M_MMAP_THRESHOLD
  if (kSanitizerAllocator || bytes < kHugePageMinBytes || bytes > size_t(1) << 30) return 0;
  if (!::mallopt(M_MMAP_THRESHOLD, kHeapAllocationMax) ||
      !::mallopt(M_TRIM_THRESHOLD, int(bytes)) || !::mallopt(M_TOP_PAD, int(bytes)))
    return 0;
  // The next growth of the heap (this allocation, unless the top of the heap
  // already has room for it) extends it by `bytes`: advise the part after the
  // allocation, up to the heap's end, and hand the allocation back.
  void* p = std::malloc(kHugePage);
  if (p == nullptr) return 0;
  const uintptr_t after = reinterpret_cast<uintptr_t>(p) + kHugePage;
  const uintptr_t heap_end = reinterpret_cast<uintptr_t>(::sbrk(0));
  const uintptr_t begin = (after + kHugePage - 1) & ~(kHugePage - 1);
  const uintptr_t end = heap_end & ~(kHugePage - 1);
  size_t advised = 0;
  // p lies below the heap's end only if it came from the heap (not a mapping
  // of its own, as when the heap cannot grow).
  if (after <= heap_end && end > begin && end - begin <= bytes + kHugePage &&
      ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE) == 0)
    advised = end - begin;
  std::free(p);
  ::mallopt(M_TOP_PAD, int(kHugePageMinBytes));  // later growth in steps of a few MiB
  return advised;
#else
  (void)bytes;
  return 0;
#endif
}

}  // namespace rayscope
