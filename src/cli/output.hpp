// Presentation of `dev` results: a table for people, CSV and JSON for
// programs. Also the rule that nothing the user has is overwritten unasked.
#pragma once
#include <memory>
#include <ostream>
#include <string>

#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"

namespace cubecal::cli {

struct DevContext {
  std::string file;
  double ci = 0.683;
  std::string edf_method = "greenhall";
  bool intervals = true;
};

void write_dev_table(std::ostream& out, const pipeline::DevResult& r, const DevContext& ctx);
void write_dev_csv(std::ostream& out, const pipeline::DevResult& r, const DevContext& ctx);
// analysis.json, adev.csv, drift.csv and imu.yaml into dir (created).
void write_analysis_files(const std::string& dir, const pipeline::AnalysisResult& r,
                          const pipeline::OutputContext& ctx);

// Opens `path` for writing; refuses (io::UsageError) to replace an existing
// file unless `force`. Writes go to a temporary file renamed into place on
// commit(), so an interrupted run never leaves a half-written result.
class OutputFile {
 public:
  OutputFile(std::string path, bool force);
  ~OutputFile();
  std::ostream& stream();
  void commit();

 private:
  std::string path_;
  std::string tmp_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cubecal::cli
