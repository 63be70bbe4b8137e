// Bounded reads of a record (sample_stream.hpp): the file descriptor is read
// a piece at a time; text pieces end at a line end and are parsed by the
// delimited reader with the header line put in front; binary pieces are
// whole frames decoded column by column.
#include "cubecal/io/sample_stream.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include <zlib.h>

#include "cubecal/error.hpp"
#include "detail/binary_input.hpp"
#include "detail/file_buffer.hpp"
#include "detail/npy_reader.hpp"
#include "cubecal/io/recording.hpp"
#include "cubecal/io/recording_manifest.hpp"
#include "cubecal/stats/sampling.hpp"
#include "detail/shortest_text.hpp"
#include "detail/container_streams.hpp"

namespace cubecal::io {

namespace {

using detail::lower_case;
const auto& stamp = detail::shortest_text;

// The file descriptor of the input, read in pieces; a gzip file (told by its
// magic bytes) inflated on the way, member after member, a piece at a time.
class ByteSource {
 public:
  explicit ByteSource(const std::string& path) {
    const bool stdin_input = path == kStdinPath;
    label_ = stdin_input ? std::string(kStdinLabel) : path;
    fd_ = stdin_input ? STDIN_FILENO : ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    own_ = !stdin_input;
    if (fd_ < 0) throw InputError(label_, 0, 0, std::string("cannot open: ") + std::strerror(errno), "check the path");
    struct stat st {};
    if (::fstat(fd_, &st) == 0 && S_ISREG(st.st_mode)) total_ = static_cast<std::size_t>(st.st_size);
#ifdef F_SETPIPE_SZ
    // A pipe of 1 MiB rather than 64 KiB: a fast producer and this reader
    // then trade pieces in a few system calls instead of many (best effort:
    // the system's pipe-max-size may refuse it).
    if (S_ISFIFO(st.st_mode)) (void)::fcntl(fd_, F_SETPIPE_SZ, 1 << 20);
#endif
    char magic[2];
    const std::size_t got = read_fd(magic, 2);
    consumed_ = got;
    if (got == 2 && static_cast<unsigned char>(magic[0]) == 0x1f && static_cast<unsigned char>(magic[1]) == 0x8b) {
      start_gzip(magic);
    } else {
      head_.assign(magic, got);
    }
  }
  // The chunks of a recording (cubecal record) as one text: the header line
  // of every chunk after the first left out, and each chunk's bytes checked
  // against the size and CRC-32 of the manifest as they go by. An open chunk
  // (the one a running recorder writes) is read up to `bytes`, the end of
  // its last complete line when the stream was opened, and has no CRC yet.
  struct Chunk {
    std::string path;
    std::size_t bytes = 0;
    std::uint32_t crc = 0;
    bool open = false;
  };
  ByteSource(std::vector<Chunk> chunks, const std::string& dir) : own_(true), label_(dir), chunks_(std::move(chunks)) {
    for (const Chunk& c : chunks_) total_ += c.bytes;
  }
  ~ByteSource() {
    if (own_ && fd_ >= 0) ::close(fd_);
    if (zs_) inflateEnd(zs_.get());
  }
  ByteSource(const ByteSource&) = delete;
  ByteSource& operator=(const ByteSource&) = delete;

  // How errors name the input: the path, "<stdin>" or the recording.
  const std::string& label() const noexcept { return label_; }
  // The size of a regular file or of a recording's chunks (0: unknown).
  std::size_t total() const noexcept { return total_; }
  // Bytes taken from the file(s) so far (compressed bytes for gzip): the
  // progress against total().
  std::size_t consumed() const noexcept { return consumed_; }
  bool gzip() const noexcept { return zs_ != nullptr; }
  // A regular file, not gzip: read_at() can read anywhere in it.
  bool seekable() const noexcept { return chunks_.empty() && !zs_ && total_ > 0 && fd_ >= 0 && own_; }
  // n bytes at byte offset `at` of a seekable() file, whatever was read
  // before; false (errno set) on an error or a short read.
  bool read_at(std::size_t at, char* dst, std::size_t n) {
    std::size_t got = 0;
    while (got < n) {
      const ssize_t r = ::pread(fd_, dst + got, n - got, static_cast<off_t>(at + got));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) {
        if (r == 0) errno = EIO;
        return false;
      }
      got += static_cast<std::size_t>(r);
    }
    return true;
  }
  // Compressed bytes inflated so far (gzip only).
  std::size_t compressed_used() const noexcept { return zs_ ? consumed_ - zs_->avail_in : consumed_; }

  // The first n bytes of the (inflated) input, or all of a shorter one,
  // without taking them: read() gives them again.
  std::string_view peek(std::size_t n) {
    if (head_.size() < n) {
      const std::size_t at = head_.size();
      head_.resize(n);
      head_.resize(at + read_content(head_.data() + at, n - at));
    }
    return std::string_view(head_).substr(0, n);
  }

  // Up to n bytes (fewer only at the end of the input).
  std::size_t read(char* dst, std::size_t n) {
    std::size_t got = 0;
    if (head_at_ < head_.size()) {
      got = std::min(n, head_.size() - head_at_);
      std::memcpy(dst, head_.data() + head_at_, got);
      head_at_ += got;
      if (head_at_ == head_.size()) {
        head_.clear();
        head_.shrink_to_fit();
        head_at_ = 0;
      }
    }
    return got + (got < n ? read_content(dst + got, n - got) : 0);
  }

