// What this machine can do at best on a record, for the stage table of
// `make bench` (bench/run.sh): each cubecal stage is set beside the plain
// work it cannot avoid, measured here in the same run.
//
//   bench_limits RECORD.csv RUNS [GRID]
//
//   read      the file from the page cache: pread in 1 MiB pieces, every
//             byte touched, all cores
//   doubles   one pass over the parsed columns in memory, all cores
//   parse     fast_float over every field of the file (its bytes already in
//             memory), each value stored in its column, all cores
//   oadev     the minimum OADEV work: per column, the phase by a running
//             sum and one plain pass per averaging factor of GRID (default
//             log:20) over it, columns on all cores; compiled for this
//             machine's widest vectors (-march=native, FMA)
//
// Prints per limit "limit NAME min median max" in seconds of wall clock
// over RUNS runs, plus "info" lines (sizes, threads, the terms of the OADEV
// work). The columns are every field after the first (the time).
#include <fast_float/fast_float.h>
#include <fcntl.h>
#include <omp.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cubecal/stats/statistic.hpp"
#include "cubecal/stats/tau_grid.hpp"

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

struct Spread {
  double min, median, max;
};

template <class Work>
Spread timed(int runs, Work work) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const double s = now();
    work();
    t.push_back(now() - s);
  }
  std::sort(t.begin(), t.end());
  return {t.front(), t[t.size() / 2], t.back()};
}

volatile std::uint64_t g_sink_bits = 0;
volatile double g_sink = 0.0;

// Chunk starts at line boundaries: chunk k covers [cut[k], cut[k+1]).
std::vector<std::size_t> line_cuts(const std::string& text, std::size_t body, std::size_t parts) {
  std::vector<std::size_t> cut{body};
  for (std::size_t k = 1; k < parts; ++k) {
    std::size_t at = body + (text.size() - body) * k / parts;
    at = text.find('\n', at);
    cut.push_back(at == std::string::npos ? text.size() : at + 1);
  }
  cut.push_back(text.size());
  return cut;
}

// Fields of a chunk: every value into columns[field][row0 + row].
std::size_t parse_chunk(const char* p, const char* e, std::vector<std::vector<double>>& cols, std::size_t row0) {
  std::size_t row = row0;
  const std::size_t fields = cols.size();
  while (p < e) {
    for (std::size_t f = 0; f < fields; ++f) {
      double v = 0.0;
      const auto r = fast_float::from_chars(p, e, v);
      p = r.ptr + 1;  // past ',' or '\n'
      cols[f][row] = v;
    }
    ++row;
  }
  return row - row0;
}

