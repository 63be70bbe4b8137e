// Internal: advice that a long array be backed by 2 MiB pages. A record's
// column or phase array is tens of MB; where the kernel leaves huge pages to
// the program (transparent_hugepage=madvise, Debian's default) it is faulted
// in 512 times less often. Advice only: nothing changes where it is refused
// or on systems without it. Call it on storage not yet touched (reserved).
#pragma once

#include <cstddef>
#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace cubecal::detail {

inline void advise_huge_pages(const void* p, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  const auto b = (reinterpret_cast<std::uintptr_t>(p) + kHuge - 1) / kHuge * kHuge;
  const auto e = (reinterpret_cast<std::uintptr_t>(p) + bytes) / kHuge * kHuge;
  if (e > b) ::madvise(reinterpret_cast<void*>(b), e - b, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

}  // namespace cubecal::detail
