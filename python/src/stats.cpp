// The statistics: cubecal._deviation, the kernel behind the AllanTools-shaped
// calls of cubecal/_allantools.py (the averaging factors chosen there, as
// AllanTools chooses them), and cubecal._dev, `cubecal dev` on arrays
// (Stable32's grids and limits, noise identification, EDF and intervals,
// channels and taus in parallel).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "arrays.hpp"
#include "common.hpp"
#include "json_value.hpp"
#include "cubecal/error.hpp"
#include "errors.hpp"
#include "cubecal/pipeline/analysis_json.hpp"
#include "cubecal/io/sample_checks.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/stats/gap_deviation.hpp"
#include "cubecal/stats/stability.hpp"
#include "module.hpp"

namespace py = pybind11;

namespace cubecal::python {

Stat stat_arg(const std::string& name) {
  if (const auto s = parse_stat(name)) return *s;
  std::string known;
  for (std::string_view n : stat_names()) known += (known.empty() ? "" : ", ") + std::string(n);
  throw UsageError(Field::stat, "unknown statistic '" + name + "' (" + known + ")");
}

DataType data_type_arg(const std::string& name) {
  if (const auto t = parse_data_type(name)) return *t;
  throw ArgumentError("data_type", "data_type must be \"phase\" or \"freq\", not '" + name + "'");
}

TauGrid taus_arg(const py::object& taus) {
  if (taus.is_none()) return {};
  if (py::isinstance<py::str>(taus)) {
    const auto spec = taus.cast<std::string>();
    try {
      return parse_tau_grid(spec);
    } catch (const std::invalid_argument& e) {
      throw UsageError(Field::taus, e.what());
    }
  }
  TauGrid g;
  g.kind = TauGrid::Kind::list;
  const Doubles list = Doubles::ensure(taus);
  if (!list || list.ndim() != 1 || list.size() == 0)
    throw UsageError(Field::taus,
                     "taus must be \"octave\", \"decade\", \"all\", \"log:K\" or a 1-D sequence of taus in seconds");
  g.taus.assign(list.data(), list.data() + list.size());
  for (const double t : g.taus)
    if (!(t > 0.0) || !std::isfinite(t))
      throw UsageError(Field::taus, "every tau must be a positive number of seconds");
  return g;
}

namespace {

// The readers' rule (io/sample_checks.hpp): a rate that makes every tau or
// deviation overflow or underflow is refused, as the CLI refuses it.
void check_rate(double rate) { io::check_rate(rate); }

// (m, dev, n) at the given averaging factors; n == 0 where the record is too
// short for m. No intervals: the AllanTools-shaped calls return dev/sqrt(n).
py::tuple deviation(const std::string& stat_name, const Doubles& data, double rate, const std::string& type_name,
                    const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& factors) {
  const Stat stat = stat_arg(stat_name);
  const DataType type = data_type_arg(type_name);
  check_rate(rate);
  const std::span<const double> x = view(data, "data");
  io::check_samples(x, "<arrays>", 1, "data");
  if (factors.ndim() != 1) throw std::invalid_argument("factors: a 1-D array is expected");
  std::vector<std::size_t> ms;
  ms.reserve(static_cast<std::size_t>(factors.size()));
  for (py::ssize_t i = 0; i < factors.size(); ++i) {
    const std::int64_t m = factors.data()[i];
    if (m < 1) throw UsageError(Field::taus, "every averaging factor must be at least 1");
    ms.push_back(static_cast<std::size_t>(m));
  }
  std::vector<StabilityPoint> pts;
  {
    py::gil_scoped_release free;
    const StabilityRecord record(x, type, 1.0 / rate, stat);
    StabilityOptions opt;
    opt.intervals = false;
    pts = record.evaluate(ms, opt);
  }
  std::vector<double> dev(pts.size());
  std::vector<std::int64_t> n(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    dev[i] = pts[i].dev;
    n[i] = static_cast<std::int64_t>(pts[i].n);
  }
  return py::make_tuple(to_array(std::move(dev)), to_array(std::move(n)));
}

// OADEV with missing samples (NaN) left out (stats/gap_deviation.hpp) at the
// given factors: (dev, n, lo, hi) with intervals at `ci` for a fixed noise
// type `alpha`, or the identified one when alpha is None.
py::tuple deviation_missing(const Doubles& data, double rate, const std::string& type_name,
                            const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& factors,
                            double ci, std::optional<int> alpha) {
  const DataType type = data_type_arg(type_name);
  check_rate(rate);
  if (!(ci > 0.0 && ci < 1.0)) throw UsageError(Field::ci, "ci must be between 0 and 1");
  const std::span<const double> x = view(data, "data");
  io::check_samples(x, "<arrays>", 1, "data", true);
  std::vector<std::size_t> ms;
  for (py::ssize_t i = 0; i < factors.size(); ++i) {
    if (factors.data()[i] < 1) throw UsageError(Field::taus, "every averaging factor must be at least 1");
    ms.push_back(static_cast<std::size_t>(factors.data()[i]));
  }
  StabilityOptions opt;
  opt.ci = ci;
  opt.alpha = alpha;
  std::vector<StabilityPoint> pts;
  {
    py::gil_scoped_release free;
    pts = oadev_skipping_missing(x, type, 1.0 / rate, ms, opt);
  }
  std::vector<double> dev(pts.size()), lo(pts.size()), hi(pts.size());
  std::vector<std::int64_t> n(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    dev[i] = pts[i].dev;
    lo[i] = pts[i].interval.lo;
    hi[i] = pts[i].interval.hi;
    n[i] = static_cast<std::int64_t>(pts[i].n);
  }
  return py::make_tuple(to_array(std::move(dev)), to_array(std::move(n)), to_array(std::move(lo)),
                        to_array(std::move(hi)));
}

py::dict curve(const pipeline::DevChannel& ch, bool intervals) {
  const std::size_t k = ch.points.size();
  std::vector<std::int64_t> m(k), n(k), alpha(k);
  std::vector<double> tau(k), dev(k), lo(k), hi(k), edf(k);
  std::vector<bool> carried(k);
  for (std::size_t i = 0; i < k; ++i) {
    const StabilityPoint& p = ch.points[i];
    m[i] = static_cast<std::int64_t>(p.m);
    n[i] = static_cast<std::int64_t>(p.n);
    tau[i] = p.tau;
    dev[i] = p.dev;
    lo[i] = p.interval.lo;
    hi[i] = p.interval.hi;
    edf[i] = p.edf;
    alpha[i] = p.alpha;
    carried[i] = p.type_carried;
  }
  py::dict c;
  c["name"] = ch.name;
  c["af"] = to_array(std::move(m));
  c["tau"] = to_array(std::move(tau));
  c["dev"] = to_array(std::move(dev));
  c["n"] = to_array(std::move(n));
  if (intervals) {
    c["lo"] = to_array(std::move(lo));
    c["hi"] = to_array(std::move(hi));
    c["edf"] = to_array(std::move(edf));
    c["alpha"] = to_array(std::move(alpha));
    py::array_t<bool> tc(static_cast<py::ssize_t>(k));
    for (std::size_t i = 0; i < k; ++i) tc.mutable_data()[i] = carried[i];
    c["type_carried"] = tc;
  }
  return c;
}

// `cubecal dev` on arrays of one length: the DevResult as the CLI's JSON
// (dev --format json) without its columns, and the columns as arrays.
py::tuple dev(const std::vector<Doubles>& channels, const std::vector<std::string>& names, double rate,
              const std::string& stat_name, const std::string& type_name, const py::object& taus, double ci,
              std::optional<int> alpha, const std::string& edf, bool conservative, bool intervals, unsigned threads,
              const std::string& gaps) {
  if (gaps != "error" && gaps != "skip") throw UsageError(Field::gaps, "gaps must be \"error\" or \"skip\" for arrays");
  pipeline::DevRequest req;
  req.stat = stat_arg(stat_name);
  req.type = data_type_arg(type_name);
  req.grid = taus_arg(taus);
  check_rate(rate);
  if (!(ci > 0.0 && ci < 1.0)) throw UsageError(Field::ci, "ci must be between 0 and 1");
  req.options.ci = ci;
  if (alpha && (*alpha < -4 || *alpha > 2)) throw UsageError(Field::alpha, "alpha must be an integer from -4 to 2");
  req.options.alpha = alpha;
  if (edf != "greenhall" && edf != "simple") throw UsageError(Field::edf, "edf must be \"greenhall\" or \"simple\"");
  req.options.edf = edf == "simple" ? EdfMethod::simple : EdfMethod::greenhall;
  req.options.conservative_short = conservative;
  req.options.intervals = intervals;
  req.threads = threads;
  if (names.size() != channels.size()) throw std::invalid_argument("names: one name per channel");
  std::vector<std::span<const double>> views;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    views.push_back(view(channels[c], "data"));
    io::check_samples(views.back(), "<arrays>", c + 1, names[c], gaps == "skip");
    if (views.back().size() != views.front().size())
      throw ArgumentError("data", "every channel must have the same length (" + names[c] + " has " +
                                      std::to_string(views.back().size()) + ", " + names[0] + " " +
                                      std::to_string(views.front().size()) + ")");
  }
  pipeline::DevResult r;
  if (gaps == "skip") {
    // NaN: a missing sample, left out of the OADEV terms (`dev --gaps skip`, pipeline/dev_missing.hpp).
    io::Series s;
    s.rate_hz = rate;
    s.tau0 = 1.0 / rate;
    s.names = names;
    for (const auto& v : views) s.channels.emplace_back(v.begin(), v.end());
    s.segments = {IndexRange{0, s.samples()}};
    s.gaps = io::GapPolicy::skip;
    py::gil_scoped_release free;
    r = pipeline::run_dev(s, req);
  } else {
    py::gil_scoped_release free;
    r = pipeline::run_dev(names, views, rate, {}, req);
  }
  nlohmann::json meta = pipeline::to_json(r);
  meta.erase("columns");
  py::list columns;
  for (const pipeline::DevChannel& ch : r.channels) columns.append(curve(ch, intervals));
  return py::make_tuple(to_python(meta), columns);
}

}  // namespace

