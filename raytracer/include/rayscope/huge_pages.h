// Transparent huge pages (2 MiB) for the large arrays of the builders and the
// walk. The kernel backs a page only when it is first written, one page fault
// per 4 KiB page by default, and on virtual machines a page fault is
// expensive: building the 1.1M-triangle mesh's BVH spent more time in page
// faults than in the builder (docs/performance.md). With huge pages advised
// before an array is filled it takes one fault per 2 MiB, and the walk misses
// the TLB less. Embree asks for huge pages the same way.
#pragma once

#include <cstddef>
#include <vector>

namespace rayscope {

/// Arrays smaller than this keep the default pages (a huge page is advised
/// only for the 2 MiB-aligned part of a range).
inline constexpr size_t kHugePageMinBytes = size_t(4) << 20;

/// Asks the kernel to back the 2 MiB-aligned part of [p, p + bytes) with
/// transparent huge pages (madvise MADV_HUGEPAGE): pages written after the
/// call, when the system's setting allows it ("madvise" or "always" in
/// /sys/kernel/mm/transparent_hugepage/enabled). Does nothing for ranges
/// below kHugePageMinBytes or where the call is not supported; never fails.
void advise_huge_pages(const void* p, size_t bytes);

/// Virtual address space use_huge_pages_for_heap() reserves by default. Pages
/// are backed only when written, so an unused reserve costs no memory.
inline constexpr size_t kHugeHeapBytes = size_t(512) << 20;

/// For programs, not libraries: it changes how the whole process's malloc
/// works. The small and middle-sized allocations of everything else a program
/// runs (VTK's readers and filters, the scene's containers) come from the
/// main heap, which grows 4 KiB page by page, one page fault each: page
/// faults were 18% of the CPU time of a cold `rayscope render` of the bunny
/// (perf; docs/performance.md). This grows the main heap by `bytes` now and
/// advises huge pages for it, keeps allocations of up to 32 MiB on that heap
/// (instead of a fresh mapping each), and keeps freed memory for reuse.
/// glibc only (mallopt); elsewhere, or under a sanitizer's allocator, it does
/// nothing. Call it at the start of main(), before other threads start.
/// Returns the bytes advised (0: nothing done).
size_t use_huge_pages_for_heap(size_t bytes = kHugeHeapBytes);

/// v.reserve(n), then huge pages advised for its storage: call it on an
/// array before filling it (assign, push_back).
template <class T>
void reserve_huge(std::vector<T>& v, size_t n) {
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

/// v.assign(n, value) into storage with huge pages advised (reserve_huge()).
template <class T>
void assign_huge(std::vector<T>& v, size_t n, const T& value = T()) {
  reserve_huge(v, n);
  v.assign(n, value);
}

/// v.shrink_to_fit() into storage with huge pages advised: the copy that
/// shrink_to_fit makes would otherwise take a page fault per 4 KiB (on the
/// 1.1M-triangle mesh the wide nodes' copy took longer than collapsing them).
template <class T>
void shrink_huge(std::vector<T>& v) {
  if (v.capacity() == v.size()) return;
  std::vector<T> compact;
  reserve_huge(compact, v.size());
  compact.assign(v.begin(), v.end());
  v.swap(compact);
}

}  // namespace rayscope