double oadev_pass(const double* x, std::size_t count, std::size_t m) {
  double s = 0.0;
#pragma omp simd reduction(+ : s)
  for (std::size_t i = 0; i < count; ++i) {
    const double d = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
    s += d * d;
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_limits RECORD.csv RUNS [GRID]\n");
    return 2;
  }
  const std::string path = argv[1];
  const int runs = std::max(1, std::atoi(argv[2]));
  const std::string grid = argc > 3 ? argv[3] : "log:20";
  const int threads = omp_get_max_threads();

  const int fd = ::open(path.c_str(), O_RDONLY);
  struct stat st {};
  if (fd < 0 || ::fstat(fd, &st) != 0) {
    std::perror(path.c_str());
    return 2;
  }
  const auto size = static_cast<std::size_t>(st.st_size);

  // (a) the file from the page cache.
  const Spread read = timed(runs, [&] {
    std::uint64_t bits = 0;
#pragma omp parallel reduction(^ : bits)
    {
      constexpr std::size_t kPiece = std::size_t{1} << 20;
      std::vector<std::uint64_t> buf(kPiece / 8);
      const auto t = static_cast<std::size_t>(omp_get_thread_num());
      const auto n = static_cast<std::size_t>(omp_get_num_threads());
      const std::size_t from = size * t / n, to = size * (t + 1) / n;
      for (std::size_t at = from; at < to;) {
        const ssize_t got = ::pread(fd, buf.data(), std::min(kPiece, to - at), static_cast<off_t>(at));
        if (got <= 0) break;
        for (std::size_t w = 0; w < static_cast<std::size_t>(got) / 8; ++w) bits ^= buf[w];
        at += static_cast<std::size_t>(got);
      }
    }
    g_sink_bits = bits;
  });

  // The bytes in memory, the header skipped, the rows counted.
  std::string text(size, '\0');
  for (std::size_t at = 0; at < size;) {
    const ssize_t got = ::pread(fd, text.data() + at, size - at, static_cast<off_t>(at));
    if (got <= 0) {
      std::perror(path.c_str());
      return 2;
    }
    at += static_cast<std::size_t>(got);
  }
  ::close(fd);
  if (text.empty() || text.back() != '\n') text.push_back('\n');
  const std::size_t body = text.find('\n') + 1;
  const std::size_t fields =
      static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(body), ',')) + 1;
  const auto parts = static_cast<std::size_t>(threads);
  const std::vector<std::size_t> cut = line_cuts(text, body, parts);
  std::vector<std::size_t> first_row(parts + 1, 0);
  for (std::size_t k = 0; k < parts; ++k)
    first_row[k + 1] = first_row[k] + static_cast<std::size_t>(
                                          std::count(text.begin() + static_cast<std::ptrdiff_t>(cut[k]),
                                                     text.begin() + static_cast<std::ptrdiff_t>(cut[k + 1]), '\n'));
  const std::size_t rows = first_row[parts];
  std::vector<std::vector<double>> cols(fields, std::vector<double>(rows, 0.0));  // faulted in here, not timed

  // (b) the parse at best.
  const Spread parse = timed(runs, [&] {
#pragma omp parallel for schedule(static, 1)
    for (std::size_t k = 0; k < parts; ++k)
      parse_chunk(text.data() + cut[k], text.data() + cut[k + 1], cols, first_row[k]);
  });

  // (a') the parsed columns from memory.
  const Spread doubles = timed(runs, [&] {
    double total = 0.0;
#pragma omp parallel for reduction(+ : total) schedule(static, 1)
    for (std::size_t c = 1; c < fields; ++c) {
      double s = 0.0;
#pragma omp simd reduction(+ : s)
      for (std::size_t i = 0; i < rows; ++i) s += cols[c][i];
      total += s;
    }
    g_sink = total;
  });

  // (c) the minimum OADEV work.
  const double tau0 = rows > 1 ? (cols[0][rows - 1] - cols[0][0]) / static_cast<double>(rows - 1) : 1.0;
  const std::size_t n_phase = rows + 1;
  const std::vector<std::size_t> ms = cubecal::averaging_factors(
      cubecal::parse_tau_grid(grid), cubecal::max_averaging_factor(cubecal::Stat::oadev, n_phase), tau0);
  double terms = 0.0;
  for (const std::size_t m : ms) terms += static_cast<double>(n_phase - 2 * m);
  std::vector<std::vector<double>> phase(fields, std::vector<double>(n_phase, 0.0));
  const Spread oadev = timed(runs, [&] {
    double total = 0.0;
#pragma omp parallel for reduction(+ : total) schedule(dynamic, 1)
    for (std::size_t c = 1; c < fields; ++c) {
      double* x = phase[c].data();
      double acc = 0.0;
      for (std::size_t i = 0; i < rows; ++i) x[i + 1] = acc += cols[c][i] * tau0;
      for (const std::size_t m : ms) total += oadev_pass(x, n_phase - 2 * m, m);
    }
    g_sink = total;
  });

  std::printf("info threads %d\ninfo bytes %zu\ninfo rows %zu\ninfo columns %zu\ninfo taus %zu\ninfo terms %.6g\n",
              threads, size, rows, fields - 1, ms.size(), terms * static_cast<double>(fields - 1));
  for (const auto& [name, s] :
       {std::pair{"read", read}, std::pair{"doubles", doubles}, std::pair{"parse", parse}, std::pair{"oadev", oadev}})
    std::printf("limit %s %.4f %.4f %.4f\n", name, s.min, s.median, s.max);
  return 0;
}
