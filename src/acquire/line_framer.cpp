// Text lines into samples (line_framer.hpp). The hot path is one memchr per
// line, one per field and one fast_float parse per field, into buffers that
// are reused: no allocation per line.
#include "cubecal/acquire/line_framer.hpp"

#include <fast_float/fast_float.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "cubecal/error.hpp"
#include "cubecal/printable_text.hpp"

namespace cubecal::acquire {

namespace {

bool is_pad(char delim, char c) { return c == ' ' || (c == '\t' && delim != '\t'); }

// A number filling the whole field (a leading '+' allowed, as the readers
// allow it); false for anything else.
bool parse_field(std::string_view f, double& v) {
  const char* p = f.data();
  const char* e = p + f.size();
  if (p < e && *p == '+') ++p;
  if (p == e) return false;
  const auto [ptr, ec] = fast_float::from_chars(p, e, v);
  return ec == std::errc() && ptr == e;
}

char detect_delimiter(std::string_view s) {
  if (s.find(',') != std::string_view::npos) return ',';
  if (s.find('\t') != std::string_view::npos) return '\t';
  if (s.find(';') != std::string_view::npos) return ';';
  return ' ';
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r' || s.front() == '\n'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r' || s.back() == '\n'))
    s.remove_suffix(1);
  return s;
}

// Well-formed UTF-8 without control bytes, tab aside: text a header can be.
bool is_text(std::string_view s) {
  for (std::size_t b = 0; b <= s.size();) {
    const std::size_t tab = std::min(s.find('\t', b), s.size());
    const std::string_view piece = s.substr(b, tab - b);
    if (printable_text(piece) != piece) return false;
    b = tab + 1;
  }
  return true;
}

std::string header_name(std::string_view f) {
  if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = f.substr(1, f.size() - 2);
  return std::string(f);
}

}  // namespace

LineFramer::LineFramer(LineFramerOptions opt) : opt_(std::move(opt)) {
  if (opt_.delimiter && *opt_.delimiter != ',' && *opt_.delimiter != '\t' && *opt_.delimiter != ';' &&
      *opt_.delimiter != ' ')
    throw UsageError(Field::delimiter, "the delimiter is one of , ; tab or space");
  for (const auto& c : opt_.columns)
    if (c.empty() || !is_text(c) || c.find('\t') != std::string::npos)
      throw UsageError(Field::columns, "{columns}: '" + printable_text(c) + "' is not a column name (text, not empty)");
  values_.reserve(64);
  fields_.reserve(64);
}

bool LineFramer::split(std::string_view text, std::vector<std::string_view>& fields) const {
  fields.clear();
  const char* s = text.data();
  const char* e = s + text.size();
  if (delim_ == ' ') {
    while (s < e) {
      const char* b = s;
      while (s < e && *s != ' ' && *s != '\t') ++s;
      fields.emplace_back(b, static_cast<std::size_t>(s - b));
      while (s < e && (*s == ' ' || *s == '\t')) ++s;
    }
    return true;
  }
  for (;;) {
    const auto* hit = static_cast<const char*>(std::memchr(s, delim_, static_cast<std::size_t>(e - s)));
    const char* stop = hit != nullptr ? hit : e;
    const char* b = s;
    while (b < stop && is_pad(delim_, *b)) ++b;
    const char* fe = stop;
    while (fe > b && is_pad(delim_, fe[-1])) --fe;
    fields.emplace_back(b, static_cast<std::size_t>(fe - b));
    if (stop == e) break;
    s = stop + 1;
  }
  return true;
}

void LineFramer::feed(std::string_view bytes, SampleHandler& h) {
  const char* p = bytes.data();
  const char* const end = p + bytes.size();
  if (ending_ == Ending::unknown) {
    // A CR held at the end of the last batch decides by the next byte.
    if (!carry_.empty() && carry_.back() == '\r' && p < end) {
      if (*p == '\n') {
        ending_ = Ending::lf;
      } else {
        // Lines end in CR, and the CR held ended the first line: hand that
        // line on now (consume would join it to the next one).
        ending_ = Ending::cr;
        std::string first = std::move(carry_);
        carry_.clear();
        first.pop_back();
        line(first, h);
      }
    } else {
      const char* q = p;
      while (q < end && *q != '\n' && *q != '\r') ++q;
      if (q == end || (*q == '\r' && q + 1 == end)) {
        carry_.append(p, end);
        if (carry_.size() > opt_.max_line) drop_partial("line longer than the longest line allowed", h);
        return;
      }
      ending_ = (*q == '\n' || q[1] == '\n') ? Ending::lf : Ending::cr;
    }
  }
  consume(p, end, h);
}

void LineFramer::consume(const char* p, const char* end, SampleHandler& h) {
  const char term = ending_ == Ending::cr ? '\r' : '\n';
  if (!carry_.empty()) {
    const auto* nl = static_cast<const char*>(std::memchr(p, term, static_cast<std::size_t>(end - p)));
    if (nl == nullptr) {
      carry_.append(p, end);
      if (carry_.size() > opt_.max_line) drop_partial("line longer than the longest line allowed", h);
      return;
    }
    carry_.append(p, nl);
    line(carry_, h);
    carry_.clear();
    p = nl + 1;
  }
  while (p < end) {
    const auto* nl = static_cast<const char*>(std::memchr(p, term, static_cast<std::size_t>(end - p)));
    if (nl == nullptr) break;
    line(std::string_view(p, static_cast<std::size_t>(nl - p)), h);
    p = nl + 1;
  }
  if (p < end) {
    carry_.assign(p, end);
    if (carry_.size() > opt_.max_line) drop_partial("line longer than the longest line allowed", h);
  }
}

