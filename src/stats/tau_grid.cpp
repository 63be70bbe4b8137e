#include "cubecal/stats/tau_grid.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cubecal {

namespace {

double parse_positive(std::string_view s, std::string_view what) {
  double v = 0.0;
  const auto* b = s.data();
  const auto* e = s.data() + s.size();
  auto [p, ec] = std::from_chars(b, e, v);
  if (ec != std::errc() || p != e || !std::isfinite(v) || v <= 0.0)
    throw std::invalid_argument("bad " + std::string(what) + " '" + std::string(s) +
                                "' in tau grid (expected a positive number)");
  return v;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

TauGrid parse_tau_grid(std::string_view spec) {
  spec = trim(spec);
  TauGrid g;
  if (spec == "octave") {
    g.kind = TauGrid::Kind::octave;
    return g;
  }
  if (spec == "decade") {
    g.kind = TauGrid::Kind::decade;
    return g;
  }
  if (spec == "all") {
    g.kind = TauGrid::Kind::all;
    return g;
  }
  if (spec.starts_with("log:")) {
    const double k = parse_positive(spec.substr(4), "points per decade");
    if (k != std::floor(k) || k > 1000) throw std::invalid_argument("log:K needs an integer K between 1 and 1000");
    g.kind = TauGrid::Kind::log;
    g.per_decade = static_cast<unsigned>(k);
    return g;
  }
  if (spec.empty()) throw std::invalid_argument("empty tau grid (use octave, decade, all, log:K or a list of taus)");
  g.kind = TauGrid::Kind::list;
  while (!spec.empty()) {
    const auto comma = spec.find(',');
    const auto item = trim(spec.substr(0, comma));
    g.taus.push_back(parse_positive(item, "tau"));
    if (comma == std::string_view::npos) break;
    spec.remove_prefix(comma + 1);
  }
  return g;
}

double listed_factor(double tau, double tau0) noexcept { return std::max(1.0, std::round(tau / tau0)); }

std::vector<std::size_t> averaging_factors(const TauGrid& grid, std::size_t max_m, double tau0) {
  std::vector<std::size_t> ms;
  if (max_m == 0) return ms;
  switch (grid.kind) {
    case TauGrid::Kind::octave:
      for (std::size_t m = 1; m <= max_m; m *= 2) ms.push_back(m);
      break;
    case TauGrid::Kind::decade:
      for (std::size_t d = 1; d <= max_m; d *= 10)
        for (std::size_t f : {1u, 2u, 4u})
          if (d * f <= max_m) ms.push_back(d * f);
      break;
    case TauGrid::Kind::all:
      ms.reserve(max_m);
      for (std::size_t m = 1; m <= max_m; ++m) ms.push_back(m);
      break;
    case TauGrid::Kind::log: {
      const double k = grid.per_decade;
      for (unsigned j = 0;; ++j) {
        const double v = std::round(std::pow(10.0, j / k));
        if (v > static_cast<double>(max_m)) break;
        ms.push_back(static_cast<std::size_t>(v));
      }
      break;
    }
    case TauGrid::Kind::list:
      for (double tau : grid.taus) {
        const double v = listed_factor(tau, tau0);
        if (v <= static_cast<double>(max_m)) ms.push_back(static_cast<std::size_t>(v));
      }
      break;
  }
  std::sort(ms.begin(), ms.end());
  ms.erase(std::unique(ms.begin(), ms.end()), ms.end());
  return ms;
}

}  // namespace cubecal