 private:
  std::size_t read_content(char* dst, std::size_t n) {
    if (zs_) return read_gzip(dst, n);
    if (chunks_.empty()) {
      const std::size_t got = read_fd(dst, n);
      consumed_ += got;
      return got;
    }
    std::size_t got = 0;
    while (got < n) {
      if (fd_ < 0 && !open_next_chunk()) break;
      const Chunk& c = chunks_[next_];
      const std::size_t want = c.open ? std::min(n - got, c.bytes - seen_) : n - got;
      std::size_t r = want > 0 ? read_fd(dst + got, want) : 0;
      const bool chunk_ended = r < want || (c.open && seen_ + r == c.bytes);
      crc_ = static_cast<std::uint32_t>(::crc32(crc_, reinterpret_cast<const Bytef*>(dst + got), static_cast<uInt>(r)));
      seen_ += r;
      consumed_ += r;
      if (skip_header_) {  // a later chunk's header line: counted, not passed on
        const char* nl = static_cast<const char*>(std::memchr(dst + got, '\n', r));
        if (nl == nullptr) {
          r = 0;
        } else {
          const std::size_t cut = static_cast<std::size_t>(nl - (dst + got)) + 1;
          std::memmove(dst + got, dst + got + cut, r - cut);
          r -= cut;
          skip_header_ = false;
        }
      }
      lines_ += static_cast<std::size_t>(std::count(dst + got, dst + got + r, '\n'));
      got += r;
      if (chunk_ended) finish_chunk();
    }
    return got;
  }

  void start_gzip(const char magic[2]) {
    zs_ = std::make_unique<z_stream>();
    // 16 + MAX_WBITS: gzip wrapper only; zlib checks the CRC-32 and length
    // trailer of each member itself.
    if (inflateInit2(zs_.get(), 16 + MAX_WBITS) != Z_OK) {
      zs_.reset();
      throw std::bad_alloc();
    }
    in_.resize(kGzipInput);
    in_[0] = magic[0];
    in_[1] = magic[1];
    const std::size_t got = read_fd(in_.data() + 2, in_.size() - 2);
    raw_eof_ = got < in_.size() - 2;
    consumed_ += got;
    zs_->next_in = reinterpret_cast<Bytef*>(in_.data());
    zs_->avail_in = static_cast<uInt>(got + 2);
  }
  void refill() {
    const std::size_t got = read_fd(in_.data(), in_.size());
    raw_eof_ = got < in_.size();
    consumed_ += got;
    zs_->next_in = reinterpret_cast<Bytef*>(in_.data());
    zs_->avail_in = static_cast<uInt>(got);
  }
  // Where zlib is, in the words of the whole-file reader (file_buffer.cpp).
  std::string gzip_place() const {
    return "at byte offset " + std::to_string(consumed_ - zs_->avail_in) + ", in gzip member " +
           std::to_string(member_) + ", after " + std::to_string(inflated_) + " bytes of text";
  }
  // Inflates into dst up to n bytes: every member in turn; a stream cut
  // short or damaged is an InputError naming its byte offset and member.
  std::size_t read_gzip(char* dst, std::size_t n) {
    z_stream& zs = *zs_;
    zs.next_out = reinterpret_cast<Bytef*>(dst);
    zs.avail_out = static_cast<uInt>(std::min<std::size_t>(n, std::size_t{1} << 30));
    const uInt room = zs.avail_out;
    while (zs.avail_out > 0 && !gzip_done_) {
      if (zs.avail_in == 0 && !raw_eof_) refill();
      const uInt before = zs.avail_out;
      const int rc = inflate(&zs, Z_NO_FLUSH);
      inflated_ += before - zs.avail_out;
      if (rc == Z_STREAM_END) {
        if (zs.avail_in == 0 && !raw_eof_) refill();
        if (zs.avail_in == 0) {
          gzip_done_ = true;
          break;
        }
        inflateReset(&zs);  // the next member
        ++member_;
        continue;
      }
      if (rc == Z_OK) continue;
      if (rc == Z_BUF_ERROR && zs.avail_in == 0 && raw_eof_)
        throw InputError(label_, 0, 0, "truncated gzip stream: the data end " + gzip_place(),
                         "the file is incomplete; copy or download it again");
      if (rc == Z_BUF_ERROR) continue;
      if (rc == Z_MEM_ERROR) throw std::bad_alloc();
      throw InputError(label_, 0, 0,
                       "corrupt gzip data " + gzip_place() + ": " + (zs.msg != nullptr ? zs.msg : "inflate failed"),
                       "the file is damaged; copy or download it again");
    }
    return room - zs.avail_out;
  }

 public:
  // Where line `line` (1-based) of the text read so far lies: for a
  // recording's chunks, the chunk and its own line (a later chunk's header,
  // left out of the text, counted back in); false for one file.
  bool place(std::size_t line, std::string& file, std::size_t& local) const {
    if (chunks_.empty() || first_line_.empty() || line == 0) return false;
    const auto k =
        static_cast<std::size_t>(std::upper_bound(first_line_.begin(), first_line_.end(), line) - first_line_.begin());
    if (k == 0) return false;
    file = chunks_[k - 1].path;
    local = line - first_line_[k - 1] + 1 + (k > 1 ? 1 : 0);
    return true;
  }

 private:
  bool open_next_chunk() {
    if (next_ == chunks_.size()) return false;
    const Chunk& c = chunks_[next_];
    fd_ = ::open(c.path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0)
      throw InputError(c.path, 0, 0, std::string("cannot open: ") + std::strerror(errno),
                       "the recording's manifest lists this chunk");
    skip_header_ = next_ > 0;
    first_line_.push_back(lines_ + 1);
    crc_ = static_cast<std::uint32_t>(::crc32(0L, Z_NULL, 0));
    seen_ = 0;
    return true;
  }
  void finish_chunk() {
    const Chunk& c = chunks_[next_];
    ::close(fd_);
    fd_ = -1;
    ++next_;
    if (c.open ? seen_ != c.bytes : seen_ != c.bytes || crc_ != c.crc)
      throw InputError(c.path, 0, 0,
                       seen_ != c.bytes
                           ? std::to_string(seen_) + " bytes where the manifest has " + std::to_string(c.bytes)
                           : "CRC-32 " + crc32_hex(crc_) + " where the manifest has " + crc32_hex(c.crc),
                       "the chunk changed since it was recorded: restore it, or remove the recording's damaged part");
  }
  std::size_t read_fd(char* dst, std::size_t n) {
    std::size_t got = 0;
    while (got < n) {
      const ssize_t r = ::read(fd_, dst + got, n - got);
      if (r == 0) break;
      if (r < 0) {
        if (errno == EINTR) continue;
        throw InputError(label_, 0, 0, std::string("read error: ") + std::strerror(errno));
      }
      got += static_cast<std::size_t>(r);
    }
    return got;
  }

