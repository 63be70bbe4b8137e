// The host's receive stamp of a batch of bytes: CLOCK_MONOTONIC (for
// intervals within one run of the recorder) and CLOCK_REALTIME (UTC, to
// place runs against each other), read together once per read() batch.
#pragma once
#include <cstddef>
#include <ctime>
#include <string>

namespace cubecal::acquire {

struct HostStamp {
  timespec mono{};
  timespec utc{};

  double mono_s() const noexcept { return static_cast<double>(mono.tv_sec) + 1e-9 * static_cast<double>(mono.tv_nsec); }
  double utc_s() const noexcept { return static_cast<double>(utc.tv_sec) + 1e-9 * static_cast<double>(utc.tv_nsec); }
};

HostStamp host_now() noexcept;

// "SECONDS.NNNNNNNNN" (nine decimals, exact) into `out` (at least 32 bytes);
// returns the characters written.
std::size_t format_seconds(const timespec& t, char* out) noexcept;

// "MONO,UTC," — the prefix of every chunk line received in the batch.
std::string stamp_prefix(const HostStamp& s);

}  // namespace cubecal::acquire
