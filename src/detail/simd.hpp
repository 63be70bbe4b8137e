// Internal: build hot loops twice on x86-64 (AVX2 and baseline) and pick the
// one the CPU supports at load time, so the library stays portable (flight
// computers, other architectures) and still uses the wide units here.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(CUBECAL_NO_CLONES)
#define CUBECAL_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define CUBECAL_VECTOR_CLONES
#endif
