// Binary frames into samples (frame_decoder.hpp).
#include "cubecal/acquire/frame_decoder.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

namespace cubecal::acquire {

namespace {

std::uint64_t load(const char* p, std::size_t n, bool big_endian) {
  std::uint64_t v = 0;
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  if (big_endian)
    for (std::size_t i = 0; i < n; ++i) v = (v << 8) | b[i];
  else
    for (std::size_t i = n; i-- > 0;) v = (v << 8) | b[i];
  return v;
}

template <typename T>
void put(std::string& out, T v) {
  char buf[40];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

}  // namespace

FrameDecoder::FrameDecoder(FrameSpec spec) : spec_(std::move(spec)), size_(spec_.frame_size()) {
  values_.resize(spec_.fields.size());
}

void FrameDecoder::flush_skipped(SampleHandler& h) {
  if (skipped_.empty()) return;
  h.on_reject("bytes skipped looking for the sync bytes", skipped_, true);
  skipped_.clear();
}

void FrameDecoder::drop_partial(std::string_view reason, SampleHandler& h) {
  flush_skipped(h);
  if (pos_ < buf_.size()) h.on_reject(reason, std::string_view(buf_).substr(pos_), true);
  buf_.clear();
  pos_ = 0;
}

void FrameDecoder::decode(const char* frame, SampleHandler& h) {
  fields_.clear();
  for (std::size_t i = 0; i < spec_.fields.size(); ++i) {
    const FrameField& f = spec_.fields[i];
    const std::uint64_t raw = load(frame + f.offset, size_of(f.type), spec_.big_endian);
    if (i > 0) fields_ += ',';
    double v = 0;
    switch (f.type) {
      case FieldType::u8:
      case FieldType::u16:
      case FieldType::u32:
      case FieldType::u64:
        put(fields_, raw);
        v = static_cast<double>(raw);
        break;
      case FieldType::i8: {
        const auto x = static_cast<std::int8_t>(raw);
        put(fields_, static_cast<int>(x));
        v = x;
        break;
      }
      case FieldType::i16: {
        const auto x = static_cast<std::int16_t>(raw);
        put(fields_, static_cast<int>(x));
        v = x;
        break;
      }
      case FieldType::i32: {
        const auto x = static_cast<std::int32_t>(raw);
        put(fields_, x);
        v = x;
        break;
      }
      case FieldType::i64: {
        const auto x = static_cast<std::int64_t>(raw);
        put(fields_, x);
        v = static_cast<double>(x);
        break;
      }
      case FieldType::f32: {
        const float x = std::bit_cast<float>(static_cast<std::uint32_t>(raw));
        put(fields_, x);
        v = x;
        break;
      }
      case FieldType::f64: {
        const double x = std::bit_cast<double>(raw);
        put(fields_, x);
        v = x;
        break;
      }
    }
    if (!std::isfinite(v)) {
      // As a text field that is not finite: a chunk holds numbers only.
      h.on_reject("field " + std::to_string(i + 1) + " is not finite", std::string_view(frame, size_), true);
      return;
    }
    values_[i] = v;
  }
  h.on_sample(fields_, values_);
}

void FrameDecoder::feed(std::string_view bytes, SampleHandler& h) {
  if (!announced_) {
    std::vector<std::string> names;
    for (const auto& f : spec_.fields) names.push_back(f.name);
    h.on_layout(names);
    announced_ = true;
  }
  if (pos_ > 0 && pos_ == buf_.size()) {
    buf_.clear();
    pos_ = 0;
  }
  buf_.append(bytes);
  const std::string_view sync = spec_.sync;
  const std::size_t csum = size_of(spec_.checksum);
  for (;;) {
    const std::string_view rest = std::string_view(buf_).substr(pos_);
    const auto at = rest.find(sync);
    if (at == std::string_view::npos) {
      // Keep the last sync.size()-1 bytes: a sync may straddle two batches.
      const std::size_t keep = std::min(rest.size(), sync.size() - 1);
      skipped_.append(rest.substr(0, rest.size() - keep));
      pos_ += rest.size() - keep;
      if (skipped_.size() >= 65536) flush_skipped(h);  // a long run is several entries
      break;
    }
    if (at > 0) {
      skipped_.append(rest.substr(0, at));
      pos_ += at;
    }
    if (buf_.size() - pos_ < size_) break;  // the frame is not complete yet
    const char* frame = buf_.data() + pos_;
    bool ok = true;
    if (csum > 0) {
      const std::string_view covered(frame + sync.size(), spec_.payload_size());
      const std::uint32_t want =
          static_cast<std::uint32_t>(load(frame + sync.size() + spec_.payload_size(), csum, spec_.big_endian));
      ok = checksum_of(spec_.checksum, covered) == want;
    }
    flush_skipped(h);
    if (ok)
      decode(frame, h);
    else
      h.on_reject("bad checksum", std::string_view(frame, size_), true);
    pos_ += size_;
  }
  // Compact: drop what was consumed once it is most of the buffer.
  if (pos_ > 0 && pos_ >= buf_.size() / 2) {
    buf_.erase(0, pos_);
    pos_ = 0;
  }
}

}  // namespace cubecal::acquire
