// Delimited-text reader.
//
// The file is read in two steps. A short sequential scan finds the layout
// (preamble, comments, delimiter, header, field count) and resolves the
// requested columns. The data rows are then split into one chunk per thread
// at line boundaries; every thread first counts its lines so that the final
// column arrays can be sized once, then parses its rows straight into its
// own slice of those arrays. Only selected fields are converted; the others
// are skipped but still counted. Error locations are computed lazily: a
// chunk just remembers where its first fault is and the line number is
// derived from the text (error path only).
#include "cubecal/io/delimited_reader.hpp"

#include <fast_float/fast_float.h>
#include <limits>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <optional>
#include <string>
#include <system_error>
#include <thread>
#include <utility>

#include "cubecal/error.hpp"
#include "cubecal/printable_text.hpp"
#include "detail/file_buffer.hpp"
#include "detail/file_table.hpp"
#include "detail/binary_input.hpp"
#include "detail/npy_reader.hpp"
#include "detail/plain_decimal.hpp"
#include "../detail/huge_pages.hpp"
#include "../detail/for_channels.hpp"

namespace cubecal::io {

namespace {

// Small files are not worth a thread: below this many bytes per chunk the
// thread start-up costs more than it saves.
constexpr std::size_t kMinChunkBytes = std::size_t{1} << 20;

// slot[] value of a field that is skipped.
constexpr std::size_t kNotParsed = static_cast<std::size_t>(-1);

// Longest field text quoted in an error message.
constexpr std::size_t kMaxQuoted = 40;

// --------------------------------------------------------------------------
// Lines and fields (shared by layout detection, the parser and locate()).

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// One physical line without its terminator and without the blanks around it
// (which also takes care of CRLF endings).
struct Line {
  const char* begin;
  const char* end;
  const char* next;  // start of the following line
  bool is_content() const { return begin != end && *begin != '#'; }
};

Line next_line(const char* p, const char* end) {
  const auto* nl = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
  const char* eol = nl != nullptr ? nl : end;
  const char* next = nl != nullptr ? nl + 1 : end;
  while (p < eol && is_blank(*p)) ++p;
  while (eol > p && is_blank(eol[-1])) --eol;
  return {p, eol, next};
}

char separator(Delimiter d) {
  switch (d) {
    case Delimiter::comma: return ',';
    case Delimiter::tab: return '\t';
    case Delimiter::semicolon: return ';';
    case Delimiter::whitespace: break;
  }
  return ' ';
}

// Padding allowed around a field ("1, 2"): blanks that are not the separator.
template <Delimiter D>
bool is_pad(char c) {
  if constexpr (D == Delimiter::tab)
    return c == ' ';
  else
    return c == ' ' || c == '\t';
}

bool is_pad(Delimiter d, char c) { return c == ' ' || (c == '\t' && d != Delimiter::tab); }

struct FieldSpan {
  const char* begin;  // first character after padding: the column reported
  const char* end;
};

// Splits a trimmed content line. The hot parser below implements the same
// rules inline; this version is for headers and error paths.
std::vector<FieldSpan> split_fields(const Line& line, Delimiter d) {
  std::vector<FieldSpan> out;
  const char* s = line.begin;
  const char* e = line.end;
  if (d == Delimiter::whitespace) {
    while (s < e) {
      const char* b = s;
      while (s < e && *s != ' ' && *s != '\t') ++s;
      out.push_back({b, s});
      while (s < e && (*s == ' ' || *s == '\t')) ++s;
    }
    return out;
  }
  const char sep = separator(d);
  for (;;) {
    const auto* hit = static_cast<const char*>(std::memchr(s, sep, static_cast<std::size_t>(e - s)));
    const char* stop = hit != nullptr ? hit : e;
    const char* b = s;
    while (b < stop && is_pad(d, *b)) ++b;
    const char* fe = stop;
    while (fe > b && is_pad(d, fe[-1])) --fe;
    out.push_back({b, fe});
    if (stop == e) break;
    s = stop + 1;
  }
  return out;
}

// --------------------------------------------------------------------------
// Numbers.

enum class Fault { none, non_numeric, empty, not_finite, out_of_range, field_count };

// Parses a number at `s` (no leading blanks). On success advances `s` past
// it; the caller checks what follows. fast_float is locale-free, exact
// (correctly rounded) and ~18 % faster here than libstdc++'s from_chars; it
// rejects a leading '+', which people and some loggers write, so that is
// stripped here.
inline Fault parse_number(const char*& s, const char* e, double& v) {
  const char* p = s;
  if (p < e && *p == '+') {
    ++p;
    if (p < e && *p == '-') return Fault::non_numeric;
  }
  const auto [ptr, ec] = fast_float::from_chars(p, e, v);
  if (ec == std::errc::invalid_argument) return Fault::non_numeric;
  if (ec == std::errc::result_out_of_range) return Fault::out_of_range;
  if (!std::isfinite(v)) {
    // fast_float returns +-inf for overflowing literals; "inf" and "nan" are
    // spelled with letters.
    const bool spelled = std::any_of(p, ptr, [](char c) { return c == 'i' || c == 'I' || c == 'n' || c == 'N'; });
    return spelled ? Fault::not_finite : Fault::out_of_range;
  }
  s = ptr;
  return Fault::none;
}

// Header detection: a field that no reading could take for a number (a
// NaN, an empty or an overflowing field is a bad value, not a name).
bool is_name(const FieldSpan& f) {
  if (f.begin == f.end) return false;
  const char* s = f.begin;
  double v = 0;
  const Fault fault = parse_number(s, f.end, v);
  if (fault == Fault::non_numeric) return true;
  return fault == Fault::none && s != f.end;
}

// --------------------------------------------------------------------------
// Layout: everything before the first data row.

struct Layout {
  Delimiter delimiter = Delimiter::comma;
  bool has_header = false;
  std::vector<std::string> header;
  std::size_t total_columns = 0;
  std::size_t header_line = 0;      // 0 without header
  std::size_t first_data_line = 0;  // 1-based
  std::size_t body_offset = 0;      // byte offset of the first data row
  std::size_t text_offset = 0;      // bytes of the file before the text parsed (a byte-order mark)
};

// Spreadsheet programs start UTF-8 CSV files with a byte-order mark; it
// would otherwise end up in the first column name.
std::string_view strip_bom(std::string_view text) {
  if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.remove_prefix(3);
  return text;
}

// A column name as every face shows it: control bytes and bytes that are not
// UTF-8 written as \xNN (printable_text), so that no writer (JSON, CSV, a
// table, a Python str) meets them.
std::string header_name(const FieldSpan& f) {
  std::string_view s(f.begin, static_cast<std::size_t>(f.end - f.begin));
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return printable_text(s);
}

Delimiter detect_delimiter(const Line& line) {
  const std::string_view s(line.begin, static_cast<std::size_t>(line.end - line.begin));
  if (s.find(',') != std::string_view::npos) return Delimiter::comma;
  if (s.find('\t') != std::string_view::npos) return Delimiter::tab;
  if (s.find(';') != std::string_view::npos) return Delimiter::semicolon;
  return Delimiter::whitespace;
}

[[noreturn]] void throw_no_rows(const std::string& file, std::string why) {
  throw InputError(file, 0, 0, "no data rows: " + std::move(why),
                   "check the file name and the number of preamble rows to skip");
}

Layout detect_layout(std::string_view text, const std::string& file, std::size_t skip_rows) {
  const char* p = text.data();
  const char* const end = p + text.size();
  if (p == end) throw_no_rows(file, "the file is empty");

  std::size_t line_no = 0;
  for (; line_no < skip_rows; ++line_no) {
    if (p == end) {
      throw_no_rows(
          file, "the file has " + std::to_string(line_no) + " lines and " + std::to_string(skip_rows) + " are skipped");
    }
    p = next_line(p, end).next;
  }

  Layout lay;
  Line first{};
  for (;;) {
    if (p == end) throw_no_rows(file, "only comments and blank lines");
    first = next_line(p, end);
    ++line_no;
    p = first.next;
    if (first.is_content()) break;
  }

  lay.delimiter = detect_delimiter(first);
  const std::vector<FieldSpan> fields = split_fields(first, lay.delimiter);
  lay.total_columns = fields.size();
  // A header holds names only: a line mixing numbers and words is a data
  // row with a bad field (reported there), not a header that would silently
  // swallow the first sample.
  const bool any_number =
      std::any_of(fields.begin(), fields.end(), [](const FieldSpan& f) { return f.begin != f.end && !is_name(f); });
  lay.has_header = !any_number && std::any_of(fields.begin(), fields.end(), is_name);
  if (!lay.has_header) {
    lay.first_data_line = line_no;
    lay.body_offset = static_cast<std::size_t>(first.begin - text.data());
    return lay;
  }

  lay.header_line = line_no;
  for (const FieldSpan& f : fields) lay.header.push_back(header_name(f));
  for (;;) {
    if (p == end) {
      throw_no_rows(file, "nothing after the header on line " + std::to_string(lay.header_line));
    }
    const Line line = next_line(p, end);
    ++line_no;
    if (line.is_content()) {
      lay.first_data_line = line_no;
      lay.body_offset = static_cast<std::size_t>(p - text.data());
      return lay;
    }
    p = line.next;
  }
}

// --------------------------------------------------------------------------
// Column selection.

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           const auto lower = [](char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; };
           return lower(x) == lower(y);
         });
}

