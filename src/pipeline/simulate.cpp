#include "cubecal/pipeline/simulate.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "cubecal/error.hpp"
#include "cubecal/sim/composite_noise.hpp"

namespace cubecal::pipeline {

namespace {

constexpr std::size_t kBlock = 65536;

// Independent streams per triad from one user seed (splitmix64 finalizer):
// adding a triad never changes the numbers of the others.
std::uint64_t triad_seed(std::uint64_t seed, std::size_t k) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (k + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

bool is_rate(const TriadModel& m) {
  const auto u = parse_unit(m.unit);
  return u && u->kind == SensorKind::rate;
}

struct Generator {
  const SimulateRequest& r;
  std::vector<TriadSimulator> sims;
  std::size_t rate_triad = static_cast<std::size_t>(-1);
  std::size_t profile_pos = 0;
  std::vector<double> in, temp, out;

  explicit Generator(const SimulateRequest& req) : r(req) {
    const double dt = 1.0 / r.rate_hz;
    for (std::size_t k = 0; k < r.triads.size(); ++k) {
      sims.emplace_back(r.triads[k], dt, triad_seed(r.seed, k), sample_count(r));
      if (rate_triad == static_cast<std::size_t>(-1) && is_rate(r.triads[k])) rate_triad = k;
    }
  }

  // Fills temp/out for samples [k0, k0+len): out is row-major len x 3 per triad.
  void block(std::size_t k0, std::size_t len) {
    const double dt = 1.0 / r.rate_hz;
    temp.resize(len);
    for (std::size_t j = 0; j < len; ++j) temp[j] = r.temperature.at(k0 + j, dt);
    out.resize(sims.size() * len * 3);
    for (std::size_t k = 0; k < sims.size(); ++k) {
      std::span<const double> input;
      if (k == rate_triad && !r.true_input.empty()) {
        in.resize(len * 3);
        for (std::size_t j = 0; j < len; ++j) {
          const double t = static_cast<double>(k0 + j) * dt;
          while (profile_pos + 1 < r.true_input.t.size() && r.true_input.t[profile_pos + 1] <= t) ++profile_pos;
          const bool before = t < r.true_input.t.front();
          for (int a = 0; a < 3; ++a) in[j * 3 + a] = before ? 0.0 : r.true_input.w[a][profile_pos];
        }
        input = in;
      }
      sims[k].run(len, input, temp, std::span<double>(out.data() + k * len * 3, len * 3));
    }
  }
};

std::size_t axes_of(const TriadModel& m) {
  std::size_t n = 0;
  for (const auto& a : m.axis_names) n += a.empty() ? 0 : 1;
  return n;
}

}  // namespace

std::size_t sample_count(const SimulateRequest& r) {
  const double n = r.duration_s * r.rate_hz;
  // 1e15 samples (30 000 years at 1 kHz) is past any disk and far below
  // where the count would overflow.
  if (!(n >= 0.0) || !(n <= kMaxSimulatedSamples)) {
    char count[32];
    std::snprintf(count, sizeof count, "%.3g", n);
    throw UsageError(Field::duration, std::string("duration x rate = ") + count +
                                          " samples: more than any record can hold (at most 1e15); shorten it");
  }
  return static_cast<std::size_t>(std::llround(n));
}

std::vector<std::string> channel_names(const SimulateRequest& r) {
  std::vector<std::string> names;
  for (const auto& m : r.triads)
    for (const auto& a : m.axis_names)
      if (!a.empty()) names.push_back(a);
  if (r.temperature_column) names.push_back("temp");
  return names;
}

SimulatedRecord simulate(const SimulateRequest& r) {
  SimulatedRecord rec;
  rec.rate_hz = r.rate_hz;
  rec.names = channel_names(r);
  const std::size_t n = sample_count(r);
  rec.channels.assign(rec.names.size(), std::vector<double>(n));
  Generator g(r);
  for (std::size_t k0 = 0; k0 < n; k0 += kBlock) {
    const std::size_t len = std::min(kBlock, n - k0);
    g.block(k0, len);
    std::size_t c = 0;
    for (std::size_t k = 0; k < g.sims.size(); ++k)
      for (std::size_t a = 0; a < axes_of(r.triads[k]); ++a, ++c)
        for (std::size_t j = 0; j < len; ++j) rec.channels[c][k0 + j] = g.out[k * len * 3 + j * 3 + a];
    if (r.temperature_column)
      std::copy(g.temp.begin(), g.temp.begin() + static_cast<std::ptrdiff_t>(len),
                rec.channels[c].begin() + static_cast<std::ptrdiff_t>(k0));
  }
  return rec;
}

void write_simulation(const SimulateRequest& r, io::CsvWriter& out) {
  std::vector<std::string> header{"t"};
  for (auto& n : channel_names(r)) header.push_back(n);
  out.header(header);
  const std::size_t n = sample_count(r);
  const double dt = 1.0 / r.rate_hz;
  Generator g(r);
  std::vector<double> row(header.size());
  for (std::size_t k0 = 0; k0 < n; k0 += kBlock) {
    const std::size_t len = std::min(kBlock, n - k0);
    g.block(k0, len);
    for (std::size_t j = 0; j < len; ++j) {
      std::size_t c = 0;
      row[c++] = static_cast<double>(k0 + j) * dt;
      for (std::size_t k = 0; k < g.sims.size(); ++k)
        for (std::size_t a = 0; a < axes_of(r.triads[k]); ++a) row[c++] = g.out[k * len * 3 + j * 3 + a];
      if (r.temperature_column) row[c++] = g.temp[j];
      out.row(row);
    }
    if (r.progress) r.progress(static_cast<double>(k0 + len) / static_cast<double>(n));
  }
}

void simulate_blocks(const SimulateRequest& r,
                     const std::function<void(std::size_t k0, std::span<const double> frames)>& sink) {
  const std::size_t n = sample_count(r);
  const std::size_t channels = channel_names(r).size();
  Generator g(r);
  std::vector<double> frames(kBlock * channels);
  for (std::size_t k0 = 0; k0 < n; k0 += kBlock) {
    const std::size_t len = std::min(kBlock, n - k0);
    g.block(k0, len);
    for (std::size_t j = 0; j < len; ++j) {
      std::size_t c = 0;
      double* row = frames.data() + j * channels;
      for (std::size_t k = 0; k < g.sims.size(); ++k)
        for (std::size_t a = 0; a < axes_of(r.triads[k]); ++a) row[c++] = g.out[k * len * 3 + j * 3 + a];
      if (r.temperature_column) row[c++] = g.temp[j];
    }
    sink(k0, std::span<const double>(frames.data(), len * channels));
    if (r.progress) r.progress(static_cast<double>(k0 + len) / static_cast<double>(n));
  }
}

void write_record(const SimulatedRecord& rec, io::CsvWriter& out) {
  std::vector<std::string> header{"t"};
  for (const auto& n : rec.names) header.push_back(n);
  out.header(header);
  const std::size_t n = rec.channels.empty() ? 0 : rec.channels[0].size();
  const double dt = 1.0 / rec.rate_hz;
  std::vector<double> row(header.size());
  for (std::size_t k = 0; k < n; ++k) {
    row[0] = static_cast<double>(k) * dt;
    for (std::size_t c = 0; c < rec.channels.size(); ++c) row[c + 1] = rec.channels[c][k];
    out.row(row);
  }
}

std::vector<TriadModel> models_from_analysis(const AnalysisResult& r, const std::string& label, bool gm) {
  if (r.channels.empty()) throw UsageError(label + ": not an analysis.json written by cubecal analyze");
  std::vector<TriadModel> out;
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    const ChannelAnalysis& ch = r.channels[c];
    if (c % 3 == 0) {
      out.emplace_back();
      out.back().name = label;
      out.back().axis_names = {"", "", ""};
      out.back().unit = ch.unit.name;
    }
    TriadModel& m = out.back();
    const std::size_t a = c % 3;
    // (std::string{"c"} += ...: GCC 12 warns falsely on "c" + std::to_string at -O3.)
    m.axis_names[a] = !ch.name.empty() ? ch.name : (std::string{"c"} += std::to_string(c + 1));
    AxisModel& ax = m.axes[a];
    ax.fixed_bias = ch.mean;
    // With a temperature analysis the twin simulates the temperature term
    // itself: its noise is the model fitted to the compensated series (the
    // record's own carries the temperature swing in sigma_mu), where there is one.
    const ModelAnalysis& model =
        ch.temperature && (gm ? ch.temperature->compensated_model.gm_ok : ch.temperature->compensated_model.ok)
            ? ch.temperature->compensated_model
            : ch.model;
    if (gm) {
      if (!model.gm_ok)
        throw UsageError(Field::bias, label + ": channel " + m.axis_names[a] +
                                          " has no Gauss-Markov model (use the random-walk model, or re-run analyze)");
      ax.white_sigma = model.gauss_markov.sigma_n;
      ax.bias = BiasProcess::gauss_markov;
      ax.bias_sigma = model.gauss_markov.sigma_b;
      ax.tau_c = model.gauss_markov.tau_c;
    } else {
      if (!model.ok)
        throw UsageError(Field::bias,
                         label + ": channel " + m.axis_names[a] + " has no fitted random-walk model (" +
                             (model.error.empty() ? std::string("no minimum in its Allan curve") : model.error) +
                             "; the Gauss-Markov model may have one)");
      ax.white_sigma = model.random_walk.sigma_n;
      ax.bias = BiasProcess::random_walk;
      ax.bias_sigma = model.random_walk.sigma_mu;
      m.lsb = model.random_walk.lsb;
    }
    if (ch.temperature) {
      const TemperatureFit& t = ch.temperature->fit;
      if (t.coeff.size() > 1) ax.temp_coeff = t.coeff[1];
      m.temp_ref = t.t_ref;
      if (!t.coeff.empty()) ax.fixed_bias = t.coeff[0];
    }
  }
  return out;
}

TriadModel model_at_rate(const TriadModel& model, double from_hz, double to_hz) {
  if (!(from_hz > 0.0) || !std::isfinite(from_hz) || !(to_hz > 0.0) || !std::isfinite(to_hz))
    throw std::invalid_argument("model_at_rate: rates must be positive and finite");
  // docs/formulas/simulator.md §2.1, noise-terms.md §4: N = sigma_n sqrt(dt) and
  // K = sigma_mu sqrt(dt) are the sensor's; the per-sample sigmas scale as
  // 1/sqrt(dt), i.e. by sqrt(dt_from / dt_to) = sqrt(to_hz / from_hz). The
  // Gauss-Markov sigma_b (stationary, u) and T_c (s) do not depend on dt.
  const double s = std::sqrt(to_hz / from_hz);
  TriadModel m = model;
  for (auto& a : m.axes) {
    a.white_sigma *= s;
    if (a.bias == BiasProcess::random_walk) a.bias_sigma *= s;
    a.composite = composite_at_period(a.composite, 1.0 / from_hz, 1.0 / to_hz);
  }
  return m;
}

namespace {

// One channel of a composite simulation: its name, unit, fixed bias and
// model (per sample at the fit's rate).
struct CompositeChannel {
  std::string name;
  std::string unit;
  double fixed_bias = 0.0;
  CompositeModel model;
  double lsb = 0.0;         // the triad's quantizer (counts per unit), from its first channel
  double temp_coeff = 0.0;  // u per degC
  double temp_ref = 25.0;   // degC
};

std::vector<TriadModel> composite_triads(const std::vector<CompositeChannel>& channels, const std::string& label,
                                         double from_hz, double to_hz) {
  if (!(to_hz > 0.0) || !std::isfinite(to_hz)) throw UsageError(Field::rate, "the sampling rate must be positive");
  if (!(from_hz > 0.0) || !std::isfinite(from_hz))
    throw UsageError(label + ": the composite models have no sampling rate (fit them again)");
  std::vector<TriadModel> out;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    if (c % 3 == 0) {
      out.emplace_back();
      out.back().name = label;
      out.back().axis_names = {"", "", ""};
      out.back().unit = channels[c].unit;
    }
    TriadModel& m = out.back();
    m.axis_names[c % 3] = !channels[c].name.empty() ? channels[c].name : (std::string{"c"} += std::to_string(c + 1));
    AxisModel& ax = m.axes[c % 3];
    ax.fixed_bias = channels[c].fixed_bias;
    ax.composite = channels[c].model;
    ax.temp_coeff = channels[c].temp_coeff;
    if (c % 3 == 0) {
      m.lsb = channels[c].lsb;
      m.temp_ref = channels[c].temp_ref;
    }
  }
  for (auto& m : out) m = model_at_rate(m, from_hz, to_hz);
  return out;
}

}  // namespace

