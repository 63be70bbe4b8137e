// libFuzzer target: the analysis.json loader (parse_analysis_json), which
// `cubecal report DIR` and `simulate --model` run on files users hand them.
// Text that is not an analysis must be a UsageError, never another
// exception; a document that loads must write out (to_json) and load again.
#include <cstddef>
#include <cstdint>
#include <string>

#include "cubecal/pipeline/analysis_json.hpp"
#include "error_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cubecal;
  const std::string text(reinterpret_cast<const char*>(data), size);
  fuzz::expect_clean([&] {
    const pipeline::AnalysisDocument d = pipeline::parse_analysis_json(text, "analysis.json");
    const std::string again = pipeline::to_json(d).dump();
    try {
      (void)pipeline::parse_analysis_json(again, "analysis.json (written back)");
    } catch (const UsageError& e) {
      fuzz::finding("a loaded analysis does not load again after to_json", e.what());
    }
  });
  return 0;
}
