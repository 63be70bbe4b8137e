// The recording loop (recorder.hpp).
#include "cubecal/acquire/recorder.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "cubecal/acquire/chunk_writer.hpp"
#include "cubecal/acquire/frame_decoder.hpp"
#include "cubecal/acquire/host_clock.hpp"
#include "cubecal/acquire/rejects_writer.hpp"
#include "cubecal/acquire/sample_handler.hpp"
#include "cubecal/acquire/write_failure.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/printable_text.hpp"
#include "detail/append_file.hpp"

namespace cubecal::acquire {

namespace {

std::string segment_dir_name(int index) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "seg-%03d", index);
  return buf;
}

std::string iso_from_seconds(double utc_s) {
  const double whole = std::floor(utc_s);
  long ns = std::lround((utc_s - whole) * 1e9);
  auto sec = static_cast<std::int64_t>(whole);
  if (ns >= 1000000000L) {
    ns -= 1000000000L;
    ++sec;
  }
  return io::utc_iso8601(sec, ns);
}

bool is_dir(const std::string& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

std::vector<std::string> dir_entries(const std::string& dir);

// Whether anything (a dangling symbolic link included) has this name.
bool exists(const std::string& p) {
  struct stat st {};
  return ::lstat(p.c_str(), &st) == 0;
}

// What a recording may hold at `p`: nothing, or an entry of the kind
// expected (a directory, a regular file), never a symbolic link.
void check_entry(const std::string& p, bool directory) {
  struct stat st {};
  if (::lstat(p.c_str(), &st) != 0) return;
  const bool ok = directory ? S_ISDIR(st.st_mode) : S_ISREG(st.st_mode);
  if (ok) return;
  const std::string what = S_ISLNK(st.st_mode) ? "a symbolic link"
                           : directory         ? "not a directory"
                                               : "not a regular file";
  throw UsageError(Field::out, printable_text(p) + " is " + what + ": a recording holds " +
                                   (directory ? "its segment directories" : "regular files") +
                                   " only and record never writes through a link; put the " +
                                   (directory ? "directory" : "file") + " itself there or record into a new directory");
}

// A name from the manifest: PREFIX, digits, SUFFIX; nothing else (no '/',
// no "..": never a path outside the directory).
bool well_formed(const std::string& name, std::string_view prefix, std::string_view suffix) {
  if (name.size() <= prefix.size() + suffix.size() || name.rfind(prefix, 0) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return false;
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  return digits.find_first_not_of("0123456789") == std::string::npos;
}

// A recording about to be continued: every name the manifest gives is a
// segment directory or a chunk file inside DIR, and what recovery will open
// (the open segments' directories, chunks and rejects) is what it should be.
void check_recording(const std::string& dir, const io::RecordingManifest& m) {
  for (const auto& seg : m.segments) {
    if (!well_formed(seg.dir, "seg-", ""))
      throw UsageError(Field::out, dir + "/manifest.json names a segment directory '" + printable_text(seg.dir) +
                                       "', not seg-NNN: record into a new directory");
    for (const auto& c : seg.chunks)
      if (!well_formed(c.file, "chunk-", ".csv"))
        throw UsageError(Field::out, dir + "/manifest.json names a chunk '" + printable_text(c.file) + "' in " +
                                         seg.dir + ", not chunk-NNNNNN.csv: record into a new directory");
    if (seg.end != io::SegmentEnd::open) continue;
    const std::string sdir = dir + "/" + seg.dir;
    check_entry(sdir, true);
    check_entry(sdir + "/" + std::string(io::kRejectsName), false);
    for (const auto& c : seg.chunks) check_entry(sdir + "/" + c.file, false);
    for (const auto& name : dir_entries(sdir))
      if (well_formed(name, "chunk-", ".csv")) check_entry(sdir + "/" + name, false);
  }
}

std::vector<std::string> dir_entries(const std::string& dir) {
  std::vector<std::string> out;
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) return out;
  while (const dirent* e = ::readdir(d)) {
    const std::string n = e->d_name;
    if (n != "." && n != "..") out.push_back(n);
  }
  ::closedir(d);
  std::sort(out.begin(), out.end());
  return out;
}

void make_dirs(const std::string& dir) {
  std::string path;
  std::size_t i = 0;
  while (i <= dir.size()) {
    const auto slash = dir.find('/', i);
    path = dir.substr(0, slash);
    if (!path.empty() && !is_dir(path) && ::mkdir(path.c_str(), 0755) != 0 && errno != EEXIST)
      throw UsageError(Field::out, dir + ": cannot create the directory (" + std::strerror(errno) + ")");
    if (slash == std::string::npos) break;
    i = slash + 1;
  }
}

// The rejects entries already in DIR/rejects.csv; a partial last entry (a
// crash while it was written) is cut off and its bytes added to `partial`.
std::size_t count_rejects(const std::string& dir, std::size_t& partial) {
  const std::string path = dir + "/" + std::string(io::kRejectsName);
  if (!exists(path)) return 0;
  const int fd = detail::open_regular(path, O_RDWR);  // never through a link
  if (fd < 0) throw WriteFailure(path, errno);
  std::string text;
  char buf[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buf, static_cast<std::size_t>(n));
  }
  const auto last_nl = text.rfind('\n');
  const std::size_t keep = last_nl == std::string::npos ? 0 : last_nl + 1;
  if (keep < text.size()) {
    partial += text.size() - keep;
    if (::ftruncate(fd, static_cast<off_t>(keep)) != 0) {
      const int err = errno;
      ::close(fd);
      throw WriteFailure(path, err);
    }
  }
  ::close(fd);
  const auto lines =
      static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(keep), '\n'));
  return lines > 0 ? lines - 1 : 0;  // less the header line
}

