// Internal: build hot loops twice on x86-64 (AVX2 and baseline) and pick the
// one the CPU supports at load time, so the library stays portable (flight
// computers, other architectures) and still uses the wide units here. The
// clones give the same bits: each loop's lanes are written out in the source
// (eight accumulators are two AVX2 registers or four SSE2 ones, added in the
// same order), and no multiply and add is fused (-ffp-contract=off,
// CMakeLists.txt). An AVX-512 clone gave the same bits and measured no
// faster (docs/performance.md), so there is none.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(CUBECAL_NO_CLONES)
#define CUBECAL_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define CUBECAL_VECTOR_CLONES
#endif