std::string column_list(const std::vector<std::string>& header) {
  constexpr std::size_t kMaxListed = 24;
  std::string s;
  for (std::size_t i = 0; i < header.size() && i < kMaxListed; ++i) {
    if (i != 0) s += ", ";
    s += header[i];
  }
  if (header.size() > kMaxListed) s += ", ...";
  return s;
}

// Name (exact, then ignoring case) or 1-based index -> 0-based field index.
// A name is compared as the header shows it (header_name): with the raw
// bytes of a malformed name or with their \xNN escapes.
std::size_t resolve_column(const std::string& raw_spec, const Layout& lay, const std::string& file) {
  const std::vector<std::string>& h = lay.header;
  const std::string spec = printable_text(raw_spec);
  if (auto it = std::find(h.begin(), h.end(), spec); it != h.end()) {
    return static_cast<std::size_t>(it - h.begin());
  }
  // An error about a column points at the header, or at the first data
  // row (where the field count comes from) when there is none.
  const std::size_t line = lay.has_header ? lay.header_line : lay.first_data_line;
  const bool numeric =
      !spec.empty() && std::all_of(spec.begin(), spec.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (numeric) {
    std::size_t k = 0;
    const auto [ptr, ec] = std::from_chars(spec.data(), spec.data() + spec.size(), k);
    if (ec == std::errc{} && ptr == spec.data() + spec.size() && k >= 1 && k <= lay.total_columns) return k - 1;
    throw InputError(file, line, 1, "column index " + spec + " out of range",
                     "the file has " + std::to_string(lay.total_columns) + " columns; use 1 to " +
                         std::to_string(lay.total_columns));
  }
  if (!lay.has_header) {
    throw InputError(file, line, 1, "column '" + spec + "' given by name but the file has no header line",
                     "use 1-based column indices, 1 to " + std::to_string(lay.total_columns));
  }
  if (auto it = std::find_if(h.begin(), h.end(), [&](const std::string& n) { return iequals(n, spec); });
      it != h.end()) {
    return static_cast<std::size_t>(it - h.begin());
  }
  throw InputError(file, line, 1, "unknown column '" + spec + "'", "columns are: " + column_list(h));
}

std::string column_name(const Layout& lay, std::size_t index) {
  return lay.has_header ? lay.header[index] : "col" + std::to_string(index + 1);
}

// --------------------------------------------------------------------------
// Parallel parsing.

struct ChunkResult {
  std::size_t rows = 0;
  Fault fault = Fault::none;
  const char* where = nullptr;  // start of the offending field (or end of a short row)
  std::size_t field = 0;        // 0-based field index of the fault
};

// One row of plain numbers at p: its values stored at dst[field][row], and
// the start of the next row returned; null where the row is anything else
// (the caller then parses it by the general rules). Separated fields only.
template <Delimiter D>
inline const char* fast_row(const char* p, const char* end, std::size_t total_columns, double* const* dst,
                            std::size_t row) {
  constexpr char sep = D == Delimiter::comma ? ',' : D == Delimiter::tab ? '\t' : ';';
  // A blank or comment line, or leading padding: the general path's.
  if (*p == '\n' || *p == '\r' || *p == '#' || *p == ' ' || *p == '\t') return nullptr;
  const char* s = p;
  for (std::size_t f = 0; f < total_columns; ++f) {
    if (double* out = dst[f]) {
      double v;
      if (const char* q = detail::plain_decimal(s, end, v)) {
        s = q;
      } else {
        const auto [ptr, ec] = fast_float::from_chars(s, end, v);
        if (ec != std::errc() || ptr == s || !std::isfinite(v)) return nullptr;
        s = ptr;
      }
      out[row] = v;
    } else {
      while (s < end && *s != sep && *s != '\n') ++s;
    }
    const bool last = f + 1 == total_columns;
    if (s == end) return last && s != p ? s : nullptr;
    if (*s != (last ? '\n' : sep)) return nullptr;
    ++s;
  }
  return s;
}

// Parses the rows in [p, end) into dst[field][row] (dst[field] is null for
// fields not selected). Stops at the first fault.
template <Delimiter D>
void parse_chunk(const char* p, const char* end, std::size_t total_columns, double* const* dst, ChunkResult& r,
                 bool missing_as_nan) {
  constexpr bool ws = D == Delimiter::whitespace;
  constexpr char sep = D == Delimiter::comma ? ',' : D == Delimiter::tab ? '\t' : ';';
  const auto fail = [&r](Fault f, const char* where, std::size_t field) {
    r.fault = f;
    r.where = where;
    r.field = field;
  };

  std::size_t row = 0;
  while (p < end) {
    if constexpr (!ws) {
      // The common row first: every field a plain number, the separator
      // right after it, '\n' after the last. Parsed straight from the
      // bytes, without finding the line's end beforehand; anything else
      // (padding, a comment or blank line, CRLF, an empty, non-numeric or
      // non-finite field, a short or long row) leaves this row to the
      // general path below, from its first byte, which reads it by the same
      // rules and says what is wrong (values written here for the row are
      // written again there).
      if (const char* next = fast_row<D>(p, end, total_columns, dst, row)) {
        p = next;
        ++row;
        continue;
      }
    }
    const Line line = next_line(p, end);
    p = line.next;
    if (!line.is_content()) continue;

    const char* s = line.begin;
    const char* const e = line.end;
    std::size_t f = 0;  // index of the current field = fields seen so far
    for (;;) {
      if constexpr (!ws) {
        while (s < e && is_pad<D>(*s)) ++s;
      }
      if (f == total_columns) return fail(Fault::field_count, s, f);
      if (double* out = dst[f]) {
        const char* q = s;
        double v;
        bool empty = false;
        if constexpr (!ws) empty = s == e || *s == sep;
        if (empty) {
          if (!missing_as_nan) return fail(Fault::empty, s, f);
          v = std::numeric_limits<double>::quiet_NaN();  // a missing sample (TableOptions::missing_as_nan)
        } else if (const Fault fault = parse_number(q, e, v); fault != Fault::none) {
          // NaN spelled out is a missing sample too when asked; infinities never are.
          if (!(fault == Fault::not_finite && missing_as_nan && std::isnan(v))) return fail(fault, s, f);
          q = fast_float::from_chars(s + (*s == '+' ? 1 : 0), e, v).ptr;  // past the NaN; what follows is checked below
          v = std::numeric_limits<double>::quiet_NaN();
        }
        if constexpr (ws) {
          if (q < e && *q != ' ' && *q != '\t') return fail(Fault::non_numeric, s, f);
        } else {
          while (q < e && is_pad<D>(*q)) ++q;
          if (q < e && *q != sep) return fail(Fault::non_numeric, s, f);
        }
        out[row] = v;
        s = q;
      } else if constexpr (ws) {
        while (s < e && *s != ' ' && *s != '\t') ++s;
      } else {
        while (s < e && *s != sep) ++s;
      }
      ++f;
      if constexpr (ws) {
        while (s < e && (*s == ' ' || *s == '\t')) ++s;
        if (s == e) break;
      } else {
        if (s == e) break;
        ++s;  // past the separator
      }
    }
    if (f != total_columns) return fail(Fault::field_count, e, f);
    ++row;
  }
  r.rows = row;
}

using ChunkParser = void (*)(const char*, const char*, std::size_t, double* const*, ChunkResult&, bool);

ChunkParser chunk_parser(Delimiter d) {
  switch (d) {
    case Delimiter::comma: return parse_chunk<Delimiter::comma>;
    case Delimiter::tab: return parse_chunk<Delimiter::tab>;
    case Delimiter::semicolon: return parse_chunk<Delimiter::semicolon>;
    case Delimiter::whitespace: break;
  }
  return parse_chunk<Delimiter::whitespace>;
}

// Runs job(0..n-1), job(0) on the calling thread. Jobs must not throw.
template <class Job>
void run_parallel(std::size_t n, const Job& job) {
  std::vector<std::jthread> pool;
  pool.reserve(n - 1);
  for (std::size_t k = 1; k < n; ++k) pool.emplace_back([&job, k] { job(k); });
  job(0);
}

// Cuts [begin, end) into n pieces that each end just after a newline.
std::vector<const char*> chunk_bounds(const char* begin, const char* end, std::size_t n) {
  std::vector<const char*> b{begin};
  const auto size = static_cast<std::size_t>(end - begin);
  for (std::size_t k = 1; k < n; ++k) {
    const char* target = std::max(begin + size / n * k, b.back());
    const auto* nl = static_cast<const char*>(std::memchr(target, '\n', static_cast<std::size_t>(end - target)));
    b.push_back(nl != nullptr ? nl + 1 : end);
  }
  b.push_back(end);
  return b;
}

// A branch-free count that the compiler vectorises (a memchr call per
// line costs a call per 50-100 bytes).
std::size_t count_newlines(const char* p, const char* end) {
  std::size_t n = 0;
  while (p < end) {
    // Blocks of at most 255 bytes: the per-lane byte counters cannot wrap.
    const char* stop = p + std::min<std::ptrdiff_t>(end - p, 255);
    unsigned char block = 0;
    for (; p < stop; ++p) block = static_cast<unsigned char>(block + (*p == '\n'));
    n += block;
  }
  return n;
}

// A thread walks its chunk of a mapped file a window at a time: the window's
// pages are mapped in one call ahead of the work and dropped behind it, so
// that the file's pages never all sit in the process's memory at once (a
// 200 MB record would otherwise add 200 MB to the peak, beside the parsed
// columns). Windows end just after a newline, as chunks do, past a multiple
// of 2 MiB in the file's address space: the kernel can map whole huge pages
// of the page cache, whose TLB entries make the scan as fast as over a file
// mapped at once, and no huge page is split by a release in its middle.
constexpr std::size_t kWindowBytes = std::size_t{4} << 20;
// The line count's read size (a copy per thread; fits the L2 cache).
constexpr std::size_t kCopyBytes = std::size_t{256} << 10;
constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;

const char* huge_floor(const char* p) { return p - reinterpret_cast<std::uintptr_t>(p) % kHugePage; }

template <class Work>
void windowed(const char* b, const char* const e, const FileBuffer* pages, const Work& work) {
  const char* released = huge_floor(b);  // what lies before this is dropped (or another thread's)
  while (b < e) {
    const char* w = e;
    if (static_cast<std::size_t>(e - b) > kWindowBytes) {
      const char* target = huge_floor(b + kWindowBytes);
      if (target <= b) target = b + kWindowBytes;
      const auto* nl = static_cast<const char*>(std::memchr(target, '\n', static_cast<std::size_t>(e - target)));
      w = nl != nullptr ? nl + 1 : e;
    }
    if (pages != nullptr) {
      const char* from = huge_floor(b);
      const char* to = huge_floor(w - 1) + kHugePage;  // whole huge pages (clipped to the file by populate)
      pages->populate(std::string_view(from, static_cast<std::size_t>(to - from)));
    }
    const bool more = work(b, w);
    if (pages != nullptr && huge_floor(w) > released) {
      // The whole huge pages behind the window: the one holding w is the
      // next window's (or the next thread's) first.
      pages->release(std::string_view(released, static_cast<std::size_t>(huge_floor(w) - released)));
      released = huge_floor(w);
    }
    if (!more) return;
    b = w;
  }
}

// --------------------------------------------------------------------------
// Error reporting (cold).

struct Position {
  std::size_t line;
  std::size_t column;
  const char* line_begin;
};

// 1-based character column of `where` in the line starting at `line_begin`.
// Columns count UTF-8 code points so that they match what an editor shows.
std::size_t column_in_line(const char* line_begin, const char* where) {
  std::size_t column = 1;
  for (const char* c = line_begin; c < where; ++c) {
    if ((static_cast<unsigned char>(*c) & 0xC0) != 0x80) ++column;
  }
  return column;
}

// 1-based line and column of `where` in `text`.
Position position_of(std::string_view text, const char* where) {
  Position pos{1, 1, text.data()};
  for (const char* c = text.data(); c < where; ++c) {
    if (*c == '\n') {
      ++pos.line;
      pos.line_begin = c + 1;
    }
  }
  pos.column = column_in_line(pos.line_begin, where);
  return pos;
}

std::string quoted_field(const char* b, const char* e) {
  std::string s(b, std::min(static_cast<std::size_t>(e - b), kMaxQuoted));
  if (static_cast<std::size_t>(e - b) > kMaxQuoted) s += "...";
  return "'" + s + "'";
}

std::string column_label(const Layout& lay, std::size_t field) {
  std::string s = "column " + std::to_string(field + 1);
  if (lay.has_header) s += " '" + lay.header[field] + "'";
  return s;
}

// Where the table seems to start when a fault sits in its first rows: the
// number of physical lines before the first content line that is a header
// (names only) or a row of numbers, followed by a row of numbers with as many
// fields. nullopt when the first lines show no such start.
std::optional<std::size_t> table_start(std::string_view text) {
  constexpr std::size_t kScannedLines = 200;
  struct Row {
    std::size_t line;  // 0-based physical line
    std::size_t fields;
    bool names;    // every field a name (a header)
    bool numbers;  // every field a number
  };
  std::vector<Row> rows;
  const char* p = text.data();
  const char* const end = p + text.size();
  for (std::size_t n = 0; p != end && n < kScannedLines; ++n) {
    const Line line = next_line(p, end);
    p = line.next;
    if (!line.is_content()) continue;
    const std::vector<FieldSpan> fields = split_fields(line, detect_delimiter(line));
    bool names = true, numbers = true;
    for (const FieldSpan& f : fields) {
      const bool name = is_name(f);
      names = names && name;
      const char* c = f.begin;
      double v = 0;
      numbers = numbers && f.begin != f.end && parse_number(c, f.end, v) == Fault::none && c == f.end;
    }
    rows.push_back({n, fields.size(), names, numbers});
  }
  for (std::size_t i = 0; i + 1 < rows.size(); ++i)
    if ((rows[i].names || rows[i].numbers) && rows[i + 1].numbers && rows[i + 1].fields == rows[i].fields &&
        rows[i].fields > 1)
      return rows[i].line;
  return std::nullopt;
}

// " (a preamble of N lines: add {skip_rows} N)" when the table seems to start
// after line `first_data_line` was taken for its first row; else empty.
std::string preamble_hint(std::string_view text, const Layout& lay) {
  const auto start = table_start(text);
  const std::size_t first_row = lay.has_header ? lay.header_line : lay.first_data_line;  // 1-based
  if (!start || *start + 1 <= first_row) return {};
  return "the table seems to start on line " + std::to_string(*start + 1) + " after a preamble: add {skip_rows} " +
         std::to_string(*start);
}

[[noreturn]] void throw_fault(std::string_view text, const std::string& file, const Layout& lay, const ChunkResult& r) {
  const Position pos = position_of(text, r.where);
  const char* const text_end = text.data() + text.size();
  const Line line = next_line(pos.line_begin, text_end);
  // A binary byte anywhere in the row (the fault is where it broke the
  // parse, or its field count) says more than the fault, and is not echoed.
  if (const char* b = detail::find_binary_byte(pos.line_begin, line.end)) {
    detail::throw_binary_byte(text, b, file, pos.line, column_in_line(pos.line_begin, b), lay.text_offset);
  }

  if (r.fault == Fault::field_count) {
    const std::size_t found = split_fields(line, lay.delimiter).size();
    const std::string expected = std::to_string(lay.total_columns);
    const std::string preamble = preamble_hint(text, lay);
    throw InputError(file, pos.line, pos.column, "row has " + std::to_string(found) + " fields, expected " + expected,
                     !preamble.empty() ? preamble
                     : lay.has_header
                         ? "header has " + expected
                         : "the first data row, line " + std::to_string(lay.first_data_line) + ", has " + expected);
  }

  const std::vector<FieldSpan> fields = split_fields(line, lay.delimiter);
  const FieldSpan field = r.field < fields.size() ? fields[r.field] : FieldSpan{r.where, r.where};
  const std::string label = column_label(lay, r.field);
  const std::string text_of_field = quoted_field(field.begin, field.end);

  switch (r.fault) {
    case Fault::empty:
      throw InputError(file, pos.line, pos.column, "empty field in " + label,
                       "a missing sample: {gaps} skip leaves it out of the OADEV terms (dev, davar); otherwise "
                       "fill or remove the row");
    case Fault::not_finite: {
      const char* c = field.begin;
      while (c < field.end && (*c == '+' || *c == '-')) ++c;
      if (c < field.end && (*c == 'n' || *c == 'N')) {
        throw InputError(file, pos.line, pos.column, "NaN is not accepted in " + label,
                         "a missing sample: {gaps} skip leaves it out of the OADEV terms (dev, davar); otherwise "
                         "remove the row or split the record there");
      }
      throw InputError(file, pos.line, pos.column, "infinite value " + text_of_field + " in " + label,
                       "remove the row or split the record there");
    }
    case Fault::out_of_range:
      throw InputError(file, pos.line, pos.column, "value " + text_of_field + " out of range in " + label,
                       "values must fit in a double; fix or remove the row");
    default: break;
  }

  std::string hint = "fix the row, remove it or comment it out with '#'";
  const std::string_view f(field.begin, static_cast<std::size_t>(field.end - field.begin));
  if (lay.delimiter != Delimiter::comma && f.find(',') != std::string_view::npos) {
    hint = "decimal commas are not accepted; write numbers with a '.'";
  } else if (const std::string preamble = preamble_hint(text, lay); !preamble.empty()) {
    hint = preamble;
  } else if (pos.line == lay.first_data_line) {
    hint += "; a preamble before the header can be skipped with {skip_rows} N";
  }
  throw InputError(file, pos.line, pos.column, "non-numeric field " + text_of_field + " in " + label, hint);
}

// Parses the data rows of `text` in parallel. slot[field] is the index of
// the output column for that field, or kNotParsed.
std::vector<std::vector<double>> parse_rows(std::string_view text, const std::string& file, const Layout& lay,
                                            const std::vector<std::size_t>& slot, std::size_t n_columns,
                                            unsigned threads, const FileBuffer* pages, bool missing_as_nan) {
  // Chunks: one per thread, but none smaller than kMinChunkBytes.
  const char* const body = text.data() + lay.body_offset;
  const char* const end = text.data() + text.size();
  const std::size_t workers = threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
  const std::size_t n_chunks =
      std::clamp<std::size_t>(static_cast<std::size_t>(end - body) / kMinChunkBytes, 1, workers);
  const std::vector<const char*> bounds = chunk_bounds(body, end, n_chunks);

  // Every line may be a row: size the arrays for the line count, then
  // squeeze out what comments and blank lines left unused.
  std::vector<std::size_t> offset(n_chunks + 1, 0);
  run_parallel(n_chunks, [&](std::size_t k) {
    // A mapped file's lines are counted in copies of its bytes: mapping the
    // pages here, dropping them and mapping them again for the parse costs
    // more than reading them.
    std::size_t nl = 0;
    std::vector<char> copy(pages != nullptr ? kCopyBytes : 0);
    for (const char* b = bounds[k]; b < bounds[k + 1];) {
      const std::size_t len = std::min(kCopyBytes, static_cast<std::size_t>(bounds[k + 1] - b));
      const bool copied = pages != nullptr && pages->copy(std::string_view(b, len), copy.data());
      nl += copied ? count_newlines(copy.data(), copy.data() + len) : count_newlines(b, b + len);
      b += len;
    }
    const bool unterminated = bounds[k + 1] > bounds[k] && bounds[k + 1][-1] != '\n';
    offset[k + 1] = nl + (unterminated ? 1 : 0);
  });
  for (std::size_t k = 0; k < n_chunks; ++k) offset[k + 1] += offset[k];

  // Zero-filling the fresh arrays is mostly page faults: share them out.
  std::vector<std::vector<double>> columns(n_columns);
  cubecal::detail::ItemErrors alloc_failure(n_chunks);
  run_parallel(n_chunks, [&](std::size_t k) {
    alloc_failure.run(k, [&](std::size_t) {
      for (std::size_t c = k; c < columns.size(); c += n_chunks) {
        columns[c].reserve(offset[n_chunks]);
        cubecal::detail::advise_huge_pages(columns[c].data(), offset[n_chunks] * sizeof(double));
        columns[c].resize(offset[n_chunks]);
      }
    });
  });
  alloc_failure.rethrow_first();

  // Per chunk and field: where row 0 of the chunk goes (null: skipped).
  std::vector<std::vector<double*>> dst(n_chunks, std::vector<double*>(lay.total_columns, nullptr));
  for (std::size_t k = 0; k < n_chunks; ++k) {
    for (std::size_t i = 0; i < lay.total_columns; ++i) {
      if (slot[i] != kNotParsed) dst[k][i] = columns[slot[i]].data() + offset[k];
    }
  }
  const ChunkParser parser = chunk_parser(lay.delimiter);
  std::vector<ChunkResult> results(n_chunks);
  run_parallel(n_chunks, [&](std::size_t k) {
    std::vector<double*> out = dst[k];
    ChunkResult& r = results[k];
    windowed(bounds[k], bounds[k + 1], pages, [&](const char* b, const char* e) {
      ChunkResult w;
      parser(b, e, lay.total_columns, out.data(), w, missing_as_nan);
      r.rows += w.rows;
      for (double*& o : out)
        if (o != nullptr) o += w.rows;
      if (w.fault == Fault::none) return true;
      r.fault = w.fault;
      r.where = w.where;
      r.field = w.field;
      return false;
    });
  });
  for (const ChunkResult& r : results) {
    if (r.fault != Fault::none) throw_fault(text, file, lay, r);
  }

  std::size_t rows = results[0].rows;
  for (std::size_t k = 1; k < n_chunks; ++k) {
    if (offset[k] != rows) {
      for (auto& c : columns) {
        std::memmove(c.data() + rows, c.data() + offset[k], results[k].rows * sizeof(double));
      }
    }
    rows += results[k].rows;
  }
  for (auto& c : columns) c.resize(rows);
  return columns;
}

Table table_from_layout(const Layout& lay, const std::string& file, const TableOptions& opt, std::size_t bytes) {
  Table t;
  t.file = file;
  t.delimiter = lay.delimiter;
  t.has_header = lay.has_header;
  t.header = lay.header;
  t.total_columns = lay.total_columns;
  t.first_data_line = lay.first_data_line;
  t.options = opt;
  t.bytes = bytes;
  return t;
}

}  // namespace

