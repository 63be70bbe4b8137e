// Presentation of `dev` results: a table for people, CSV and JSON for
// programs. Also the rule that nothing the user has is overwritten unasked.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/pipeline/json_text.hpp"

namespace cubecal::cli {

struct DevContext {
  std::string file;
  double ci = 0.683;
  std::string edf_method = "greenhall";
  bool intervals = true;
};

// A sampling rate as a user reads it: six significant digits, so the
// rounding of a rate taken from time stamps (10.0010001) shows as 10.001 and
// a rate within that of a round value as the round value (10).
std::string rate_text(double hz);

// What became of an explicit --taus list, one line each for stderr (empty
// when there is nothing to say): the warning naming every listed tau the
// statistic cannot evaluate on the record, with the reason (and, for
// analyze, those left out of the model's --max-samples part), and the note
// naming listed taus merged with an earlier one on the same averaging factor.
std::string excluded_taus_warning(const TauListOutcome& t, const std::vector<ExcludedTau>& model = {});
std::string merged_taus_note(const TauListOutcome& t);

void write_dev_table(std::ostream& out, const pipeline::DevResult& r, const DevContext& ctx);
void write_dev_csv(std::ostream& out, const pipeline::DevResult& r, const DevContext& ctx);
// pipeline::analysis_files into dir (created); returns the names written
// and notes on stderr each estimator file that lacks a sensor's terms.
std::vector<std::string> write_analysis_files(const std::string& dir, const pipeline::AnalysisResult& r,
                                              const pipeline::OutputContext& ctx);

// Opens `path` for writing; refuses (UsageError) to replace an existing
// file unless `force`. Writes go through an io::AtomicFile renamed into
// place on commit(), so an interrupted run never leaves a half-written result.
class OutputFile {
 public:
  OutputFile(std::string path, bool force);
  ~OutputFile();
  std::ostream& stream();
  void commit();

 private:
  std::string path_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Where a command's result goes: standard output, or the --out file. The
// file is refused at construction when it exists and !force (before any
// work), written atomically, and announced on stderr by finish().
class ResultOutput {
 public:
  ResultOutput(const std::string& path, bool force);
  std::ostream& stream();
  void finish();

 private:
  std::string path_;
  std::unique_ptr<OutputFile> file_;
};

// A calibration command's result on `out`: its to_json with the invocation
// added (json), or the table print_table(stream, r) writes; then finished.
template <class Result, class PrintTable>
void write_result(ResultOutput& out, bool json, const Result& r, const std::string& invocation,
                  PrintTable&& print_table) {
  std::ostream& os = out.stream();
  if (json) {
    nlohmann::json j = to_json(r);
    j["invocation"] = invocation;
    os << pipeline::json_text(j, 2) << '\n';
  } else {
    print_table(os, r);
  }
  out.finish();
}

}  // namespace cubecal::cli
