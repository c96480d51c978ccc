// The instruction set this translation unit is compiled for, as a name:
// code whose layout or inline functions depend on it lives in
// `inline namespace RAYSCOPE_ISA { ... }`, so that translation units compiled
// for different instruction sets (the tests build some walks for several)
// never share an inline function or a type that differs between them.
#pragma once

#if defined(__AVX512F__)
#define RAYSCOPE_ISA avx512
#elif defined(__AVX__)
#define RAYSCOPE_ISA avx
#elif defined(__SSE2__)
#define RAYSCOPE_ISA sse
#else
#define RAYSCOPE_ISA scalar
#endif
