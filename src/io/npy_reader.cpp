#include "detail/npy_reader.hpp"

#include <bit>
#include <charconv>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "cubecal/error.hpp"
#include "detail/binary_table.hpp"

namespace cubecal::io {

namespace {

constexpr std::string_view kMagic("\x93NUMPY", 6);
constexpr const char* kWrite = "write a 1-D or 2-D array of numbers with numpy.save";

// The header: a Python dict literal of 'descr', 'fortran_order' and 'shape'
// (what numpy.lib.format writes), read by a small parser that says where it
// stopped understanding.
class HeaderParser {
 public:
  HeaderParser(std::string_view text, std::size_t base, const std::string& file) : s_(text), base_(base), file_(file) {}

  struct Header {
    std::string descr;
    std::optional<bool> fortran_order;
    std::optional<std::vector<std::size_t>> shape;
    bool has_descr = false;
  };

  Header parse() {
    Header h;
    expect('{');
    for (;;) {
      skip_space();
      if (peek() == '}') break;
      const std::size_t key_at = i_;
      const std::string key = string_literal();
      expect(':');
      skip_space();
      if (key == "descr") {
        if (peek() != '\'' && peek() != '"') fail(i_, "a structured type (a record of fields) is not supported");
        h.descr = string_literal();
        h.has_descr = true;
      } else if (key == "fortran_order") {
        h.fortran_order = boolean();
      } else if (key == "shape") {
        h.shape = tuple();
      } else {
        fail(key_at, "unknown header key '" + key + "'");
      }
      skip_space();
      if (peek() == ',') {
        ++i_;
        continue;
      }
      skip_space();
      if (peek() != '}') fail(i_, "',' or '}' expected in the header");
      break;
    }
    if (!h.has_descr || !h.fortran_order || !h.shape) fail(0, "the header lacks 'descr', 'fortran_order' or 'shape'");
    return h;
  }

  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    throw InputError(file_, 0, 0, "NumPy header, byte offset " + std::to_string(base_ + at) + ": " + what, kWrite);
  }

 private:
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  void skip_space() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\t' || s_[i_] == '\r')) ++i_;
  }
  void expect(char c) {
    skip_space();
    if (peek() != c) fail(i_, std::string("'") + c + "' expected");
    ++i_;
  }
  std::string string_literal() {
    skip_space();
    const char q = peek();
    if (q != '\'' && q != '"') fail(i_, "a quoted name expected");
    const std::size_t end = s_.find(q, i_ + 1);
    if (end == std::string_view::npos) fail(i_, "unterminated string");
    std::string r(s_.substr(i_ + 1, end - i_ - 1));
    i_ = end + 1;
    return r;
  }
  bool boolean() {
    if (s_.substr(i_, 4) == "True") {
      i_ += 4;
      return true;
    }
    if (s_.substr(i_, 5) == "False") {
      i_ += 5;
      return false;
    }
    fail(i_, "True or False expected");
  }
  std::vector<std::size_t> tuple() {
    std::vector<std::size_t> v;
    expect('(');
    for (;;) {
      skip_space();
      if (peek() == ')') {
        ++i_;
        return v;
      }
      std::size_t n = 0;
      const auto [p, ec] = std::from_chars(s_.data() + i_, s_.data() + s_.size(), n);
      if (ec != std::errc() || p == s_.data() + i_) fail(i_, "a dimension (a whole number) expected");
      i_ = static_cast<std::size_t>(p - s_.data());
      v.push_back(n);
      skip_space();
      if (peek() == ',')
        ++i_;
      else if (peek() != ')')
        fail(i_, "',' or ')' expected in the shape");
    }
  }

  std::string_view s_;
  std::size_t i_ = 0;
  std::size_t base_;
  const std::string& file_;
};

// '<f8', '>i2', '|u1', '=f4' -> the sample type, or nullopt.
std::optional<SampleType> npy_type(const std::string& descr) {
  if (descr.size() < 3) return std::nullopt;
  const char order = descr[0];
  if (order != '<' && order != '>' && order != '|' && order != '=') return std::nullopt;
  std::size_t bytes = 0;
  const auto [p, ec] = std::from_chars(descr.data() + 2, descr.data() + descr.size(), bytes);
  if (ec != std::errc() || p != descr.data() + descr.size()) return std::nullopt;
  SampleType t;
  t.bytes = bytes;
  t.big_endian = order == '>' || (order == '=' && std::endian::native == std::endian::big);
  switch (descr[1]) {
    case 'f':
      t.kind = SampleKind::floating;
      if (bytes != 4 && bytes != 8) return std::nullopt;
      break;
    case 'i':
      t.kind = SampleKind::signed_int;
      if (bytes != 1 && bytes != 2 && bytes != 4 && bytes != 8) return std::nullopt;
      break;
    case 'u':
      t.kind = SampleKind::unsigned_int;
      if (bytes != 1 && bytes != 2 && bytes != 4 && bytes != 8) return std::nullopt;
      break;
    default: return std::nullopt;
  }
  if (bytes > 1 && order == '|') return std::nullopt;
  return t;
}

std::string shape_text(const std::vector<std::size_t>& shape) {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + (shape.size() == 1 ? ",)" : ")");
}

}  // namespace

