// What a framer hands on: the layout once it is known, then each sample as
// the chunk line's data fields (comma-separated text) and their values, or a
// reject with its reason and the bytes as received.
#pragma once
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace cubecal::acquire {

class SampleHandler {
 public:
  virtual ~SampleHandler() = default;
  // The column names (once, before the first sample).
  virtual void on_layout(const std::vector<std::string>& names) = 0;
  // `fields`: the sample's values as the chunk's CSV fields, comma-separated
  // without the host stamps; `values`: the same, parsed.
  virtual void on_sample(std::string_view fields, std::span<const double> values) = 0;
  // `data`: the bytes of the line (without its terminator) or of the frame;
  // `binary`: written to the rejects file in hex rather than as text.
  virtual void on_reject(std::string_view reason, std::string_view data, bool binary) = 0;
};

}  // namespace cubecal::acquire