  static constexpr std::size_t kGzipInput = std::size_t{256} << 10;

  int fd_ = -1;
  bool own_ = false;
  std::string label_;
  std::size_t total_ = 0, consumed_ = 0;
  std::string head_;  // bytes peeked, given again by read()
  std::size_t head_at_ = 0;
  std::unique_ptr<z_stream> zs_;  // gzip input: the inflater
  std::vector<char> in_;          // compressed bytes read, for zs_
  bool raw_eof_ = false, gzip_done_ = false;
  std::size_t member_ = 1, inflated_ = 0;
  std::vector<Chunk> chunks_;  // a recording's chunks, read in turn
  std::size_t next_ = 0;       // the chunk being read
  bool skip_header_ = false;
  std::uint32_t crc_ = 0;
  std::size_t seen_ = 0;                 // bytes of the chunk read so far
  std::size_t lines_ = 0;                // line ends passed on so far
  std::vector<std::size_t> first_line_;  // the line of the text each chunk opened at
};

void check_common(const SeriesOptions& opt) {
  if (opt.gaps == GapPolicy::split)
    throw UsageError(Field::gaps,
                     "a streamed record is not split at gaps: leave out {gaps} split (a gap is then an "
                     "error naming its place), or read the record into memory without {stream}");
  if (opt.gaps == GapPolicy::skip)
    throw UsageError(Field::gaps,
                     "missing samples are skipped in a record read into memory: leave out {stream}, or "
                     "{gaps} skip (a gap is then an error naming its place)");
  for (const double lsb : opt.lsb)
    if (!(lsb > 0.0) || !std::isfinite(lsb))
      throw UsageError(Field::counts_per_unit,
                       "the LSB (counts per unit) must be a positive finite number, got " + stamp(lsb));
  if (opt.rate_hz != 0.0 && !(opt.rate_hz >= kMinRateHz && opt.rate_hz <= kMaxRateHz))
    throw UsageError(Field::rate, "the sampling rate " + stamp(opt.rate_hz) + " Hz is outside the range " +
                                      stamp(kMinRateHz) + " to " + stamp(kMaxRateHz) + " Hz");
}

void check_lsb_count(const SeriesOptions& opt, const std::string& file, const std::vector<std::string>& names) {
  if (opt.lsb.size() <= 1 || opt.lsb.size() == names.size()) return;
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ",") + n;
  throw UsageError(Field::counts_per_unit, file + ": " + std::to_string(opt.lsb.size()) + " LSB values for " +
                                               std::to_string(names.size()) + " columns (" + list +
                                               "): give one value for every column, or one per column");
}

[[noreturn]] void refuse_format(const std::string& file, const std::string& what, const std::string& hint) {
  throw InputError(file, 0, 0, what + " is not read as a stream", hint);
}

// ---------------------------------------------------------------------------

constexpr std::size_t kBinaryChunk = std::size_t{256} << 10;

// Frames of samples after a header: raw binary as the options describe it,
// or the rows of a C-order NumPy array (its header says how many: fewer or
// more bytes are an error, as read_npy's).
class BinaryStream final : public SampleStream {
 public:
  BinaryStream(std::unique_ptr<ByteSource> src, RawLayout layout, const SeriesOptions& opt, std::size_t chunk_bytes,
               const NpyHeader* npy = nullptr)
      : src_(std::move(src)), layout_(std::move(layout)) {
    file_ = src_->label();
    total_bytes_ = src_->total();
    if (npy != nullptr) npy_ = *npy;
    if (opt.rate_hz == 0.0)
      throw UsageError(Field::rate, npy_ ? file_ + ": a NumPy array has no time stamps when streamed: give {rate} HZ"
                                         : std::string("raw binary has no time column: give the sampling rate"));
    rate_hz_ = opt.rate_hz;
    // Resolve the columns as read_series does, on a table without rows.
    Table all;
    all.file = file_;
    all.binary = true;
    all.total_columns = layout_.channels.size();
    all.data.resize(all.total_columns);
    TableOptions topt = opt.table;
    const Table sel = select_columns(std::move(all), topt);
    if (sel.indices.empty()) throw InputError(file_, 0, 0, "no data columns", "name the columns to analyze");
    names_ = sel.names;
    extra_names_ = sel.extra_names;
    check_lsb_count(opt, file_, names_);
    for (std::size_t c = 0; c < names_.size(); ++c) scale_.push_back(opt.lsb_of(c));
    for (std::size_t c = 0; c < layout_.channels.size(); ++c) {
      offsets_.push_back(frame_);
      frame_ += layout_.channels[c].bytes;
    }
    columns_ = sel.indices;
    extras_ = sel.extra_indices;
    // Pieces that stay in the cache between the read, the decoding and the
    // consumer (a binary frame needs no look-ahead): at most kBinaryChunk.
    frames_per_chunk_ = std::max<std::size_t>(1, std::min(chunk_bytes, kBinaryChunk) / frame_);
    buf_.resize(frames_per_chunk_ * frame_);
    if (npy_ && npy_->fortran_order) {
      start_column_major();
      return;
    }
    skip_header();
    if (npy_) data_left_ = npy_->data_bytes();
  }