bool same_names(const std::vector<std::string>& a, const std::vector<std::string>& b) { return a == b; }

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

std::string delimiter_name(char d) {
  switch (d) {
    case ',': return ",";
    case '\t': return "\t";
    case ';': return ";";
    default: return " ";
  }
}

}  // namespace

std::vector<std::string> recover_recording(const std::string& dir, io::RecordingManifest& m) {
  std::vector<std::string> notices;
  check_recording(dir, m);
  // A segment the manifest names before its directory is made (a crash
  // right then) held nothing: it is dropped.
  std::erase_if(m.segments, [&](const io::RecordingSegment& seg) {
    if (seg.end != io::SegmentEnd::open || exists(dir + "/" + seg.dir)) return false;
    notices.push_back(dir + "/" + seg.dir + ": dropped from the manifest (a crash before it held anything)");
    return true;
  });
  for (auto& seg : m.segments) {
    if (seg.end != io::SegmentEnd::open) continue;
    const std::string sdir = dir + "/" + seg.dir;
    std::size_t partial = 0;
    const std::size_t old_rejects = count_rejects(sdir, partial);
    RejectsWriter rejects(sdir);
    rejects.set_count(old_rejects);
    // Chunks the manifest does not list yet (a crash during a rotation).
    std::size_t listed = 0;
    for (const auto& c : seg.chunks) {
      unsigned long n = 0;
      if (std::sscanf(c.file.c_str(), "chunk-%lu.csv", &n) == 1) listed = std::max<std::size_t>(listed, n);
    }
    for (const auto& name : dir_entries(sdir)) {
      unsigned long n = 0;
      char tail = 0;
      if (std::sscanf(name.c_str(), "chunk-%lu.cs%c", &n, &tail) == 2 && tail == 'v' && n > listed &&
          name == chunk_file_name(n)) {
        io::RecordingChunk c;
        c.file = name;
        c.open = true;
        seg.chunks.push_back(c);
      }
    }
    std::vector<io::RecordingChunk> kept;
    for (auto& c : seg.chunks) {
      if (!c.open) {
        kept.push_back(c);
        continue;
      }
      if (!exists(sdir + "/" + c.file)) continue;  // created, then lost with its directory entry
      RecoveredChunk r = recover_chunk(sdir, c, m.columns.size());
      if (!r.had_header) {
        // Nothing received was in it: the file is removed.
        ::unlink((sdir + "/" + c.file).c_str());
        notices.push_back(sdir + "/" + c.file + ": removed (a crash left it without its header line)");
        continue;
      }
      if (!r.tail.empty()) {
        rejects.add(r.last_stamps, "partial line at end of recording", r.tail, false);
        partial += r.tail.size();
      }
      notices.push_back(
          sdir + "/" + c.file + ": recovered after a crash: " + std::to_string(r.chunk.samples) + " samples kept" +
          (r.tail.empty()
               ? std::string()
               : ", a partial last line of " + std::to_string(r.tail.size()) + " bytes moved to rejects.csv"));
      kept.push_back(r.chunk);
    }
    rejects.close();
    seg.chunks = std::move(kept);
    seg.samples = 0;
    double last_utc = 0.0;
    for (const auto& c : seg.chunks) {
      seg.samples += c.samples;
      if (c.samples > 0) last_utc = c.last_host_utc_s;
    }
    seg.rejects = rejects.count();
    seg.partial_bytes += partial;
    seg.end = io::SegmentEnd::recovered;
    seg.end_utc = last_utc > 0 ? iso_from_seconds(last_utc) : seg.start_utc;
    detail::sync_directory(sdir);
  }
  return notices;
}

