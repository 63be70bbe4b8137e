// Internal: build hot loops three times on x86-64 (AVX-512, AVX2 and
// baseline) and pick the one the CPU supports at load time, so the library
// stays portable (flight computers, other architectures) and still uses the
// wide units here. The clones give the same bits: each loop's lanes are
// written out in the source (eight accumulators are one AVX-512 register or
// two AVX2 ones, added in the same order), and no multiply and add is fused
// (-ffp-contract=off, CMakeLists.txt).
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(CUBECAL_NO_CLONES)
#define CUBECAL_VECTOR_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define CUBECAL_VECTOR_CLONES
#endif