std::vector<TriadModel> models_from_composite(const AnalysisResult& r, const std::string& label, double rate_hz) {
  if (r.channels.empty()) throw UsageError(label + ": not an analysis.json written by cubecal analyze");
  std::vector<CompositeChannel> channels;
  for (const ChannelAnalysis& ch : r.channels) {
    if (!ch.model.composite)
      throw UsageError(Field::bias,
                       label + ": channel " + ch.name + " has no twin (composite model)" +
                           (r.composite_skipped.empty() ? std::string() : " (" + r.composite_skipped + ")") +
                           ": re-run analyze, or simulate the random-walk or Gauss-Markov model");
    CompositeChannel cc{ch.name, ch.unit.name, ch.mean, ch.model.composite->fit.model};
    cc.lsb = ch.model.random_walk.lsb;
    // With a temperature analysis the twin of the compensated series and the
    // coefficients, so that the temperature's share is simulated once; a
    // channel whose compensated series has no twin keeps the record's twin,
    // which carries the temperature's effect as noise, and no temperature term.
    if (ch.temperature && ch.temperature->compensated_model.composite) {
      const TemperatureFit& t = ch.temperature->fit;
      cc.model = ch.temperature->compensated_model.composite->fit.model;
      if (!t.coeff.empty()) cc.fixed_bias = t.coeff[0];
      if (t.coeff.size() > 1) cc.temp_coeff = t.coeff[1];
      cc.temp_ref = t.t_ref;
    }
    channels.push_back(std::move(cc));
  }
  return composite_triads(channels, label, r.rate_hz, rate_hz);
}