Table parse_layout(std::string_view text, const std::string& file_label, const TableOptions& opt) {
  detail::check_text_start(text, file_label, false);
  const std::string_view body = strip_bom(text);
  return table_from_layout(detect_layout(body, file_label, opt.skip_rows), file_label, opt, text.size());
}

namespace {

Table parse_text(std::string_view text, const std::string& file_label, const TableOptions& opt,
                 const FileBuffer* pages) {
  const std::size_t bytes = text.size();
  detail::check_text_start(text, file_label, false);
  text = strip_bom(text);
  Layout lay = detect_layout(text, file_label, opt.skip_rows);
  lay.text_offset = bytes - text.size();
  Table t = table_from_layout(lay, file_label, opt, bytes);

  std::vector<std::size_t>& extra_idx = t.extra_indices;
  for (const std::string& spec : opt.extra_columns) extra_idx.push_back(resolve_column(spec, lay, file_label));
  if (opt.columns.empty()) {
    for (std::size_t i = 0; i < lay.total_columns; ++i) {
      if (std::find(extra_idx.begin(), extra_idx.end(), i) == extra_idx.end()) t.indices.push_back(i);
    }
  } else {
    for (const std::string& spec : opt.columns) t.indices.push_back(resolve_column(spec, lay, file_label));
  }
  for (std::size_t i : t.indices) t.names.push_back(column_name(lay, i));
  for (std::size_t i : extra_idx) t.extra_names.push_back(column_name(lay, i));

  // A field asked for twice is parsed once and copied.
  std::vector<std::size_t> slot(lay.total_columns, kNotParsed);
  std::vector<std::size_t> uses;
  for (const auto* list : {&t.indices, &extra_idx}) {
    for (std::size_t i : *list) {
      if (slot[i] == kNotParsed) {
        slot[i] = uses.size();
        uses.push_back(0);
      }
      ++uses[slot[i]];
    }
  }
  std::vector<std::vector<double>> columns =
      parse_rows(text, file_label, lay, slot, uses.size(), opt.threads, pages, opt.missing_as_nan);
  const auto take = [&](std::size_t field) -> std::vector<double> {
    const std::size_t s = slot[field];
    if (--uses[s] == 0) return std::move(columns[s]);
    return columns[s];
  };
  for (std::size_t i : t.indices) t.data.push_back(take(i));
  for (std::size_t i : extra_idx) t.extra.push_back(take(i));
  return t;
}

}  // namespace

