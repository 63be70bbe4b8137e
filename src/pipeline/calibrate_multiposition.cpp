#include "cubecal/pipeline/calibrate_multiposition.hpp"

#include "cubecal/error.hpp"

namespace cubecal::pipeline {

namespace mp = cubecal::multipos;

namespace {

mp::TriadSeries series_of(const TriadSamples& s, double rate_hz) { return {s.x, s.t, rate_hz}; }

double mean_rate(const TriadSamples& s, double rate) {
  if (s.t.size() < 2) return rate;
  return static_cast<double>(s.t.size() - 1) / (s.t.back() - s.t.front());
}

}  // namespace

std::vector<std::string> multiposition_acc_units() {
  return {"rad", "rad", "rad", "g-unit/raw", "g-unit/raw", "g-unit/raw", "raw", "raw", "raw"};
}

std::vector<std::string> multiposition_gyro_units(std::size_t n) {
  std::vector<std::string> u{"rad", "rad", "rad", "rad", "rad", "rad", "rad/s/raw", "rad/s/raw", "rad/s/raw"};
  if (n == 12) u.insert(u.end(), {"raw", "raw", "raw"});
  return u;
}

MultipositionResult calibrate_multiposition_accelerometer(const TriadSamples& acc, const MultipositionRequest& req) {
  const bool stamped = !acc.t.empty();
  if (stamped && req.rate_hz > 0.0)
    throw UsageError(Field::sampling, "give the time stamps or the sampling rate, not both");
  if (!stamped && !(req.rate_hz > 0.0))
    throw UsageError(Field::sampling, "the time stamps or the sampling rate are needed");
  MultipositionResult r;
  r.acc_file = acc.file;
  r.samples = acc.x.size();
  r.rate_hz = mean_rate(acc, req.rate_hz);
  r.options = req.options;
  r.accelerometer = mp::calibrate_accelerometer(series_of(acc, req.rate_hz), req.options);
  const auto time_of = [&](std::size_t i) { return stamped ? acc.t[i] : static_cast<double>(i) / req.rate_hz; };
  for (const IndexRange& i : r.accelerometer.intervals) r.interval_times.emplace_back(time_of(i.begin), time_of(i.end));
  return r;
}

void add_multiposition_gyroscope(MultipositionResult& r, const TriadSamples& acc, const TriadSamples& gyro,
                                 const MultipositionRequest& req) {
  r.gyro_file = gyro.file;
  r.gyroscope =
      mp::calibrate_gyroscope(series_of(acc, req.rate_hz), r.accelerometer, series_of(gyro, req.rate_hz), req.options);
}

MultipositionResult calibrate_multiposition(const TriadSamples& acc, const std::optional<TriadSamples>& gyro,
                                            const MultipositionRequest& req) {
  MultipositionResult r = calibrate_multiposition_accelerometer(acc, req);
  if (gyro) add_multiposition_gyroscope(r, acc, *gyro, req);
  return r;
}

}  // namespace cubecal::pipeline
