/// @file
/// `cubecal analyze --stream`: the analysis of analyze.hpp on a record read
/// in pieces (io::SampleStream), in memory bounded by the window bound
/// whatever the record's length. One pass gives the OADEV curves
/// (stats/streaming_deviation.hpp: exact to the window bound, at a stride
/// above it), their noise terms and sensor models, the model's curve on the
/// first max_samples samples, the fixed bias and standard deviation, the bias
/// drift, the covariance and the least-squares temperature fit. With a
/// temperature, a second pass over the record (it is opened again) gives the
/// compensated curves. The joint estimate of the coefficients with the bias
/// random walk refits a noise model on the whole compensated record at each
/// iteration and is not streamed: the least-squares fit is reported, with
/// that reason.
#pragma once
#include <cstddef>
#include <functional>
#include <memory>

#include "cubecal/io/sample_stream.hpp"
#include "cubecal/pipeline/analyze.hpp"

namespace cubecal::pipeline {

/// Opens the record again from its start; empty when it can be read once
/// only (the standard input).
using ReopenStream = std::function<std::unique_ptr<io::SampleStream>()>;

/// Throws UsageError(Field::temp_index) when a temperature is asked of a record
/// that cannot be read twice, UsageError(Field::psd) for the spectral view
/// (AnalyzeRequest::psd: it needs the whole record) and UsageError(Field::composite)
/// for the composite model (AnalyzeRequest::composite: likewise).
void check_analyze_streamable(const AnalyzeRequest& request, bool can_reopen);

/// request.units: one per channel or one for all (given: the drift window
/// follows the sensor kind). Throws as run_analyze, and InputError when the
/// second pass does not find the record the first one read.
AnalysisResult run_analyze_stream(io::SampleStream& input, const AnalyzeRequest& request, std::size_t window_bound,
                                  const ReopenStream& reopen = {});

}  // namespace cubecal::pipeline