class Recorder::Impl final : public SampleHandler {
 public:
  Impl(Source& src, RecorderOptions opt, io::RecordingManifest& m) : src_(src), opt_(std::move(opt)), m_(m) {
    if (!(opt_.chunk_seconds > 0 && std::isfinite(opt_.chunk_seconds)))
      throw UsageError(Field::chunk_seconds, "{chunk_seconds} must be a positive number of seconds");
    if (opt_.chunk_bytes < 4096) throw UsageError(Field::chunk_bytes, "{chunk_bytes} must be at least 4096");
    if (opt_.sync_interval_s <= 0 || opt_.sync_interval_s > 1.0)
      throw UsageError(Field::sync, "the sync interval is between 0 and 1 s");
    if (opt_.rate_hz && !(*opt_.rate_hz > 0 && std::isfinite(*opt_.rate_hz)))
      throw UsageError(Field::rate, "the rate must be a positive number of Hz");
    const std::string& dir = opt_.out_dir;
    if (dir.empty()) throw UsageError(Field::out, "{out} DIR is required: the recording directory");
    if (exists(dir) && !is_dir(dir)) throw UsageError(Field::out, dir + " is a file; {out} names a directory");
    if (is_dir(dir) && exists(dir + "/" + std::string(io::kManifestName))) {
      check_entry(dir + "/" + std::string(io::kManifestName), false);
      m_ = io::read_manifest(dir);
      existing_ = true;
      for (const auto& n : recover_recording(dir, m_)) notice(n);
      io::write_manifest(dir, m_);
    } else if (is_dir(dir)) {
      // A manifest's temporary (io/atomic_file.hpp; ".tmp" from earlier
      // versions) left by a run killed before its first rename.
      for (const auto& e : dir_entries(dir))
        if (e != std::string(io::kManifestName) + ".partial" && e != std::string(io::kManifestName) + ".tmp")
          throw UsageError(Field::out, dir +
                                           " is not empty and holds no cubecal recording (no manifest.json); "
                                           "record into a new or empty directory");
    } else {
      make_dirs(dir);
    }
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
      throw UsageError(Field::out, dir + ": cannot write there (" + std::strerror(errno) + ")");
    segment_index_ = 1;
    for (const auto& s : m_.segments) segment_index_ = std::max(segment_index_, s.index + 1);
    if (exists(segment_path_of(segment_index_)))
      throw UsageError(Field::out, printable_text(segment_path_of(segment_index_)) +
                                       " exists but the manifest does not name it: move it away, or record into a "
                                       "new directory");
    if (opt_.frame) {
      bin_.emplace(*opt_.frame);
      check_framing(names_of(*opt_.frame));
    } else {
      text_.emplace(opt_.text);
      if (!opt_.text.columns.empty() && existing_ && !m_.columns.empty() && m_.columns != opt_.text.columns)
        throw UsageError(Field::out, opt_.out_dir + " was recorded with the columns " + join(m_.columns) + ", not " +
                                         join(opt_.text.columns) + "; record into a new directory");
    }
    last_.reserve(64);
  }

  RecorderSummary run();

 private:
  // When the next flush, sync and status are due, and the samples and time
  // of the last status.
  struct Schedule {
    double next_flush = 0.0;
    double next_sync = 0.0;
    double next_status = 0.0;
    std::size_t status_samples = 0;
    double status_time = 0.0;
  };
  double stamp_batch();
  bool take(const ReadResult& r, const std::vector<char>& buf, double& now);
  void periodic(double now, Schedule& due);
  RecorderSummary finish(RecordEnd end, double now);