  bool next(SampleChunk& out) override {
    if (column_major_) return next_rows(out);
    const std::size_t want = npy_ ? std::min(buf_.size(), data_left_) : buf_.size();
    const std::size_t got = src_->read(buf_.data(), want);
    bytes_read_ = src_->consumed();
    if (npy_) check_npy_end(want, got);
    const std::size_t rows = got / frame_;
    if (got % frame_ != 0) {
      throw InputError(file_, 0, 0,
                       "trailing partial frame: " + std::to_string(got % frame_) + " bytes at byte offset " +
                           std::to_string(offset_ + rows * frame_) + " after " + std::to_string(rows_read_ + rows) +
                           " whole frames",
                       "the frame of " + std::to_string(layout_.channels.size()) + " channels is " +
                           std::to_string(frame_) + " bytes; check {binary} and {header_bytes}");
    }
    out.channels.resize(columns_.size());
    out.extra.resize(extras_.size());
    for (std::size_t c = 0; c < columns_.size(); ++c) decode(columns_[c], rows, scale_[c], out.channels[c]);
    for (std::size_t c = 0; c < extras_.size(); ++c) decode(extras_[c], rows, 1.0, out.extra[c]);
    offset_ += got;
    rows_read_ += rows;
    return rows > 0;
  }

 private:
  // A Fortran-order array: the next rows of each column read where the
  // column lies in the file.
  bool next_rows(SampleChunk& out) {
    const std::size_t rows = std::min(frames_per_chunk_, npy_->rows - rows_read_);
    out.channels.resize(columns_.size());
    out.extra.resize(extras_.size());
    for (std::size_t c = 0; c < columns_.size(); ++c) decode(columns_[c], rows, scale_[c], out.channels[c]);
    for (std::size_t c = 0; c < extras_.size(); ++c) decode(extras_[c], rows, 1.0, out.extra[c]);
    rows_read_ += rows;
    bytes_read_ = npy_->data_at + rows_read_ * frame_;  // the share of the file
    return rows > 0;
  }
  std::size_t column_offset(std::size_t col) const {
    const std::size_t b = layout_.channels[col].bytes;
    return npy_->data_at + col * npy_->rows * b + rows_read_ * b;
  }
  void read_column(std::size_t col, std::size_t rows) {
    const std::size_t n = rows * layout_.channels[col].bytes;
    if (!src_->read_at(column_offset(col), buf_.data(), n))
      throw InputError(file_, 0, 0, std::string("read error: ") + std::strerror(errno));
  }

  void skip_header() {
    std::size_t left = layout_.header_bytes;
    while (left > 0) {
      const std::size_t got = src_->read(buf_.data(), std::min(left, buf_.size()));
      if (got == 0)
        throw InputError(file_, 0, 0,
                         "the input has " + std::to_string(layout_.header_bytes - left) + " bytes, fewer than the " +
                             std::to_string(layout_.header_bytes) + " header bytes to skip",
                         "check {header_bytes}");
      left -= got;
      offset_ += got;
    }
    bytes_read_ = src_->consumed();
  }

  // A Fortran-order array read column by column from a file (the size
  // checked first, as read_npy checks it).
  void start_column_major() {
    const NpyHeader& h = *npy_;
    if (!src_->seekable())
      throw InputError(file_, 0, 0,
                       "a 2-D NumPy array in Fortran order (column after column) is streamed from a file, not from "
                       "gzip or a pipe",
                       "give the .npy file itself, or save it in C order: numpy.save(f, numpy.ascontiguousarray(a))");
    const std::size_t size = total_bytes_, need = h.data_at + h.data_bytes();
    const auto fail = [&](std::size_t offset, const std::string& what, const char* hint) {
      throw InputError(file_, 0, 0, "NumPy file, byte offset " + std::to_string(offset) + ": " + what, hint);
    };
    if (size < need) fail(size, npy_short_data(h, size - h.data_at), kNpyShortHint);
    if (size > need) fail(need, npy_extra_data(h, size - need), kNpyExtraHint);
    column_major_ = true;
  }

  // A NumPy array's data: as many bytes as its header declares, no fewer
  // (the piece read short) and none after them.
  void check_npy_end(std::size_t want, std::size_t got) {
    const NpyHeader& h = *npy_;
    const auto fail = [&](std::size_t offset, const std::string& what, const char* hint) {
      throw InputError(file_, 0, 0, "NumPy file, byte offset " + std::to_string(offset) + ": " + what, hint);
    };
    if (got < want) {
      const std::size_t have = h.data_bytes() - data_left_ + got;
      fail(h.data_at + have, npy_short_data(h, have), kNpyShortHint);
    }
    data_left_ -= got;
    if (data_left_ > 0 || got > 0) return;
    std::size_t extra = 0;
    for (std::size_t n = 0; (n = src_->read(buf_.data(), buf_.size())) > 0;) extra += n;
    if (extra > 0) fail(h.data_at + h.data_bytes(), npy_extra_data(h, extra), kNpyExtraHint);
  }

