#include "rayscope/isa.h"

#include <cstdlib>
#include <stdexcept>

namespace rayscope {

std::string_view isa_name(Isa isa) {
  switch (isa) {
    case Isa::Sse2:
      return "sse2";
    case Isa::Sse42:
      return "sse4.2";
    case Isa::Avx2:
      return "avx2";
    case Isa::Avx512:
      return "avx512";
  }
  return "?";
}

bool cpu_runs(Isa isa) {
#if defined(__x86_64__)
  // libgcc's (and compiler-rt's) CPUID reading, which also asks the operating
  // system (XGETBV) whether it saves the AVX and AVX-512 registers.
  __builtin_cpu_init();
  switch (isa) {
    case Isa::Sse2:
      return true;
    case Isa::Sse42:
      return __builtin_cpu_supports("ssse3") && __builtin_cpu_supports("sse4.1") &&
             __builtin_cpu_supports("sse4.2") && __builtin_cpu_supports("popcnt");
    case Isa::Avx2:
      return cpu_runs(Isa::Sse42) && __builtin_cpu_supports("avx") &&
             __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
             __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2");
    case Isa::Avx512:
      return cpu_runs(Isa::Avx2) && __builtin_cpu_supports("avx512f") &&
             __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512cd") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
  }
  return false;
#else
  return isa == kCompiledIsa;
#endif
}

Isa best_cpu_isa() {
  Isa best = Isa::Sse2;
  for (Isa isa : kAllIsas)
    if (cpu_runs(isa)) best = isa;
  return best;
}

Isa chosen_isa() {
  const char* asked = std::getenv(kIsaVariable);
  if (asked == nullptr || *asked == '\0') return best_cpu_isa();
  std::string names;
  for (Isa isa : kAllIsas) {
    if (isa_name(isa) == asked) {
      if (!cpu_runs(isa))
        throw std::runtime_error(std::string(kIsaVariable) + "=" + asked +
                                 ": this CPU runs at most " +
                                 std::string(isa_name(best_cpu_isa())));
      return isa;
    }
    names += (names.empty() ? "" : ", ") + std::string(isa_name(isa));
  }
  throw std::runtime_error(std::string(kIsaVariable) + "=" + asked +
                           ": not an instruction set (one of " + names + ")");
}

}  // namespace rayscope
