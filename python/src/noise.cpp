// cubecal._cubecal's noise generators for cubecal.noise and cubecal.Noise
// (AllanTools' noise.py and noise_kasdin.py): Kasdin & Walter's power-law
// filter of white noise (sim/power_law_generator.hpp) as one record or as an
// endless stream, and the periodogram and Welch spectra of an array
// (pipeline/welch_psd.hpp).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "arrays.hpp"
#include "cubecal/pipeline/welch_psd.hpp"
#include "cubecal/sim/power_law_generator.hpp"
#include "cubecal/spectral/allan_conversion.hpp"
#include "cubecal/spectral/welch_options.hpp"
#include "cubecal/spectral/window.hpp"
#include "errors.hpp"
#include "module.hpp"

namespace cubecal::python {

namespace {

// The record lengths a generator takes: a filter as long as the record is
// made, two transforms of twice its length held at once (some 100 bytes a
// sample), so 2^31 samples is beyond any machine this runs on.
constexpr std::size_t kMaxSamples = std::size_t{1} << 31;

void check_term(double alpha, double h, double dt) {
  if (!std::isfinite(alpha)) throw ArgumentError("alpha", "alpha: the power-law exponent must be a finite number");
  if (!std::isfinite(h) || h < 0.0) throw ArgumentError("h", "h: the level must be a finite number >= 0");
  if (!std::isfinite(dt) || !(dt > 0.0)) throw ArgumentError("dt", "dt: the sampling interval must be positive (s)");
}

// n samples of one-sided PSD h f^alpha (for f << 1/dt) sampled every dt,
// after the first `skip` (which are drawn and dropped), by Kasdin & Walter's
// exact generator: the filter is as long as the whole draw.
py::array_t<double> power_law(double alpha, double h, double dt, std::size_t n, std::uint64_t seed, std::size_t skip) {
  check_term(alpha, h, dt);
  if (n > kMaxSamples || skip > kMaxSamples)
    throw ArgumentError("n", "n: at most 2^31 samples can be generated at once");
  std::vector<double> out(n + skip, 0.0);
  if (!out.empty()) {
    py::gil_scoped_release release;
    PowerLawGenerator gen({alpha, h}, dt, std::bit_ceil(out.size()), seed);
    gen.next(out);
  }
  out.erase(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(skip));
  return to_array(std::move(out));
}

// The same process without end, a block of filter_length samples at a time
// (the law holds down to f ~ 1 / (filter_length dt)).
class PowerLawStream {
 public:
  PowerLawStream(double alpha, double h, double dt, std::size_t filter_length, std::uint64_t seed)
      : gen_(make(alpha, h, dt, filter_length, seed)) {}

  py::array_t<double> next(std::size_t n) {
    if (n > kMaxSamples) throw ArgumentError("n", "n: at most 2^31 samples can be drawn at once");
    std::vector<double> out(n, 0.0);
    {
      py::gil_scoped_release release;
      gen_.next(out);
    }
    return to_array(std::move(out));
  }

 private:
  static PowerLawGenerator make(double alpha, double h, double dt, std::size_t filter_length, std::uint64_t seed) {
    check_term(alpha, h, dt);
    if (filter_length == 0 || !std::has_single_bit(filter_length) || filter_length > PowerLawGenerator::kMaxFilter)
      throw ArgumentError("filter_length", "filter_length: a power of two from 1 to 2^18 is expected");
    return PowerLawGenerator({alpha, h}, dt, filter_length, seed);
  }

  PowerLawGenerator gen_;
};

// The one-sided spectrum of x by Welch's method as scipy.signal.welch(x,
// rate, window, nperseg=segment, noverlap=floor(overlap*segment), detrend)
// gives it: (frequencies in Hz, densities in unit^2/Hz).
py::tuple welch(const Doubles& x, double rate, std::size_t segment, double overlap, const std::string& window,
                const std::string& detrend) {
  const auto data = view(x, "x");
  WelchOptions options;
  const auto w = parse_window(window);
  const auto d = parse_detrend(detrend);
  if (!w) throw ArgumentError("window", "window: one of " + known_windows() + " is expected, not " + window);
  if (!d) throw ArgumentError("detrend", "detrend: none, constant or linear is expected, not " + detrend);
  options.window = *w;
  options.detrend = *d;
  options.segment_length = segment;
  options.overlap = overlap;
  Psd psd;
  {
    py::gil_scoped_release release;
    psd = pipeline::welch_psd(data, rate, options);
  }
  return py::make_tuple(to_array(std::move(psd.frequency)), to_array(std::move(psd.density)));
}

// The Allan variance of one-sided h f^alpha (NIST SP 1065 Table 2):
// alpha 2 (white PM up to f_h), 0, -1, -2.
double avar_of_power_law(int alpha, double h, double tau, double f_h) {
  if (alpha != 2 && alpha != 0 && alpha != -1 && alpha != -2)
    throw ArgumentError("alpha", "alpha: the closed form is known for 2, 0, -1 and -2, not " + std::to_string(alpha));
  if (!std::isfinite(h)) throw ArgumentError("h", "h: the level must be a finite number");
  if (!(tau > 0.0) || !std::isfinite(tau)) throw ArgumentError("tau", "tau: a positive averaging time is expected (s)");
  if (alpha == 2 && (!(f_h > 0.0) || !std::isfinite(f_h)))
    throw ArgumentError("f_h", "f_h: white PM needs a positive high cutoff (Hz)");
  return power_law_avar(alpha, h, tau, f_h);
}

}  // namespace

void bind_noise(py::module_& m) {
  m.def("_power_law", &power_law, py::arg("alpha"), py::arg("h"), py::arg("dt"), py::arg("n"), py::arg("seed"),
        py::arg("skip") = 0,
        "n samples of one-sided PSD h f^alpha sampled every dt (s), Kasdin & Walter's exact generator, after "
        "`skip` samples drawn and dropped.");
  py::class_<PowerLawStream>(m, "_PowerLawStream")
      .def(py::init<double, double, double, std::size_t, std::uint64_t>(), py::arg("alpha"), py::arg("h"),
           py::arg("dt"), py::arg("filter_length"), py::arg("seed"))
      .def("next", &PowerLawStream::next, py::arg("n"), "The next n samples of the process.");
  m.def("_power_law_avar", &avar_of_power_law, py::arg("alpha"), py::arg("h"), py::arg("tau"), py::arg("f_h") = 0.0,
        "AVAR of one-sided h f^alpha at tau (s), continuous time (alpha 2, 0, -1, -2; f_h in Hz for 2).");
  m.def("_welch", &welch, py::arg("x"), py::arg("rate"), py::arg("segment"), py::arg("overlap"), py::arg("window"),
        py::arg("detrend"), "(frequencies (Hz), one-sided densities (unit^2/Hz)) of x by Welch's method.");
}

}  // namespace cubecal::python