  // Column `col` of the piece: its samples from buf_ + first, `stride`
  // bytes apart; `at` is the input's byte offset of the first (messages).
  void decode(std::size_t col, std::size_t rows, double lsb, std::vector<double>& v) {
    if (column_major_) return decode(col, rows, lsb, v, 0, layout_.channels[col].bytes, column_offset(col));
    decode(col, rows, lsb, v, offsets_[col], frame_, offset_ + offsets_[col]);
  }
  void decode(std::size_t col, std::size_t rows, double lsb, std::vector<double>& v, std::size_t first,
              std::size_t stride, std::size_t at) {
    if (column_major_) read_column(col, rows);
    v.resize(rows);
    const SampleType t = layout_.channels[col];
    const char* p = buf_.data() + first;
    if (t == SampleType{SampleKind::floating, 8, false} && std::endian::native == std::endian::little) {
      if (stride == 8) {
        if (rows > 0) std::memcpy(v.data(), p, rows * 8);  // the samples are the values
      } else {
        for (std::size_t r = 0; r < rows; ++r, p += stride) std::memcpy(&v[r], p, 8);
      }
    } else {
      for (std::size_t r = 0; r < rows; ++r, p += stride) v[r] = decode_sample(t, p);
    }
    bool ok = true;
    const double top = kMaxMagnitude * lsb;
    for (std::size_t r = 0; r < rows; ++r) ok &= std::abs(v[r]) <= top;
    if (!ok) {
      std::size_t r = 0;
      while (std::abs(v[r]) <= top) ++r;
      const std::size_t offset = at + r * stride;
      const bool finite = std::isfinite(v[r]);
      throw InputError(file_, 0, 0,
                       (finite ? "value " + stamp(v[r]) + " exceeds the magnitude " + stamp(kMaxMagnitude)
                               : std::string(std::isnan(v[r]) ? "NaN" : "infinite value")) +
                           " at byte offset " + std::to_string(offset) + " (row " + std::to_string(rows_read_ + r + 1) +
                           ", column " + std::to_string(col + 1) + ")",
                       finite ? "rescale the column, e.g. to other units"
                              : "a missing or invalid sample: cut the record there, or fill the gap");
    }
    if (lsb != 1.0)
      for (double& x : v) x /= lsb;
  }

  std::unique_ptr<ByteSource> src_;
  RawLayout layout_;
  std::optional<NpyHeader> npy_;
  std::size_t offset_ = 0;     // of the next byte in the (inflated) input
  std::size_t data_left_ = 0;  // bytes of a NumPy array's data still to come
  bool column_major_ = false;  // a Fortran-order array, read column by column
  std::size_t frame_ = 0, frames_per_chunk_ = 0;
  std::vector<std::size_t> offsets_, columns_, extras_;
  std::vector<double> scale_;
  std::vector<char> buf_;
};

// ---------------------------------------------------------------------------

bool is_comment_or_blank(std::string_view line) {
  for (char c : line) {
    if (c == ' ' || c == '\t' || c == '\r') continue;
    return c == '#';
  }
  return true;
}

class TextStream final : public SampleStream {
 public:
  // The columns were chosen for the caller (a recording's data columns, as
  // its whole read chooses them): said as default columns, with those left out.
  void take_as_default_columns(std::vector<std::string> left_out) {
    default_columns_ = true;
    left_out_ = std::move(left_out);
  }

  // A file, the standard input or a recording's chunks as one text.
  TextStream(std::unique_ptr<ByteSource> src, const SeriesOptions& opt, std::size_t chunk_bytes)
      : src_(std::move(src)), opt_(opt), chunk_bytes_(std::max<std::size_t>(chunk_bytes, 4096)) {
    file_ = src_->label();
    total_bytes_ = src_->total();
    try {
      start(opt);
    } catch (const InputError& e) {
      placed(e);
    }
  }

 private:
  // The first piece: the layout, the time column, the columns, the rate.
  void start(const SeriesOptions& opt) {
    // The start checked as the whole-file reader checks it (binary data, a
    // gzip bomb of zeros) before a line end is looked for.
    const std::string_view head = src_->peek(detail::kTextProbeBytes);
    if (is_known_binary_format(head))
      refuse_format(file_, "an HDF5, ULog or ROS bag file from standard input or gzip-compressed",
                    "give the uncompressed file by its path (it is then streamed), or leave out {stream}");
    if (head.starts_with("File:"))  // its header gives the rate, type and scaling: read whole
      refuse_format(file_, "a Stable32 .DAT file", "leave out {stream} (it is read into memory)");
    if (src_->gzip()) detail::check_text_start(head, file_, true);
    read_piece();
    const Table layout = parse_layout(text_, file_, opt.table);
    // The time column, as read_series chooses it.
    std::string time_spec;
    if (!opt.time_col.empty()) {
      time_spec = opt.time_col;
      timing_ = true;
    } else {
      const auto it = std::find_if(layout.header.begin(), layout.header.end(), looks_like_time_column);
      if (it == layout.header.end()) {
        if (opt.rate_hz == 0.0)
          throw UsageError(file_ +
                           ": no sampling rate: no column is named as a time column (t, time, t_s, "
                           "timestamp...): give {rate} HZ or {time_col} NAME");
      } else {
        time_spec = *it;
        timing_ = opt.rate_hz == 0.0;
      }
    }
    topt_ = opt.table;
    if (topt_.columns.empty() && layout.has_header) {  // the default columns
      default_columns_ = true;
      for (const std::string& name : layout.header) {
        bool out = !time_spec.empty() && (name == time_spec || lower_case(name) == lower_case(time_spec));
        for (const auto& e : opt.table.extra_columns) out = out || name == e;
        out = out || (opt.skip_temperature && looks_like_temperature_column(name));
        (out ? left_out_ : topt_.columns).push_back(name);
      }
      if (topt_.columns.empty())
        throw InputError(file_, 0, 0, "no data columns besides the time column", "name the columns to analyze");
    }
    extra_count_ = topt_.extra_columns.size();
    if (!time_spec.empty()) topt_.extra_columns.push_back(time_spec);
    has_time_ = !time_spec.empty();
    // The lines in front of the data after the skipped rows (header,
    // comments), put before every later piece so that it parses as the
    // first did.
    const std::size_t skip_end = line_start(opt.table.skip_rows + 1);
    scan_begin_ = line_start(layout.first_data_line);
    scan_line_ = layout.first_data_line;
    prefix_ = text_.substr(skip_end, scan_begin_ - skip_end);
    prefix_lines_ = static_cast<std::size_t>(std::count(prefix_.begin(), prefix_.end(), '\n'));
    // The first piece now: names, the rate.
    pending_ = parse_table(text_, file_, topt_);
    have_pending_ = true;
    names_ = pending_.names;
    check_lsb_count(opt, file_, names_);
    for (std::size_t c = 0; c < names_.size(); ++c) scale_.push_back(opt.lsb_of(c));
    for (std::size_t k = 0; k < extra_count_; ++k) extra_names_.push_back(pending_.extra_names[k]);
    if (has_time_) time_name_ = pending_.extra_names[extra_count_];
    set_rate();
    // Short fields ("0\n") parse to more doubles than the text has bytes:
    // later pieces hold no more doubles than chunk_bytes bytes.
    const std::size_t values = pending_.rows() * (pending_.data.size() + pending_.extra.size());
    if (values * 8 > chunk_bytes_)
      chunk_bytes_ = std::max<std::size_t>(
          4096, static_cast<std::size_t>(static_cast<double>(chunk_bytes_) * static_cast<double>(chunk_bytes_) /
                                         (8.0 * static_cast<double>(values))));
  }

