// Text lines into samples. Lines end in LF, CRLF or CR (told from the first
// line end). The first complete line sets the layout, as the readers detect
// it: the delimiter (comma, tab, semicolon, else blanks; or as given) and a
// header when every field is a name. The column names are --columns, else
// the header's, else col1..colN. Every later line must have that many
// fields, each a finite number (fast_float); any other line is a reject with
// its reason. Blank lines are counted and skipped; '#' comment lines and a
// repeated header are rejects too, so that nothing received is lost.
//
// A source joined mid-stream (a serial line) may start in the middle of a
// line. With neither --columns nor a header, the first data line is held
// until the second: when their field counts differ the first is a reject
// ("partial line at start of stream") and the second sets the layout.
//
// Before the layout is known, a line that is not text (bytes that are not
// UTF-8, control bytes other than tab: the noise of a serial line at power-up
// or at a wrong baud rate) is a reject and cannot become the header.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/acquire/sample_handler.hpp"

namespace cubecal::acquire {

struct LineFramerOptions {
  std::vector<std::string> columns;  // names of the fields; empty: from a header line or col1..colN
  std::optional<char> delimiter;     // ',', '\t', ';' or ' ' (runs of blanks); none: detected
  std::size_t max_line = 65536;      // a longer run of bytes without a line end is a reject
};

class LineFramer {
 public:
  explicit LineFramer(LineFramerOptions opt = {});

  // Bytes as received, in order; calls `h` for the layout, each sample and
  // each reject of the complete lines among them.
  void feed(std::string_view bytes, SampleHandler& h);
  // The source dropped or ended: the incomplete line held is a reject with
  // this reason (nothing when none is held).
  void drop_partial(std::string_view reason, SampleHandler& h);
  // The source ended: a first line still held sets the layout and is a
  // sample; then drop_partial("partial line at end of stream").
  void finish(SampleHandler& h);
  // A record boundary of the source (the end of a UDP datagram): the bytes
  // held since the last line end are a complete line.
  void end_record(SampleHandler& h);

  bool has_layout() const noexcept { return have_layout_; }
  const std::vector<std::string>& names() const noexcept { return names_; }
  char delimiter() const noexcept { return delim_; }  // ' ' for blanks; valid once has_layout()
  std::string_view partial() const noexcept { return carry_; }
  std::size_t blank_lines() const noexcept { return blank_lines_; }

 private:
  enum class Ending { unknown, lf, cr };
  void consume(const char* p, const char* end, SampleHandler& h);
  void line(std::string_view text, SampleHandler& h);
  void first_line(std::string_view text, SampleHandler& h);
  void set_layout(std::vector<std::string> names, SampleHandler& h);
  void data_line(std::string_view text, SampleHandler& h);
  bool split(std::string_view text, std::vector<std::string_view>& fields) const;

  LineFramerOptions opt_;
  Ending ending_ = Ending::unknown;
  bool have_layout_ = false;
  char delim_ = ',';
  std::vector<std::string> names_;
  std::string header_text_;  // the header line as received, to tell a repeat
  std::string held_;         // the first data line, until the second confirms its field count
  bool holding_ = false;
  std::string carry_;  // an incomplete line
  std::vector<std::string_view> fields_;
  std::vector<double> values_;
  std::string joined_;  // fields re-joined by commas (delimiters other than ',')
  std::size_t blank_lines_ = 0;
};

}  // namespace cubecal::acquire