void bind_stats(py::module_& m) {
  m.def("_check_rate", &io::check_rate, py::arg("rate"),
        "Refuses a sampling rate outside the readers' range (cubecal.UsageError naming rate).");
  m.def("_deviation", &deviation, py::arg("stat"), py::arg("data"), py::arg("rate"), py::arg("data_type"),
        py::arg("factors"),
        "Deviation and term count of `stat` at each averaging factor (n == 0: record too short for it).");
  m.def("_deviation_missing", &deviation_missing, py::arg("data"), py::arg("rate"), py::arg("data_type"),
        py::arg("factors"), py::arg("ci"), py::arg("alpha"),
        "OADEV with missing samples (NaN) left out: (dev, n, lo, hi) at each averaging factor.");
  m.def("_dev", &dev, py::arg("channels"), py::arg("names"), py::arg("rate"), py::arg("stat"), py::arg("data_type"),
        py::arg("taus"), py::arg("ci"), py::arg("alpha"), py::arg("edf"), py::arg("conservative"), py::arg("intervals"),
        py::arg("threads"), py::arg("gaps") = "error",
        "`cubecal dev` on arrays: (JSON of the result without its columns, list of column dicts); gaps=\"skip\": "
        "NaN is a missing sample, as `dev --gaps skip`.");
}

}  // namespace cubecal::python
