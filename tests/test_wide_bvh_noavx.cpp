// test_wide_bvh.cpp compiled without AVX (tests/CMakeLists.txt sets -mno-avx
// on this file): the BVH walk with the box test a CPU without AVX runs.
#if defined(__AVX__)
#error "test_wide_bvh_noavx must be compiled without AVX"
#endif
#include "test_wide_bvh.cpp"