void LineFramer::drop_partial(std::string_view reason, SampleHandler& h) {
  if (carry_.empty()) return;
  h.on_reject(reason, carry_, false);
  carry_.clear();
}

void LineFramer::finish(SampleHandler& h) {
  if (holding_) {
    holding_ = false;
    std::vector<std::string_view> f;
    split(held_, f);
    std::vector<std::string> names;
    for (std::size_t i = 0; i < f.size(); ++i) names.push_back("col" + std::to_string(i + 1));
    set_layout(std::move(names), h);
    data_line(held_, h);
  }
  drop_partial("partial line at end of stream", h);
}

void LineFramer::end_record(SampleHandler& h) {
  if (carry_.empty()) return;
  std::string l = std::move(carry_);
  carry_.clear();
  if (l.back() == '\r') l.pop_back();  // a CR at the end of the datagram, its ending still unknown
  line(l, h);
}

void LineFramer::line(std::string_view raw, SampleHandler& h) {
  const std::string_view text = trim(raw);
  if (text.empty()) {
    ++blank_lines_;
    return;
  }
  if (text.front() == '#') {
    h.on_reject("comment line", text, false);
    return;
  }
  if (!have_layout_ && !is_text(text)) {
    h.on_reject("not text (bytes that are not UTF-8, or control bytes) before the first line of data", text, false);
    return;
  }
  if (!have_layout_) {
    first_line(text, h);
    return;
  }
  data_line(text, h);
}

void LineFramer::set_layout(std::vector<std::string> names, SampleHandler& h) {
  names_ = std::move(names);
  have_layout_ = true;
  h.on_layout(names_);
}

void LineFramer::first_line(std::string_view text, SampleHandler& h) {
  if (holding_) {
    // The second line: does it confirm the first one's field count?
    std::vector<std::string_view> f1, f2;
    split(held_, f1);
    split(text, f2);
    holding_ = false;
    bool names2 = !f2.empty();
    for (const auto f : f2) {
      double v = 0;
      names2 = names2 && !parse_field(f, v);
    }
    if (f1.size() != f2.size() || names2) {
      h.on_reject("partial line at start of stream", held_, false);
      first_line(text, h);
      return;
    }
    std::vector<std::string> names;
    for (std::size_t i = 0; i < f1.size(); ++i) names.push_back("col" + std::to_string(i + 1));
    set_layout(std::move(names), h);
    data_line(held_, h);
    data_line(text, h);
    return;
  }
  delim_ = opt_.delimiter ? *opt_.delimiter : detect_delimiter(text);
  std::vector<std::string_view> f;
  split(text, f);
  bool any_number = false, any_name = false;
  for (const auto field : f) {
    double v = 0;
    if (field.empty()) continue;
    if (parse_field(field, v))
      any_number = true;
    else
      any_name = true;
  }
  const bool header = any_name && !any_number;
  if (header) {
    if (!opt_.columns.empty() && opt_.columns.size() != f.size())
      throw UsageError(Field::columns, "{columns} names " + std::to_string(opt_.columns.size()) +
                                           " columns but the source's header line has " + std::to_string(f.size()) +
                                           " fields: '" + printable_text(text.substr(0, 200)) + "'");
    std::vector<std::string> names;
    if (!opt_.columns.empty())
      names = opt_.columns;
    else
      for (const auto field : f) names.push_back(header_name(field));
    header_text_.assign(text);
    set_layout(std::move(names), h);
    return;
  }
  if (!opt_.columns.empty()) {
    // The names are given: the line is data, checked against their count.
    set_layout(opt_.columns, h);
    data_line(text, h);
    return;
  }
  held_.assign(text);
  holding_ = true;
}

void LineFramer::data_line(std::string_view text, SampleHandler& h) {
  split(text, fields_);
  if (fields_.size() != names_.size()) {
    if (!header_text_.empty() && text == header_text_) {
      h.on_reject("header line repeated", text, false);
      return;
    }
    h.on_reject(std::to_string(fields_.size()) + " fields where the layout has " + std::to_string(names_.size()), text,
                false);
    return;
  }
  values_.resize(fields_.size());
  for (std::size_t i = 0; i < fields_.size(); ++i) {
    double& v = values_[i];
    if (!parse_field(fields_[i], v)) {
      if (!header_text_.empty() && text == header_text_) {
        h.on_reject("header line repeated", text, false);
        return;
      }
      h.on_reject(fields_[i].empty() ? "field " + std::to_string(i + 1) + " is empty"
                                     : "field " + std::to_string(i + 1) + " is not a number",
                  text, false);
      return;
    }
    if (!std::isfinite(v)) {
      h.on_reject("field " + std::to_string(i + 1) + " is not finite", text, false);
      return;
    }
  }
  if (delim_ == ',') {
    h.on_sample(text, values_);
    return;
  }
  joined_.clear();
  for (std::size_t i = 0; i < fields_.size(); ++i) {
    if (i > 0) joined_ += ',';
    joined_.append(fields_[i]);
  }
  h.on_sample(joined_, values_);
}

}  // namespace cubecal::acquire