std::vector<TriadModel> models_from_composite(const ModelResult& r, const std::string& label, double rate_hz) {
  if (r.channels.empty()) throw UsageError(label + ": a model result without channels");
  std::vector<CompositeChannel> channels;
  for (const ModelChannel& ch : r.channels) channels.push_back({ch.name, ch.unit.name, 0.0, ch.fit.model});
  return composite_triads(channels, label, r.rate_hz, rate_hz);
}

std::vector<TriadModel> models_from_analysis(const AnalysisResult& r, const std::string& label, bool gm,
                                             double rate_hz) {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) throw UsageError(Field::rate, "the sampling rate must be positive");
  std::vector<TriadModel> out = models_from_analysis(r, label, gm);
  if (!(r.rate_hz > 0.0) || !std::isfinite(r.rate_hz))
    throw UsageError(label + ": the analysis has no sampling rate (re-run analyze)");
  for (auto& m : out) m = model_at_rate(m, r.rate_hz, rate_hz);
  return out;
}

double parse_duration(const std::string& s) {
  if (s.empty()) throw UsageError("empty duration (use e.g. 72h, 30m, 3600s or 2d)");
  double mult = 1.0;
  std::string num = s;
  switch (s.back()) {
    case 's':
      mult = 1.0;
      num.pop_back();
      break;
    case 'm':
      mult = 60.0;
      num.pop_back();
      break;
    case 'h':
      mult = 3600.0;
      num.pop_back();
      break;
    case 'd':
      mult = 86400.0;
      num.pop_back();
      break;
    default: break;
  }
  double v = 0.0;
  const auto [p, ec] = std::from_chars(num.data(), num.data() + num.size(), v);
  if (ec != std::errc() || p != num.data() + num.size() || !(v > 0.0) || !std::isfinite(v))
    throw UsageError("bad duration '" + s + "' (use e.g. 72h, 30m, 3600s or 2d)");
  return v * mult;
}

}  // namespace cubecal::pipeline
