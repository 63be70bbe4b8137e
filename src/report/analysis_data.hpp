// Internal to cubecal_report: an `analyze --out DIR` result as read back from
// its files, the plots made of it and the page that shows it.
#pragma once
#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cubecal/report/plot.hpp"
#include "cubecal/report/report.hpp"

namespace cubecal::report::detail {

using nlohmann::json;

struct Curve {
  std::vector<double> tau, dev, lo, hi;  // measured OADEV and its interval
  std::vector<double> fit, model, gm;    // five-term fit, random-walk and Gauss-Markov models (NaN: none)
};

struct ChannelData {
  const json* j = nullptr;               // channels[i] of analysis.json
  std::string name, unit, kind;
  Curve curve;
  std::vector<double> drift_t, drift;    // drift.csv (s, unit)
};

struct SensorGroup {
  std::string key;                       // rate, field, other (+ _unit when a kind has several units)
  std::string title;                     // "rate sensors (deg/s)"
  std::string unit;
  std::vector<std::size_t> channels;
};

struct AnalysisData {
  AnalysisData() = default;
  AnalysisData(AnalysisData&&) = default;             // channels point into root: moves keep them valid
  AnalysisData(const AnalysisData&) = delete;
  AnalysisData& operator=(const AnalysisData&) = delete;
  std::filesystem::path dir;
  json root;
  std::vector<ChannelData> channels;
  std::vector<SensorGroup> groups;
  bool adev_csv = false;                 // model curves read from adev.csv (else computed)
  bool drift_csv = false;
  double rate_hz = 0.0;
  double duration_s = 0.0;
  std::size_t samples = 0;
  std::string ci_text = "68.3 %";        // confidence of the intervals, from the command
};

// Throws UsageError (one line) for a missing or malformed analysis.json.
AnalysisData load_analysis(const std::filesystem::path& dir);

// A figure of the page: the plot, its caption (HTML) and the section it belongs in.
struct Figure {
  Plot plot;
  std::string caption_html;
  std::string section;                   // allan, drift, temperature
  std::string group;                     // SensorGroup::key
};

std::vector<Figure> analysis_figures(const AnalysisData& data, const ReportOptions& options);

// The page; `rendered` parallel to `figures` (empty when plots are missing,
// with `note` saying why).
std::string analysis_page(const AnalysisData& data, const std::vector<Figure>& figures,
                          const std::vector<RenderedPlot>& rendered, const std::string& note);

// JSON helpers: a number, or nullopt for null / missing / not a number.
std::optional<double> number(const json& j, const char* key);
std::optional<double> number(const json& j);

}  // namespace cubecal::report::detail