 public:
  void on_layout(const std::vector<std::string>& names) override {
    check_framing(names);
    names_ = names;
    time_idx_ = -1;
    if (!opt_.time_col.empty()) {
      for (std::size_t i = 0; i < names.size(); ++i)
        if (names[i] == opt_.time_col) time_idx_ = static_cast<int>(i);
      if (time_idx_ < 0) {
        char* end = nullptr;
        const long k = std::strtol(opt_.time_col.c_str(), &end, 10);
        if (end != nullptr && *end == '\0' && k >= 1 && static_cast<std::size_t>(k) <= names.size())
          time_idx_ = static_cast<int>(k - 1);
      }
      if (time_idx_ < 0) throw UsageError(Field::time_col, "no column '" + opt_.time_col + "' among " + join(names));
    } else {
      for (std::size_t i = 0; i < names.size() && time_idx_ < 0; ++i)
        if (io::looks_like_time_column(names[i])) time_idx_ = static_cast<int>(i);
    }
    if (!existing_ || m_.columns.empty()) {
      m_.format = std::string(io::kRecordingFormat);
      m_.columns = names;
      m_.time_column =
          time_idx_ >= 0 ? std::optional<std::string>(names[static_cast<std::size_t>(time_idx_)]) : std::nullopt;
      m_.rate_hz = opt_.rate_hz;
      m_.unit = opt_.unit;
      if (opt_.frame) {
        m_.framing.kind = io::RecordingFraming::Kind::binary;
        m_.framing.frame = opt_.frame->text;
      } else {
        m_.framing.kind = io::RecordingFraming::Kind::text;
        m_.framing.delimiter = delimiter_name(text_->delimiter());
      }
      m_.source = src_.describe();
    }
    if (opt_.rate_hz) expected_dt_ = 1.0 / *opt_.rate_hz;
  }

  void on_sample(std::string_view fields, std::span<const double> values) override {
    if (!chunk_)
      start_segment();  // at the first sample: a run without one records nothing
    else if (chunk_->bytes() >= opt_.chunk_bytes)
      rotate();
    chunk_->add(prefix_, fields, batch_utc_);
    if (time_idx_ >= 0) check_time(values[static_cast<std::size_t>(time_idx_)]);
    ++samples_;
    last_.assign(values.begin(), values.end());
    if (opt_.on_sample) opt_.on_sample(values);
  }

  void on_reject(std::string_view reason, std::string_view data, bool binary) override {
    if (!rejects_) {
      // Before the first sample (a comment, a partial first line, noise):
      // kept until the segment exists, up to a bound; past it only counted.
      if (pending_.size() < kMaxPending && pending_bytes_ + data.size() <= kMaxPendingBytes) {
        pending_.push_back({prefix_, std::string(reason), std::string(data), binary});
        pending_bytes_ += data.size();
      } else {
        ++pending_over_;
        pending_over_bytes_ += data.size();
      }
      return;
    }
    rejects_->add(prefix_, reason, data, binary);
  }

  io::RecordingManifest& m_ref() { return m_; }

 private:
  struct Pending {
    std::string prefix, reason, data;
    bool binary;
  };

  static std::vector<std::string> names_of(const FrameSpec& f) {
    std::vector<std::string> n;
    for (const auto& x : f.fields) n.push_back(x.name);
    return n;
  }

  void notice(const std::string& s) {
    if (opt_.on_notice) opt_.on_notice(s);
  }

  // A recording continued must keep its columns and framing.
  void check_framing(const std::vector<std::string>& names) const {
    if (!existing_ || m_.columns.empty()) return;
    if (!same_names(m_.columns, names))
      throw UsageError(Field::out, opt_.out_dir + " was recorded with the columns " + join(m_.columns) +
                                       " and this source gives " + join(names) + "; record into a new directory");
    const bool binary = opt_.frame.has_value();
    const bool was_binary = m_.framing.kind == io::RecordingFraming::Kind::binary;
    if (binary != was_binary)
      throw UsageError(Field::out, opt_.out_dir + " was recorded from " +
                                       (was_binary ? "binary frames" : "text lines") + " and this run reads " +
                                       (binary ? "binary frames" : "text lines") + "; record into a new directory");
    if (binary && m_.framing.frame != opt_.frame->text)
      throw UsageError(Field::out, opt_.out_dir + " was recorded with {frame} '" + m_.framing.frame + "', not '" +
                                       opt_.frame->text + "'; record into a new directory");
    if (!binary && text_ && text_->has_layout() && m_.framing.delimiter != delimiter_name(text_->delimiter()))
      throw UsageError(Field::out, opt_.out_dir + " was recorded from lines delimited by '" + m_.framing.delimiter +
                                       "', not '" + delimiter_name(text_->delimiter()) +
                                       "'; record into a new directory");
  }

