// write_report: the page of a typed analysis result, from memory or from the
// files of an earlier run.
#include "cubecal/report/report.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cubecal/error.hpp"
#include "cubecal/pipeline/analysis_json.hpp"
#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/report/analysis_report.hpp"
#include "cubecal/report/command_report.hpp"

namespace cubecal::report {

namespace fs = std::filesystem;

namespace {

std::string read_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  if (!f) throw UsageError("cannot read " + p.string());
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

std::vector<std::string> existing_report_outputs(const std::string& dir) {
  std::vector<std::string> v;
  const fs::path d(dir);
  if (fs::exists(d / "report.html")) v.push_back((d / "report.html").string());
  if (fs::exists(d / "plots")) v.push_back((d / "plots").string());
  return v;
}

ReportResult write_report(const pipeline::AnalysisResult& r, const AnalysisReportContext& context,
                          const std::string& dir, const ReportOptions& options) {
  return write_command_report(analysis_report(r, context, dir, options), dir, options);
}

ReportResult write_report(const std::string& dir, const ReportOptions& options) {
  const fs::path d(dir);
  const fs::path p = d / "analysis.json";
  if (!fs::exists(p))
    throw UsageError(p.string() + " not found: " + dir + " holds no analysis (run `cubecal analyze FILE ... {out} " +
                     dir + "` first)");
  const std::string text = read_file(p);
  pipeline::AnalysisDocument doc = pipeline::parse_analysis_json(text, p.string());
  AnalysisReportContext ctx;
  ctx.command = doc.command;
  const fs::path drift = d / "drift.csv";
  if (!fs::exists(drift)) {
    ctx.drift_note = "No drift.csv in the directory: no drift plots.";
  } else {
    bool ok = false;
    try {
      ok = pipeline::read_drift_csv(drift.string(), doc.drift_points, doc.result);
    } catch (const InputError& e) {
      ctx.drift_note = std::string("drift.csv could not be read (") + face_words(e.text()) + "): no drift plots.";
    }
    if (!ok && ctx.drift_note.empty()) ctx.drift_note = "drift.csv does not match analysis.json: no drift plots.";
  }
  return write_report(doc.result, ctx, dir, options);
}

}  // namespace cubecal::report