 public:
  bool next(SampleChunk& out) override {
    try {
      return next_piece(out);
    } catch (const InputError& e) {
      placed(e);
    }
  }

 private:
  // An error at a line of a recording's joined chunks, rethrown at the chunk
  // and line the user can open; any other error as it is.
  [[noreturn]] void placed(const InputError& e) const {
    std::string file;
    std::size_t line = 0;
    if (e.file() == file_ && src_->place(e.line(), file, line))
      throw InputError(file, line, e.column(), e.problem(), e.hint());
    throw;
  }

  bool next_piece(SampleChunk& out) {
    if (!have_pending_) {
      if (eof_ && carry_.empty()) return false;
      read_piece();
      if (text_.empty()) return false;
      std::string composed = prefix_;
      composed += text_;
      TableOptions o = topt_;
      o.skip_rows = 0;
      try {
        pending_ = parse_table(composed, file_, o);
      } catch (const InputError& e) {
        if (e.line() <= prefix_lines_) throw;
        throw InputError(e.file(), e.line() - prefix_lines_ - 1 + piece_line0_, e.column(), e.problem(), e.hint());
      }
      scan_begin_ = 0;
      scan_line_ = piece_line0_;
    }
    have_pending_ = false;
    check_piece(pending_);
    const std::size_t rows = pending_.rows();
    out.channels.resize(pending_.data.size());
    for (std::size_t c = 0; c < pending_.data.size(); ++c) {
      out.channels[c].swap(pending_.data[c]);
      if (scale_[c] != 1.0)
        for (double& v : out.channels[c]) v /= scale_[c];
    }
    out.extra.resize(extra_count_);
    for (std::size_t k = 0; k < extra_count_; ++k) out.extra[k].swap(pending_.extra[k]);
    rows_read_ += rows;
    return true;
  }

 private:
  // The next piece into text_, ending at a line end (but at the end of the
  // input); piece_line0_ is the file line of its first character.
  void read_piece() {
    piece_line0_ += static_cast<std::size_t>(std::count(text_.begin(), text_.end(), '\n'));
    text_.swap(carry_);
    carry_.clear();
    const std::size_t at = text_.size();
    text_.resize(at + chunk_bytes_);
    const std::size_t got = src_->read(text_.data() + at, chunk_bytes_);
    text_.resize(at + got);
    bytes_read_ = src_->consumed();
    eof_ = got < chunk_bytes_;
    if (!eof_) {
      const std::size_t nl = text_.rfind('\n');
      if (nl == std::string::npos)
        throw InputError(file_, piece_line0_, 0, "a line longer than " + std::to_string(chunk_bytes_) + " bytes",
                         "not a delimited text record");
      carry_ = text_.substr(nl + 1);
      text_.resize(nl + 1);
    }
  }

  // Offset in text_ of the start of 1-based line `line` (its size if beyond).
  std::size_t line_start(std::size_t line) const {
    std::size_t pos = 0;
    for (std::size_t l = 1; l < line && pos < text_.size(); ++l) {
      const std::size_t nl = text_.find('\n', pos);
      pos = nl == std::string::npos ? text_.size() : nl + 1;
    }
    return pos;
  }

  // The 1-based line of data row `row` of the piece parsed last.
  std::size_t line_of(std::size_t row) const {
    const std::string_view t(text_);
    std::size_t pos = scan_begin_, line = scan_line_, seen = 0;
    while (pos < t.size()) {
      std::size_t nl = t.find('\n', pos);
      if (nl == std::string_view::npos) nl = t.size();
      if (!is_comment_or_blank(t.substr(pos, nl - pos))) {
        if (seen == row) return line;
        ++seen;
      }
      ++line;
      pos = nl + 1;
    }
    return 0;
  }

  [[noreturn]] void fail_at(std::size_t row, const std::string& problem, const std::string& hint) const {
    throw InputError(file_, line_of(row), 0, problem, hint);
  }

  static double median(std::vector<double> v) {
    const std::size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
    if (v.size() % 2 != 0) return v[mid];
    const double upper = v[mid];
    return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
  }

  // The rate: given, or from the first piece's median interval (nine
  // significant digits, as read_series).
  void set_rate() {
    rate_hz_ = opt_.rate_hz;
    if (!has_time_) return;
    const std::vector<double>& t = pending_.extra[extra_count_];
    std::vector<double> dt;
    for (std::size_t i = 1; i < t.size(); ++i) dt.push_back(t[i] - t[i - 1]);
    if (!timing_) {
      if (opt_.check_rate_against_time && !dt.empty()) {
        const double period = median(dt);
        if (period > 0.0 && std::isfinite(period) && std::fabs(opt_.rate_hz * period - 1.0) > opt_.tolerance)
          throw UsageError(Field::rate,
                           file_ + ": the rate " + stamp(opt_.rate_hz) + " Hz contradicts the time column '" +
                               time_name_ + "' (" + stamp(1.0 / period) +
                               " Hz): leave the rate out to take it from the time stamps, or fix the time column");
      }
      return;
    }
    if (opt_.rate_hz > 0.0) return;
    if (dt.empty())
      throw InputError(file_, 0, 0, "cannot infer the sampling rate from a single time stamp", "give {rate} HZ");
    const double raw = 1.0 / median(dt);
    if (!(raw >= kMinRateHz && raw <= kMaxRateHz))
      fail_at(1,
              "time stamps " + stamp(1.0 / raw) + " s apart give a rate of " + stamp(raw) + " Hz, outside the range " +
                  stamp(kMinRateHz) + " to " + stamp(kMaxRateHz) + " Hz",
              "the time column must be in seconds");
    const double scale = std::pow(10.0, 8.0 - std::floor(std::log10(raw)));
    rate_hz_ = std::round(raw * scale) / scale;
    rate_from_time_ = true;
  }