  std::string segment_path() const { return opt_.out_dir + "/" + seg_.dir; }
  std::string segment_path_of(int index) const { return opt_.out_dir + "/" + segment_dir_name(index); }

  void start_segment() {
    seg_ = io::RecordingSegment{};
    seg_.index = segment_index_;
    seg_.dir = segment_dir_name(segment_index_);
    seg_.start_utc = io::utc_iso8601(static_cast<std::int64_t>(batch_.utc.tv_sec), batch_.utc.tv_nsec);
    seg_.start_mono_s = batch_.mono_s();
    seg_.end = io::SegmentEnd::open;
    const std::string sdir = segment_path();
    // The manifest names the segment before its directory exists, so that
    // a crash at any point leaves a recording a restart takes up.
    m_.segments.push_back(seg_);
    io::write_manifest(opt_.out_dir, m_);
    m_.segments.pop_back();
    if (::mkdir(sdir.c_str(), 0755) != 0) throw WriteFailure(sdir, errno);  // a new one, never one found there
    detail::sync_directory(opt_.out_dir, true);
    chunk_index_ = 1;
    chunk_ = std::make_unique<ChunkWriter>(sdir, chunk_file_name(chunk_index_), names_);
    chunk_start_mono_ = batch_.mono_s();
    rejects_ = std::make_unique<RejectsWriter>(sdir);
    if (existing_ && !m_.segments.empty()) {
      std::size_t total = 0;
      for (const auto& s : m_.segments) total += s.samples;
      notice(opt_.out_dir + " holds a recording of " + std::to_string(m_.segments.size()) + " segment(s), " +
             std::to_string(total) + " samples: appending segment " + std::to_string(seg_.index) + " (" + seg_.dir +
             ")");
    }
    m_.segments.push_back(seg_);
    for (const auto& p : pending_) rejects_->add(p.prefix, p.reason, p.data, p.binary);
    if (pending_over_ > 0) {
      rejects_->add(prefix_, std::to_string(pending_over_) + " more pieces of input before the first sample, not kept",
                    std::to_string(pending_over_bytes_) + " bytes (counted in partial_bytes)", false);
      seg_.partial_bytes += pending_over_bytes_;
    }
    pending_.clear();
    sync_all();
  }

  void rotate() {
    closed_.push_back(chunk_->close());
    ++chunk_index_;
    chunk_ = std::make_unique<ChunkWriter>(segment_path(), chunk_file_name(chunk_index_), names_);
    chunk_start_mono_ = batch_.mono_s();
    sync_all();
  }

  void check_time(double t) {
    if (have_prev_) {
      const double dt = t - prev_t_;
      if (dt < 0) {
        io::RecordingEvent e;
        e.kind = io::RecordingEvent::Kind::reset;
        e.sample = samples_;
        e.device_time = t;
        e.previous = prev_t_;
        seg_events_.push_back(e);
        ++resets_;
      } else if (expected_dt_ > 0) {
        if (dt > 1.5 * expected_dt_) {
          io::RecordingEvent e;
          e.kind = io::RecordingEvent::Kind::gap;
          e.sample = samples_;
          e.device_time = t;
          e.dt = dt;
          e.expected_dt = expected_dt_;
          seg_events_.push_back(e);
          ++gaps_;
        }
      } else if (dt > 0) {
        // No rate given: the median of the first intervals is the period.
        dts_.push_back(dt);
        if (dts_.size() == 31) {
          std::nth_element(dts_.begin(), dts_.begin() + 15, dts_.end());
          expected_dt_ = dts_[15];
        }
      }
    }
    prev_t_ = t;
    have_prev_ = true;
  }

  void flush_all() {
    if (chunk_) chunk_->flush();
    if (rejects_) rejects_->flush();
  }

  // fsync the data, then say so in the manifest.
  void sync_all() {
    if (!chunk_) return;
    chunk_->sync();
    rejects_->sync();
    write_manifest_now(false);
  }

