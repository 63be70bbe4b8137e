/// @file
/// The report page of an analysis as data: the typed result turned into a
/// CommandReport (input, the command that reproduces it, per sensor group the
/// Allan deviation with its noise terms, the fitted models and the bias drift,
/// the temperature dependence, the covariance) for write_command_report.
#pragma once
#include <string>

#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/report/command_report.hpp"
#include "cubecal/report/report.hpp"

namespace cubecal::report {

/// `dir` is where the page goes (named in the text: `cubecal report DIR`);
/// options.max_points and options.seed shape the drift plots.
CommandReport analysis_report(const pipeline::AnalysisResult& r, const AnalysisReportContext& context,
                              const std::string& dir, const ReportOptions& options = {});

}  // namespace cubecal::report