Table parse_table(std::string_view text, const std::string& file_label, const TableOptions& opt) {
  return parse_text(text, file_label, opt, nullptr);
}

Table parse_table(const FileBuffer& buf, const TableOptions& opt) {
  return parse_text(buf.view(), buf.path(), opt, &buf);
}

Table select_columns(Table all, const TableOptions& opt) {
  Layout lay;
  lay.has_header = all.has_header;
  lay.header = all.header;
  lay.total_columns = all.total_columns;
  lay.first_data_line = all.first_data_line;
  Table t = std::move(all);
  std::vector<std::vector<double>> columns = std::move(t.data);
  t.data.clear();
  t.names.clear();
  t.indices.clear();
  t.extra.clear();
  t.extra_names.clear();
  t.extra_indices.clear();
  t.options = opt;
  for (const std::string& spec : opt.extra_columns) t.extra_indices.push_back(resolve_column(spec, lay, t.file));
  if (opt.columns.empty()) {
    for (std::size_t i = 0; i < lay.total_columns; ++i) {
      if (std::find(t.extra_indices.begin(), t.extra_indices.end(), i) == t.extra_indices.end()) t.indices.push_back(i);
    }
  } else {
    for (const std::string& spec : opt.columns) t.indices.push_back(resolve_column(spec, lay, t.file));
  }
  // A column asked for twice is copied; otherwise moved.
  std::vector<std::size_t> uses(columns.size(), 0);
  for (std::size_t i : t.indices) ++uses[i];
  for (std::size_t i : t.extra_indices) ++uses[i];
  const auto take = [&](std::size_t i) -> std::vector<double> {
    if (--uses[i] == 0) return std::move(columns[i]);
    return columns[i];
  };
  for (std::size_t i : t.indices) {
    t.names.push_back(column_name(lay, i));
    t.data.push_back(take(i));
  }
  for (std::size_t i : t.extra_indices) {
    t.extra_names.push_back(column_name(lay, i));
    t.extra.push_back(take(i));
  }
  return t;
}