  void write_manifest_now(bool closing) {
    io::RecordingSegment& s = m_.segments.back();
    s = seg_;
    s.chunks = closed_;
    if (chunk_ && !closing) s.chunks.push_back(chunk_->synced());
    s.samples = 0;
    for (const auto& c : s.chunks) s.samples += c.samples;
    s.rejects = rejects_ ? rejects_->synced_count() : 0;
    s.events = seg_events_;
    io::write_manifest(opt_.out_dir, m_);
  }

  RecorderStatus status(double now_mono) const {
    RecorderStatus st;
    st.elapsed_s = now_mono - start_mono_;
    st.samples = samples_;
    st.rejects = rejects_ ? rejects_->count() : pending_.size() + pending_over_;
    st.gaps = gaps_;
    st.resets = resets_;
    st.reconnects = reconnects_;
    st.device_rate_hz = expected_dt_ > 0 ? 1.0 / expected_dt_ : 0.0;
    st.names = names_;
    st.last = last_;
    std::size_t bytes = chunk_ ? chunk_->bytes() : 0;
    for (const auto& c : closed_) bytes += c.bytes;
    st.bytes = bytes;
    st.segment = chunk_ ? seg_.index : 0;
    st.chunk = chunk_ ? chunk_index_ : 0;
    return st;
  }

  friend class Recorder;

  Source& src_;
  RecorderOptions opt_;
  io::RecordingManifest& m_;
  bool existing_ = false;
  int segment_index_ = 1;
  std::optional<LineFramer> text_;
  std::optional<FrameDecoder> bin_;
  std::vector<std::string> names_;
  io::RecordingSegment seg_;
  std::vector<io::RecordingChunk> closed_;
  std::vector<io::RecordingEvent> seg_events_;
  std::unique_ptr<ChunkWriter> chunk_;
  std::size_t chunk_index_ = 0;
  double chunk_start_mono_ = 0.0;
  std::unique_ptr<RejectsWriter> rejects_;
  static constexpr std::size_t kMaxPending = 1000, kMaxPendingBytes = std::size_t{1} << 20;
  std::vector<Pending> pending_;
  std::size_t pending_bytes_ = 0, pending_over_ = 0, pending_over_bytes_ = 0;
  HostStamp batch_ = host_now();
  double batch_utc_ = 0.0;
  std::string prefix_ = ",,";
  double start_mono_ = 0.0;
  std::size_t samples_ = 0, gaps_ = 0, resets_ = 0, reconnects_ = 0;
  std::vector<double> last_;
  int time_idx_ = -1;
  bool have_prev_ = false;
  double prev_t_ = 0.0, expected_dt_ = 0.0;
  std::vector<double> dts_;
};

RecorderSummary Recorder::Impl::run() {
  std::vector<char> buf(opt_.read_buffer);
  batch_ = host_now();
  start_mono_ = batch_.mono_s();
  double now = start_mono_;
  Schedule due{now + opt_.flush_interval_s, now + opt_.sync_interval_s, now + opt_.status_interval_s, 0, now};
  RecordEnd end = RecordEnd::source_ended;
  const double deadline = opt_.duration_s > 0 ? start_mono_ + opt_.duration_s : 0.0;
  for (;;) {
    if (opt_.stop != nullptr && *opt_.stop != 0) {
      end = RecordEnd::stopped;
      break;
    }
    if (deadline > 0 && now >= deadline) {
      end = RecordEnd::duration;
      break;
    }
    double wake = std::min({due.next_flush, due.next_sync, due.next_status});
    if (deadline > 0) wake = std::min(wake, deadline);
    const int timeout_ms = static_cast<int>(std::clamp(std::ceil((wake - now) * 1000.0), 0.0, 200.0));
    const ReadResult r = src_.read(buf.data(), buf.size(), timeout_ms);
    const bool ended = take(r, buf, now);
    if (ended) break;
    periodic(now, due);
  }
  return finish(end, now);
}

// The host time of the bytes read now, and the stamp prefix of their lines.
double Recorder::Impl::stamp_batch() {
  batch_ = host_now();
  const double now = batch_.mono_s();
  batch_utc_ = batch_.utc_s();
  prefix_ = stamp_prefix(batch_);
  return now;
}

