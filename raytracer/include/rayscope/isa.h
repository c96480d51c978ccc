// Instruction sets: the one this translation unit is compiled for, and the one
// the hot loops (kernels.h) run with, chosen at run time from the CPU.
//
// RAYSCOPE_ISA names the compile-time one: code whose layout or inline
// functions depend on it lives in `inline namespace RAYSCOPE_ISA { ... }`, so
// that translation units compiled for different instruction sets (kernels.cpp
// is compiled once per Isa; the tests build some walks for several) never
// share an inline function or a type that differs between them.
#pragma once

#include <string>
#include <string_view>

#if defined(__AVX512F__)
#define RAYSCOPE_ISA avx512
#elif defined(__AVX2__)
#define RAYSCOPE_ISA avx2
#elif defined(__AVX__)
#define RAYSCOPE_ISA avx
#elif defined(__SSE4_2__)
#define RAYSCOPE_ISA sse42
#elif defined(__SSE2__)
#define RAYSCOPE_ISA sse2
#else
#define RAYSCOPE_ISA scalar
#endif

namespace rayscope {

/// The instruction sets the hot loops are compiled for, lowest first. Each is
/// an x86-64 micro-architecture level: SSE2 (every x86-64), SSE4.2
/// (x86-64-v2), AVX2 with FMA and BMI (x86-64-v3), AVX-512 F/BW/CD/DQ/VL
/// (x86-64-v4). On other processors only the build's own (kCompiledIsa).
enum class Isa { Sse2, Sse42, Avx2, Avx512 };
inline constexpr Isa kAllIsas[] = {Isa::Sse2, Isa::Sse42, Isa::Avx2, Isa::Avx512};

/// The level this translation unit is compiled for (the highest whose every
/// feature the compiler may use; plain AVX counts as SSE4.2).
inline constexpr Isa kCompiledIsa =
#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512CD__) && \
    defined(__AVX512DQ__) && defined(__AVX512VL__)
    Isa::Avx512;
#elif defined(__AVX2__) && defined(__FMA__) && defined(__BMI2__)
    Isa::Avx2;
#elif defined(__SSE4_2__) && defined(__POPCNT__)
    Isa::Sse42;
#else
    Isa::Sse2;
#endif

/// The name users write (RAYSCOPE_ISA=...) and the statistics print:
/// "sse2", "sse4.2", "avx2", "avx512".
std::string_view isa_name(Isa isa);

/// Whether this CPU (and its operating system, which must save the wider
/// registers) runs code compiled for `isa`.
bool cpu_runs(Isa isa);

/// The highest level this CPU runs.
Isa best_cpu_isa();

/// The environment variable that lowers the hot loops' instruction set (for
/// tests, and to compare paths on one machine).
inline constexpr const char* kIsaVariable = "RAYSCOPE_ISA";

/// The level the hot loops run with: $RAYSCOPE_ISA when set, else the
/// highest the CPU runs. Throws std::runtime_error naming the variable for
/// a name that is not one of isa_name()'s, or a level this CPU cannot run.
Isa chosen_isa();

}  // namespace rayscope