bool is_npy(std::string_view bytes) noexcept { return bytes.substr(0, kMagic.size()) == kMagic; }

std::size_t npy_data_offset(std::string_view bytes, const std::string& file) {
  const auto fail = [&](std::size_t offset, const std::string& what) {
    throw InputError(file, 0, 0, "NumPy file, byte offset " + std::to_string(offset) + ": " + what, kWrite);
  };
  if (bytes.size() < 10) fail(bytes.size(), "the file ends inside the NumPy preamble");
  const auto major = static_cast<unsigned char>(bytes[6]);
  if (major < 1 || major > 3) {
    fail(6, "format version " + std::to_string(major) + "." + std::to_string(static_cast<unsigned char>(bytes[7])) +
                " is not supported (1.0, 2.0 and 3.0 are)");
  }
  const auto byte = [&](std::size_t i) { return static_cast<std::size_t>(static_cast<unsigned char>(bytes[i])); };
  if (major == 1) return 10 + (byte(8) | byte(9) << 8);
  if (bytes.size() < 12) fail(bytes.size(), "the file ends inside the NumPy preamble");
  return 12 + (byte(8) | byte(9) << 8 | byte(10) << 16 | byte(11) << 24);
}

NpyHeader read_npy_header(std::string_view bytes, const std::string& file) {
  const std::size_t data_at = npy_data_offset(bytes, file);
  const std::size_t header_at = static_cast<unsigned char>(bytes[6]) == 1 ? 10 : 12;
  const std::size_t header_len = data_at - header_at;
  if (header_len > bytes.size() - header_at) {
    throw InputError(file, 0, 0,
                     "NumPy file, byte offset " + std::to_string(bytes.size()) + ": the file ends inside the header (" +
                         std::to_string(header_len) + " bytes declared at byte offset " + std::to_string(header_at) +
                         ")",
                     kWrite);
  }
  HeaderParser parser(bytes.substr(header_at, header_len), header_at, file);
  const HeaderParser::Header h = parser.parse();
  const auto type = npy_type(h.descr);
  if (!type) {
    parser.fail(0, "data type '" + h.descr +
                       "' is not supported (integers i1..i8, u1..u8 and floats f4, f8 of either byte order are)");
  }
  const std::vector<std::size_t>& shape = *h.shape;
  if (shape.empty() || shape.size() > 2) {
    parser.fail(0, "shape " + shape_text(shape) +
                       " is not supported: a 1-D array (one channel) or a 2-D array (rows of samples, a column per "
                       "channel) is");
  }
  NpyHeader out;
  out.type = *type;
  out.descr = h.descr;
  out.shape = shape_text(shape);
  out.rows = shape[0];
  out.cols = shape.size() == 2 ? shape[1] : 1;
  out.data_at = data_at;
  // A 1-D array is the same bytes in either order.
  out.fortran_order = *h.fortran_order && shape.size() == 2;
  if (out.cols == 0) parser.fail(0, "shape " + out.shape + " has no columns");
  // Before anything is sized by the column count: with no rows, any count
  // passes the size checks below.
  if (out.rows == 0) parser.fail(0, "shape " + out.shape + " holds no samples (the array is empty)");
  constexpr std::size_t kMax = std::numeric_limits<std::size_t>::max();
  if (out.rows > kMax / out.cols || out.rows * out.cols > kMax / type->bytes)
    parser.fail(0, "shape " + out.shape + " is too large");
  return out;
}

std::string npy_short_data(const NpyHeader& h, std::size_t have) {
  return "the data end " + std::to_string(h.data_bytes() - have) + " bytes short of the shape " + h.shape + " of " +
         h.descr + " declared in the header (data from byte offset " + std::to_string(h.data_at) + ")";
}

std::string npy_extra_data(const NpyHeader& h, std::size_t extra) {
  return std::to_string(extra) + " bytes after the data of shape " + h.shape + " of " + h.descr;
}

Table read_npy(std::string_view bytes, const std::string& file, bool missing_as_nan) {
  const NpyHeader h = read_npy_header(bytes, file);
  const std::size_t data_at = h.data_at;
  const std::size_t rows = h.rows;
  const std::size_t cols = h.cols;
  const SampleType* type = &h.type;
  const std::size_t need = h.data_bytes();
  const std::size_t have = bytes.size() - data_at;
  const auto fail = [&](std::size_t offset, const std::string& what, const std::string& hint) {
    throw InputError(file, 0, 0, "NumPy file, byte offset " + std::to_string(offset) + ": " + what, hint);
  };
  if (have < need) fail(bytes.size(), npy_short_data(h, have), kNpyShortHint);
  if (have > need) fail(data_at + need, npy_extra_data(h, have - need), kNpyExtraHint);
  detail::BinaryLayout bl;
  bl.rows = rows;
  bl.types.assign(cols, *type);
  if (h.fortran_order) {
    bl.row_stride = type->bytes;
    for (std::size_t c = 0; c < cols; ++c) bl.column_offsets.push_back(data_at + c * rows * type->bytes);
  } else {
    bl.row_stride = cols * type->bytes;
    for (std::size_t c = 0; c < cols; ++c) bl.column_offsets.push_back(data_at + c * type->bytes);
  }
  return detail::binary_table(bytes, file, bl, missing_as_nan);
}

}  // namespace cubecal::io