  // Magnitudes and time stamps of the piece parsed last.
  void check_piece(const Table& t) {
    for (std::size_t c = 0; c < t.data.size(); ++c) {
      const double top = kMaxMagnitude * scale_[c];
      const auto& v = t.data[c];
      bool ok = true;
      for (double x : v) ok &= std::abs(x) <= top;
      if (!ok) {
        std::size_t r = 0;
        while (std::abs(v[r]) <= top) ++r;
        fail_at(r,
                "value " + stamp(v[r]) + " exceeds the magnitude " + stamp(kMaxMagnitude) +
                    " whose square a variance can hold",
                "rescale the column, e.g. to other units");
      }
    }
    if (!has_time_ || t.extra.size() <= extra_count_) return;
    const std::vector<double>& time = t.extra[extra_count_];
    if (!timing_) {  // the rate given: stamps may repeat (coarse clocks) but not go back
      for (std::size_t i = 0; i < time.size(); ++i) {
        if (have_last_ && time[i] < last_)
          fail_at(i, "time stamp " + stamp(time[i]) + " s is before the previous one " + stamp(last_) + " s",
                  "sort the file or fix the logger clock");
        last_ = time[i];
        have_last_ = true;
      }
      return;
    }
    const double period = 1.0 / rate_hz_;
    const std::string ignore = opt_.time_col.empty() ? ", or give {rate} HZ to ignore the time stamps" : "";
    for (std::size_t i = 0; i < time.size(); ++i) {
      const double now = time[i];
      if (have_last_) {
        const double dt = now - last_;
        if (!(now > last_))
          fail_at(i, "time stamp " + stamp(now) + " s is not after the previous one " + stamp(last_) + " s",
                  now == last_ ? "duplicated time stamp: remove the repeated row or fix the logger clock"
                               : "sort the file or fix the logger clock");
        if (std::fabs(dt - period) > opt_.tolerance * period) {
          if (dt >= kGapPeriods * period)
            fail_at(i,
                    "gap of " + stamp(dt) + " s (" + std::to_string(std::llround(dt / period)) + " periods of " +
                        stamp(period) + " s) after t = " + stamp(last_) + " s",
                    "a streamed record is not split: cut it at the gap, or read it into memory with {gaps} split");
          fail_at(i, "jitter: interval " + stamp(dt) + " s differs from the period " + stamp(period) + " s",
                  "cut the record at irregular intervals" + ignore);
        }
      }
      last_ = now;
      have_last_ = true;
    }
  }

  std::unique_ptr<ByteSource> src_;
  SeriesOptions opt_;
  TableOptions topt_;
  std::size_t chunk_bytes_;
  std::string text_, carry_, prefix_;
  std::size_t prefix_lines_ = 0, piece_line0_ = 1, scan_begin_ = 0, scan_line_ = 1;
  bool eof_ = false, have_pending_ = false;
  bool timing_ = false, has_time_ = false, have_last_ = false;
  double last_ = 0.0;
  std::size_t extra_count_ = 0;
  std::vector<double> scale_;
  Table pending_;
};

}  // namespace

