// libFuzzer target: the binary frames of `cubecal record --frame`: the spec
// parser (acquire::parse_frame_spec) and the decoder (acquire::FrameDecoder)
// on arbitrary bytes arriving in arbitrary pieces. The first byte chooses a
// spec (one of a few, or, with its top bit set, the input's first line as
// the spec text), the second seeds the piece sizes; the rest is the stream.
// Checked: a bad spec is a one-line UsageError; the layout is the spec's
// fields, once; every sample has one finite value per field and its chunk
// fields read back as those values; every byte received is in exactly one
// good frame or one reject once the stream is ended; and the same samples
// and rejects whatever the pieces (the whole stream at once).
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/acquire/frame_decoder.hpp"
#include "cubecal/acquire/frame_spec.hpp"
#include "error_check.hpp"
#include "handed_log.hpp"

namespace {

using namespace cubecal;

constexpr const char* kSpecs[] = {
    "sync=A55A;fields=t:u32,gx:i16,gy:i16,gz:i16;checksum=xor8;endian=le",
    "sync=AA;fields=a:f32,b:f64,c:u8;checksum=crc16;endian=be",
    "sync=DEADBEEF;fields=n:u64,x:i64,y:i32,z:i8;checksum=crc32",
    "sync=5555;fields=v:u16,w:f32;checksum=sum8",
    "sync=7E;fields=x:i8",
    "sync=A5A5;fields=t:u32,g:f32;checksum=none;endian=be",
    "sync=0000;fields=a:u8,b:u8;checksum=xor8",
    "sync=FFFFFF;fields=d:f64;checksum=crc32;endian=le",
};

class Checker final : public acquire::SampleHandler {
 public:
  explicit Checker(const acquire::FrameSpec& spec) : spec_(spec) {}
  void on_layout(const std::vector<std::string>& names) override {
    if (layouts_++ > 0) fuzz::finding("frame decoder", "layout handed on twice");
    if (names.size() != spec_.fields.size()) fuzz::finding("frame decoder", "layout is not the spec's fields");
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] != spec_.fields[i].name) fuzz::finding("frame decoder", "layout is not the spec's fields");
  }
  void on_sample(std::string_view fields, std::span<const double> values) override {
    if (layouts_ == 0) fuzz::finding("frame decoder", "sample before the layout");
    if (values.size() != spec_.fields.size())
      fuzz::finding("frame decoder", "sample with a value count other than the spec's");
    std::size_t i = 0;
    for (std::size_t b = 0;; ++i) {
      const std::size_t e = std::min(fields.find(',', b), fields.size());
      const std::string_view f = fields.substr(b, e - b);
      if (i >= values.size() || !std::isfinite(values[i]))
        fuzz::finding("frame decoder", "a sample value is not finite");
      // An f32 is written in its shortest form as a float: it reads back as
      // that float.
      bool same = false;
      if (spec_.fields[i].type == acquire::FieldType::f32) {
        float v = 0;
        const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
        same = r.ec == std::errc() && r.ptr == f.data() + f.size() && static_cast<double>(v) == values[i];
      } else {
        double v = 0;
        const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
        same = r.ec == std::errc() && r.ptr == f.data() + f.size() && v == values[i];
      }
      if (!same) fuzz::finding("frame decoder", "chunk fields do not read back as the sample's values");
      if (e == fields.size()) break;
      b = e + 1;
    }
    if (i + 1 != values.size()) fuzz::finding("frame decoder", "chunk field count differs from the value count");
    log_.sample(fields, spec_.frame_size());
  }
  void on_reject(std::string_view reason, std::string_view data, bool binary) override {
    if (reason.empty()) fuzz::finding("frame decoder", "reject without a reason");
    if (!binary) fuzz::finding("frame decoder", "frame bytes rejected as text");
    if (data.empty()) fuzz::finding("frame decoder", "empty reject");
    log_.reject(reason, data);
  }
  std::size_t handed() const { return log_.handed; }
  const std::string& log() const { return log_.text; }

 private:
  const acquire::FrameSpec& spec_;
  std::size_t layouts_ = 0;
  fuzz::HandedLog log_;
};

std::string run(const acquire::FrameSpec& spec, std::string_view stream, unsigned seed) {
  acquire::FrameDecoder dec(spec);
  Checker c(spec);
  std::uint32_t x = seed * 2654435761u + 1u;
  std::size_t at = 0;
  dec.feed({}, c);
  while (at < stream.size()) {
    std::size_t n = stream.size() - at;
    if (seed != 0) {
      x ^= x << 13;
      x ^= x >> 17;
      x ^= x << 5;
      n = std::min<std::size_t>(n, 1 + x % 48);
    }
    dec.feed(stream.substr(at, n), c);
    at += n;
  }
  dec.drop_partial("partial frame at end of stream", c);
  if (dec.held() != 0) fuzz::finding("frame decoder", "bytes held after the stream ended");
  if (c.handed() != stream.size()) fuzz::finding("frame decoder", "bytes lost or handed on twice");
  return c.log();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const unsigned mode = data[0];
  const unsigned seed = data[1];
  std::string_view rest(reinterpret_cast<const char*>(data + 2), size - 2);
  std::optional<acquire::FrameSpec> spec;
  if ((mode & 0x80u) != 0) {
    const auto nl = rest.find('\n');
    if (nl == std::string_view::npos) return 0;
    const std::string_view text = rest.substr(0, nl);
    rest.remove_prefix(nl + 1);
    fuzz::expect_clean([&] { spec = acquire::parse_frame_spec(text); });
    if (!spec) return 0;
    if (spec->sync.empty() || spec->sync.size() > 4 || spec->fields.empty() || spec->text != text)
      fuzz::finding("frame spec", "a spec accepted that the documentation does not allow");
    if (spec->frame_size() > 4096) return 0;  // many fields: valid, but slow to fuzz
  } else {
    spec = acquire::parse_frame_spec(kSpecs[mode & 7u]);
  }
  const std::string pieces = run(*spec, rest, seed | 1u);
  const std::string whole = run(*spec, rest, 0);
  if (pieces != whole) fuzz::finding("frame decoder", "samples or rejects depend on how the bytes were split");
  return 0;
}
