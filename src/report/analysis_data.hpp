// Internal to cubecal_report: what the analysis page and its figures share:
// the sensor groups of a result, the model curves at the measured taus, the
// confidence level as text, and the figures of a group.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/report/command_report.hpp"

namespace cubecal::report::detail {

// Channels of one kind and unit: rate, field or other (+ _unit when a kind
// comes in several units).
struct SensorGroup {
  std::string key;
  std::string title;  // "Rate sensors (deg/s)"
  std::string unit;
  std::vector<std::size_t> channels;
};

std::vector<SensorGroup> sensor_groups(const pipeline::AnalysisResult& r);

// "68.3 %".
std::string ci_text(double ci);

// The five-term fit, the random-walk, the Gauss-Markov and the composite
// model at each tau of the channel's curve (NaN where a model was not fitted).
struct ModelCurves {
  std::vector<double> fit, model, gm, composite;
};
ModelCurves model_curves(const pipeline::ChannelAnalysis& c, double rate_hz);

ReportFigure allan_figure(const pipeline::AnalysisResult& r, const SensorGroup& g);
std::optional<ReportFigure> drift_figure(const pipeline::AnalysisResult& r, const SensorGroup& g,
                                         const ReportOptions& o);
std::vector<ReportFigure> temperature_figures(const pipeline::AnalysisResult& r, const SensorGroup& g);
// A channel's composite model (analyze --composite) against the curve it
// was fitted with: the measured Allan deviation with its intervals, each
// term's contribution and the total. `name`: the plot's file stem.
ReportFigure composite_figure(const pipeline::AnalysisResult& r, const pipeline::ChannelAnalysis& c,
                              const std::string& name);

}  // namespace cubecal::report::detail
