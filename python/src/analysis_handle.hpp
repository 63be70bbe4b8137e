// An analysis held for Python: the typed result, shared by the Analysis
// object and whatever is made from it (cubecal.simulate from a model).
#pragma once
#include <memory>

#include "cubecal/pipeline/analyze.hpp"

namespace cubecal::python {

struct AnalysisHandle {
  std::shared_ptr<const pipeline::AnalysisResult> result;
};

}  // namespace cubecal::python