// What a read gave: bytes fed to the framer or decoder, or a source event;
// true when the source ended.
bool Recorder::Impl::take(const ReadResult& r, const std::vector<char>& buf, double& now) {
  if (r.status == ReadResult::Status::data) {
    now = stamp_batch();
    if (chunk_ && now - chunk_start_mono_ >= opt_.chunk_seconds && chunk_->samples() > 0) rotate();
    const std::string_view bytes(buf.data(), r.bytes);
    const auto ends = src_.record_ends();
    if (ends.empty()) {
      if (bin_)
        bin_->feed(bytes, *this);
      else
        text_->feed(bytes, *this);
      return false;
    }
    // Each record of the source (a datagram) ends a line, or a frame.
    std::size_t from = 0;
    for (const std::size_t to : ends) {
      if (bin_) {
        bin_->feed(bytes.substr(from, to - from), *this);
        bin_->drop_partial("partial frame at end of datagram", *this);
      } else {
        text_->feed(bytes.substr(from, to - from), *this);
        text_->end_record(*this);
      }
      from = to;
    }
  } else {
    now = stamp_batch();
    switch (r.status) {
      case ReadResult::Status::end: return true;
      case ReadResult::Status::lost:
        if (bin_)
          bin_->drop_partial("partial frame before the connection was lost", *this);
        else
          text_->drop_partial("partial line before the connection was lost", *this);
        notice(src_.describe() + ": connection lost; reconnecting");
        break;
      case ReadResult::Status::reconnected: {
        io::RecordingEvent e;
        e.kind = io::RecordingEvent::Kind::reconnect;
        e.sample = samples_;
        e.host_utc_s = batch_utc_;
        seg_events_.push_back(e);
        ++reconnects_;
        have_prev_ = false;  // the device time may restart
        notice(src_.describe() + ": reconnected");
        break;
      }
      default: break;
    }
  }
  return false;
}

// The flush, sync and status due at `now`.
void Recorder::Impl::periodic(double now, Schedule& due) {
  double& next_flush = due.next_flush;
  double& next_sync = due.next_sync;
  double& next_status = due.next_status;
  std::size_t& status_samples = due.status_samples;
  double& status_time = due.status_time;
  if (now >= next_flush) {
    flush_all();
    next_flush = now + opt_.flush_interval_s;
  }
  if (now >= next_sync) {
    sync_all();
    next_sync = now + opt_.sync_interval_s;
  }
  if (now >= next_status) {
    if (opt_.on_status) {
      RecorderStatus st = status(now);
      st.samples_per_s = now > status_time ? static_cast<double>(samples_ - status_samples) / (now - status_time) : 0.0;
      opt_.on_status(st);
    }
    status_samples = samples_;
    status_time = now;
    next_status = now + opt_.status_interval_s;
  }
}

// The end: what is held is a reject, the chunk closed, the segment clean.
RecorderSummary Recorder::Impl::finish(RecordEnd end, double now) {
  if (end == RecordEnd::source_ended) {
    if (bin_)
      bin_->drop_partial("partial frame at end of stream", *this);
    else
      text_->finish(*this);
  } else {
    if (bin_)
      bin_->drop_partial("partial frame at end of recording", *this);
    else
      text_->drop_partial("partial line at end of recording", *this);
  }
  RecorderSummary sum;
  sum.end = end;
  sum.status = status(now);
  sum.status.samples_per_s = now > start_mono_ ? static_cast<double>(samples_) / (now - start_mono_) : 0.0;
  sum.blank_lines = text_ ? text_->blank_lines() : 0;
  sum.layout_known = !names_.empty();
  if (!chunk_ && !pending_.empty()) {
    sum.unrecorded_rejects = pending_.size() + pending_over_;
    sum.first_unrecorded_reason = pending_.front().reason;
    sum.first_unrecorded_data = pending_.front().data;
  }
  if (chunk_) {
    closed_.push_back(chunk_->close());
    rejects_->close();
    seg_.end = io::SegmentEnd::clean;
    const HostStamp fin = host_now();
    seg_.end_utc = io::utc_iso8601(static_cast<std::int64_t>(fin.utc.tv_sec), fin.utc.tv_nsec);
    write_manifest_now(true);
    chunk_.reset();
    sum.segment_dir = segment_path();
    sum.chunks = closed_.size();
    sum.status.segment = seg_.index;
  }
  return sum;
}

Recorder::Recorder(Source& source, RecorderOptions opt)
    : impl_(std::make_unique<Impl>(source, std::move(opt), manifest_)) {}

Recorder::~Recorder() = default;

RecorderSummary Recorder::run() { return impl_->run(); }

void Recorder::flush() { impl_->flush_all(); }

}  // namespace cubecal::acquire