Table read_table(const std::string& path, const TableOptions& opt) {
  // A .npy is read as the error for the other binary formats says it is
  // (calibrate's logs included); those are refused by parse_table's check.
  const FileBuffer buf = FileBuffer::open(path, Content::series);
  if (is_npy(buf.view())) return select_columns(read_npy(buf.view(), buf.path(), opt.missing_as_nan), opt);
  return parse_table(buf, opt);
}

Location locate(const Table& t, std::size_t row, std::size_t field) {
  // The file may have gone or changed since it was parsed; an unknown
  // location only shortens the message, so that is not an error here.
  if (t.binary) return {row + 1, field + 1};
  if (t.file == kStdinLabel) return {};
  std::optional<FileBuffer> buf;
  try {
    buf.emplace(FileBuffer::open(t.file));
  } catch (const InputError&) {
    return {};
  }
  const std::string_view text = strip_bom(buf->view());
  const char* p = text.data();
  const char* const end = p + text.size();
  std::size_t line_no = 1;
  for (; line_no < t.first_data_line && p < end; ++line_no) p = next_line(p, end).next;
  for (std::size_t r = 0; p < end; ++line_no) {
    const Line line = next_line(p, end);
    if (line.is_content() && r++ == row) {
      const std::vector<FieldSpan> fields = split_fields(line, t.delimiter);
      return {line_no, field < fields.size() ? column_in_line(p, fields[field].begin) : 0};
    }
    p = line.next;
  }
  return {};
}

}  // namespace cubecal::io
