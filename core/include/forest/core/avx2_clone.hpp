#pragma once
// FOREST_AVX2_CLONE before a function with a loop the compiler vectorises: where the compiler can
// (GCC or Clang on x86-64), it builds a copy for AVX2 beside the baseline x86-64 one (SSE2), and
// the loader picks the one the CPU runs (an ifunc). Twice the lanes of the baseline build's
// vectors without giving up machines without AVX2. Not under AddressSanitizer, whose runtime is
// not up yet when the loader resolves the choice.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
#define FOREST_AVX2_CLONE __attribute__((target_clones("avx2", "default")))
#else
#define FOREST_AVX2_CLONE
#endif