namespace {

// The bytes of an open chunk up to the end of its last complete line, when
// that line is a sample (0: missing, or no sample yet: the header only).
std::size_t complete_lines_bytes(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;  // created after the manifest's last rewrite
  struct stat st {};
  std::size_t end = 0, first_nl = std::string::npos;
  if (::fstat(fd, &st) == 0 && st.st_size > 0) {
    std::vector<char> block(std::size_t{64} << 10);
    auto at = static_cast<std::size_t>(st.st_size);
    while (at > 0 && end == 0) {
      const std::size_t n = std::min(at, block.size());
      at -= n;
      if (::pread(fd, block.data(), n, static_cast<off_t>(at)) != static_cast<ssize_t>(n)) break;
      for (std::size_t i = n; i-- > 0;)
        if (block[i] == '\n') {
          end = at + i + 1;
          break;
        }
    }
    const ssize_t h = ::pread(fd, block.data(), block.size(), 0);  // the header line
    for (std::size_t i = 0; h > 0 && i < static_cast<std::size_t>(h); ++i)
      if (block[i] == '\n') {
        first_nl = i;
        break;
      }
  }
  ::close(fd);
  return first_nl != std::string::npos && end > first_nl + 1 ? end : 0;
}

// A recording directory (cubecal record) streamed: its chunks read in turn
// as one text, which the one segment of a recording is (a device time
// column checked across the chunks as within one file); the open chunk of a
// running recorder up to its last complete line. A recording of several
// segments, or with a source that went away and came back, is read whole
// (recording.hpp places its pieces).
std::unique_ptr<SampleStream> open_recording_stream(const std::string& dir, const SeriesOptions& opt,
                                                    std::size_t chunk_bytes) {
  const RecordingManifest m = read_manifest(dir);
  const RecordingSegment* seg = nullptr;
  std::size_t with_samples = 0;
  for (const auto& s : m.segments)
    if (s.samples > 0 || s.end == SegmentEnd::open) {  // open: samples of its last sync, maybe none yet
      seg = &s;
      ++with_samples;
    }
  const auto whole = [&](const std::string& why) {
    return UsageError(dir + ": " + why +
                      ": a recording is streamed only as one segment without breaks; leave out "
                      "{stream} (it is read into memory and its pieces placed on one clock)");
  };
  if (seg == nullptr) throw InputError(dir, 0, 0, "the recording holds no sample", "record into it first");
  if (with_samples > 1) throw whole("it has " + std::to_string(with_samples) + " segments with samples");
  for (const auto& e : seg->events)
    if (e.kind != RecordingEvent::Kind::gap) throw whole("its source or device clock restarted in " + seg->dir);
  std::vector<ByteSource::Chunk> chunks;
  for (const auto& c : seg->chunks) {
    const std::string path = dir + "/" + seg->dir + "/" + c.file;
    if (c.open || !c.crc32) {
      // The chunk of a running (or crashed) recorder: its complete lines
      // now, as the whole read takes them (recording.hpp).
      if (const std::size_t upto = complete_lines_bytes(path); upto > 0) chunks.push_back({path, upto, 0, true});
      continue;
    }
    if (c.samples > 0) chunks.push_back({path, c.bytes, *c.crc32, false});
  }
  if (chunks.empty())
    throw InputError(dir, 0, 0, "the recording holds no complete sample yet", "wait for the recorder to write one");
  // The columns and time as read_recording takes them: the data columns
  // (not the host stamps, not the device time, not an extra column, not a
  // temperature unless asked), the device time column unless a rate is
  // given instead.
  SeriesOptions o = opt;
  std::vector<std::string> left_out;
  const bool default_columns = o.table.columns.empty();
  if (default_columns)
    for (const auto& name : m.columns) {
      const bool out = (m.time_column && name == *m.time_column) ||
                       std::find(opt.table.extra_columns.begin(), opt.table.extra_columns.end(), name) !=
                           opt.table.extra_columns.end() ||
                       (opt.skip_temperature && looks_like_temperature_column(name));
      (out ? left_out : o.table.columns).push_back(name);
    }
  if (default_columns && o.table.columns.empty())
    throw InputError(dir, 0, 0, "no data columns besides the time and temperature columns",
                     "name the columns to analyze");
  if (o.time_col.empty() && o.rate_hz == 0.0) {
    if (m.time_column)
      o.time_col = *m.time_column;
    else if (m.rate_hz)
      o.rate_hz = *m.rate_hz;
    else
      throw UsageError(dir + ": the recording has no device time column and no rate: give {rate} HZ");
  }
  auto stream = std::make_unique<TextStream>(std::make_unique<ByteSource>(std::move(chunks), dir), o, chunk_bytes);
  if (default_columns) stream->take_as_default_columns(std::move(left_out));
  return stream;
}

// A NumPy .npy: its header read, then its rows as binary frames.
std::unique_ptr<SampleStream> open_npy_stream(std::unique_ptr<ByteSource> src, const SeriesOptions& opt,
                                              std::size_t chunk_bytes) {
  // The header is at most a few hundred bytes; a preamble that declares more
  // than kMaxNpyHeader is read no further.
  constexpr std::size_t kMaxNpyHeader = std::size_t{1} << 20;
  const std::size_t data_at = std::min(npy_data_offset(src->peek(12), src->label()), kMaxNpyHeader);
  const NpyHeader h = read_npy_header(src->peek(data_at), src->label());
  RawLayout layout;
  layout.channels.assign(h.cols, h.type);
  layout.header_bytes = h.data_at;
  return std::make_unique<BinaryStream>(std::move(src), std::move(layout), opt, chunk_bytes, &h);
}

}  // namespace

std::unique_ptr<SampleStream> SampleStream::open(const std::string& path, const SeriesOptions& opt,
                                                 std::size_t chunk_bytes) {
  check_common(opt);
  if (looks_like_recording(path)) return open_recording_stream(path, opt, chunk_bytes);
  if (auto s = detail::open_message_stream(path, opt)) return s;  // ROS 1, MCAP, .db3, bag directories
  if (auto s = detail::open_hdf5_stream(path, opt)) return s;
  auto src = std::make_unique<ByteSource>(path);  // gzip inflated on the way
  if (!opt.binary.channels.empty()) return std::make_unique<BinaryStream>(std::move(src), opt.binary, opt, chunk_bytes);
  if (is_npy(src->peek(6))) return open_npy_stream(std::move(src), opt, chunk_bytes);
  return std::make_unique<TextStream>(std::move(src), opt, chunk_bytes);
}

InputEstimate estimate_input(const std::string& path) {
  InputEstimate e;
  struct stat st {};
  if (path == kStdinPath || ::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_size == 0) return e;
  const auto size = static_cast<std::size_t>(st.st_size);
  e.content_bytes = size;
  try {
    ByteSource src(path);
    e.gzip = src.gzip();
    // The first MiB of the content; of a gzip file, up to 16 MiB inflated
    // (or 4 MiB compressed) for the ratio.
    constexpr std::size_t kHead = std::size_t{1} << 20;
    e.head.resize(kHead);
    e.head.resize(src.read(e.head.data(), kHead));
    if (e.gzip) {
      std::size_t inflated = e.head.size();
      std::vector<char> scratch(kHead);
      std::size_t got = e.head.size() == kHead ? kHead : 0;
      while (got == kHead && inflated < (std::size_t{16} << 20) && src.compressed_used() < (std::size_t{4} << 20)) {
        got = src.read(scratch.data(), kHead);
        inflated += got;
      }
      const bool whole = got < kHead;
      const double ratio =
          static_cast<double>(inflated) / static_cast<double>(std::max<std::size_t>(1, src.compressed_used()));
      e.content_bytes = whole ? inflated : static_cast<std::size_t>(ratio * static_cast<double>(size));
    }
    if (is_npy(e.head)) {
      const NpyHeader h = read_npy_header(e.head, path);
      e.npy_rows = h.rows;
      e.npy_values = h.rows * h.cols;
    }
  } catch (const std::exception&) {  // what is wrong is for the reader to say
  }
  return e;
}

}  // namespace cubecal::io
