#include "detail/stable32_dat.hpp"

#include <charconv>
#include <cmath>
#include <string>

#include "cubecal/error.hpp"
#include "cubecal/printable_text.hpp"

namespace cubecal::io::detail {

namespace {

constexpr std::string_view kEnd = "# Header End";
// A header is looked for in the first lines only.
constexpr std::size_t kMaxHeaderLines = 64;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  return out;
}

// The number of a "Name: value" line, or an InputError at its place.
double number(std::string_view value, const std::string& file, std::size_t line, std::string_view name) {
  double v = 0.0;
  const auto [p, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  if (ec != std::errc() || p != value.data() + value.size() || !std::isfinite(v))
    throw InputError(
        file, line, 1,
        "Stable32 header: " + std::string(name) + " '" + printable_text(value) + "' is not a finite number",
        "correct the " + std::string(name) + ": line of the header");
  return v;
}

void take(Stable32Header& h, std::string_view name, std::string_view value, const std::string& file, std::size_t line) {
  const std::string key = lower(name);
  if (key == "type") {
    const std::string t = lower(value);
    if (t == "phase") {
      h.type = DataType::phase;
    } else if (t == "frequency" || t == "freq") {
      h.type = DataType::freq;
    } else {
      throw InputError(file, line, 1,
                       "Stable32 header: Type '" + printable_text(value) + "' is neither Phase nor Frequency",
                       "write Type: Phase or Type: Frequency");
    }
  } else if (key == "tau") {
    const double tau = number(value, file, line, name);
    if (!(tau > 0.0))
      throw InputError(file, line, 1, "Stable32 header: Tau " + printable_text(value) + " is not a positive interval",
                       "write the sampling interval in seconds");
    h.tau = tau;
  } else if (key == "points") {
    const double n = number(value, file, line, name);
    if (n < 0.0 || n != std::floor(n))
      throw InputError(file, line, 1, "Stable32 header: Points " + printable_text(value) + " is not a count",
                       "write the number of data points");
    h.points = static_cast<std::size_t>(n);
  } else if (key == "addend") {
    h.addend = number(value, file, line, name);
  } else if (key == "multiplier") {
    h.multiplier = number(value, file, line, name);
    if (h.multiplier == 0.0)
      throw InputError(file, line, 1, "Stable32 header: a Multiplier of 0 leaves no data",
                       "write Multiplier: 1 for the values as they are");
  }
  // File, Date, Tag Scale, Tag Offset and other names: descriptive.
}

}  // namespace

std::optional<Stable32Header> stable32_header(std::string_view text, const std::string& file) {
  if (!trim(text.substr(0, text.find('\n'))).starts_with("File:")) return std::nullopt;
  Stable32Header h;
  std::size_t pos = 0;
  for (std::size_t line = 1; line <= kMaxHeaderLines && pos < text.size(); ++line) {
    const std::size_t nl = text.find('\n', pos);
    const std::string_view raw = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? text.size() : nl + 1;
    const std::string_view l = trim(raw);
    if (l == kEnd) {
      h.lines = line;
      return h;
    }
    const std::size_t colon = l.find(':');
    if (colon == std::string_view::npos)
      throw InputError(file, line, 1,
                       "Stable32 header (it starts with File:): '" + printable_text(l) +
                           "' is neither a 'Name: value' line nor '# Header End'",
                       "end the header with a line '# Header End' before the data");
    take(h, trim(l.substr(0, colon)), trim(l.substr(colon + 1)), file, line);
  }
  throw InputError(file, 1, 1,
                   "Stable32 header (it starts with File:) without its '# Header End' line in the first " +
                       std::to_string(kMaxHeaderLines) + " lines",
                   "end the header with a line '# Header End' before the data");
}

}  // namespace cubecal::io::detail
