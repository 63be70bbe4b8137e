// Fixed binary frames (frame_spec.hpp) into samples. The decoder hunts for
// the sync bytes; a frame whose checksum does not match is a reject (its
// bytes in hex) and the hunt resumes after it; the bytes skipped while
// hunting are one reject per skipped run. A frame with a float field that is
// not finite (NaN, inf) is a reject too, as such a text field is. Fields are
// written as the chunk's CSV values: integers exactly, floats in their
// shortest round-trip form.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/acquire/frame_spec.hpp"
#include "cubecal/acquire/sample_handler.hpp"

namespace cubecal::acquire {

class FrameDecoder {
 public:
  explicit FrameDecoder(FrameSpec spec);

  // The layout (the field names) is handed on at the first call.
  void feed(std::string_view bytes, SampleHandler& h);
  // The source dropped or ended: the bytes held (a skipped run, a frame
  // begun) are a reject with this reason.
  void drop_partial(std::string_view reason, SampleHandler& h);

  const FrameSpec& spec() const noexcept { return spec_; }
  std::size_t held() const noexcept { return buf_.size() - pos_; }

 private:
  void flush_skipped(SampleHandler& h);
  void decode(const char* frame, SampleHandler& h);

  FrameSpec spec_;
  std::size_t size_;
  bool announced_ = false;
  std::string buf_;  // bytes not yet consumed start at pos_
  std::size_t pos_ = 0;
  std::string skipped_;  // the current run of bytes skipped while hunting
  std::vector<double> values_;
  std::string fields_;
};

}  // namespace cubecal::acquire
