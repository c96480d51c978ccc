// Which level's hot loops (kernels.h) run: the table of the baseline
// kernels.cpp (compiled with this file's flags, in its inline namespace), and
// of the copies the build adds for higher levels (RAYSCOPE_KERNELS_* set by
// raytracer/CMakeLists.txt, each in the namespace isa.h names for its level).
#include <stdexcept>
#include <string>

#include "rayscope/kernels.h"

namespace rayscope {
inline namespace RAYSCOPE_ISA {
const Kernels& isa_kernels();
}
#if RAYSCOPE_KERNELS_SSE42
namespace sse42 {
const Kernels& isa_kernels();
}
#endif
#if RAYSCOPE_KERNELS_AVX2
namespace avx2 {
const Kernels& isa_kernels();
}
#endif
#if RAYSCOPE_KERNELS_AVX512
namespace avx512 {
const Kernels& isa_kernels();
}
#endif

namespace {

/// The table of `isa`, or null when this build has none.
const Kernels* table(Isa isa) {
  if (isa == kCompiledIsa) return &isa_kernels();
  switch (isa) {
#if RAYSCOPE_KERNELS_SSE42
    case Isa::Sse42:
      return &sse42::isa_kernels();
#endif
#if RAYSCOPE_KERNELS_AVX2
    case Isa::Avx2:
      return &avx2::isa_kernels();
#endif
#if RAYSCOPE_KERNELS_AVX512
    case Isa::Avx512:
      return &avx512::isa_kernels();
#endif
    default:
      return nullptr;
  }
}

}  // namespace

bool has_kernels(Isa isa) {
  return table(isa) != nullptr;
}

const Kernels& kernels(Isa isa) {
  const Kernels* k = table(isa);
  if (k == nullptr)
    throw std::runtime_error("this build has no " + std::string(isa_name(isa)) +
                             " kernels (its lowest level is " +
                             std::string(isa_name(kCompiledIsa)) + ")");
  if (!cpu_runs(isa))
    throw std::runtime_error("this CPU cannot run the " + std::string(isa_name(isa)) +
                             " kernels (it runs at most " + std::string(isa_name(best_cpu_isa())) +
                             ")");
  return *k;
}

const Kernels& kernels() {
  const Isa want = chosen_isa();
  for (int i = int(want); i >= 0; --i)
    if (has_kernels(Isa(i))) return kernels(Isa(i));
  return kernels(want);  // below this build's lowest level: kernels() says so
}

}  // namespace rayscope
