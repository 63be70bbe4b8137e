// The steps of `analyze` that the in-memory (analyze.cpp) and the streamed
// (analyze_stream.cpp) runs share: the OADEV request, the noise terms of a
// curve, and the sensor models fitted to it. Not an installed header.
#pragma once
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"

namespace cubecal::pipeline::detail {

// Throws UsageError(Field::units / "lsb") when the request's per-channel lists
// fit neither one value for all nor one per channel.
void check_channel_lists(const AnalyzeRequest& req, std::size_t channels);
// Channel c's unit (counts when none given), quantizer of the model
// (counts per unit; 0: none), and drift window in samples (the request's,
// else 300 s for rate sensors and 1000 s otherwise, as the paper).
Unit unit_of(const AnalyzeRequest& req, std::size_t c);
double model_lsb(const AnalyzeRequest& req, std::size_t c);
// A window given (drift_window_s) shorter than one sample is a UsageError
// with the sample period (the default window is then 0: no drift); a window beyond any record comes back as
// kMaxDriftWindow samples (check_drift_window then refuses it).
std::size_t drift_window(const AnalyzeRequest& req, const Unit& unit, double dt);
inline constexpr std::size_t kMaxDriftWindow = std::size_t{1} << 60;

// Whether each channel's drift window fits in the longest gap-free stretch
// (`longest` samples of the record's `samples`, dt apart): a window given
// that does not is a UsageError naming the record length; a
// default one that does not leaves r.drift_skipped saying why there is no
// drift series.
void check_drift_window(const AnalyzeRequest& req, AnalysisResult& r, std::size_t longest, std::size_t samples,
                        double dt);

// The OADEV of every Allan curve analyze reports (intervals at req.ci, the
// widest neighbouring type below 30 averages).
DevRequest oadev_request(const AnalyzeRequest& req);

// The noise terms of a curve: slope read-offs and the five-term fit.
NoiseAnalysis noise_of(std::vector<StabilityPoint> points);
inline NoiseAnalysis noise_of(const DevChannel& ch) { return noise_of(ch.points); }

// The paper's random-walk model and the Gauss-Markov alternative fitted to
// m.adev (why not, when they do not fit).
void fit_models(ModelAnalysis& m, double dt, double lsb);

// m.composite_residual: the composite model's Allan variance (twice its Haar
// wavelet variance at tau = 2m) against m.adev; nothing without a composite.
void composite_residual(ModelAnalysis& m, double dt);

}  // namespace cubecal::pipeline::detail
