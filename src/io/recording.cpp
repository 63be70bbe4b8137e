// A recording directory read as a record (recording.hpp): the manifest
// says which chunks hold the samples; each chunk is checked against it and
// parsed as the CSV file it is; the segments are placed on one clock and
// joined, their boundaries checked like any interval of a record.
#include "cubecal/io/recording.hpp"

#include <zlib.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <limits>
#include <optional>
#include <string_view>
#include <utility>

#include "cubecal/error.hpp"
#include "cubecal/io/delimited_reader.hpp"
#include "detail/file_buffer.hpp"
#include "cubecal/io/recording_manifest.hpp"
#include "../detail/magnitude.hpp"
#include "detail/series_timing.hpp"
#include "detail/shortest_text.hpp"

namespace cubecal::io {

namespace {

using detail::lower_case;
const auto& number = detail::shortest_text;

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// The column of `header` a spec (name or 1-based index, as TableOptions
// resolves it: exact name, else index, else name ignoring case) designates.
std::string resolve(const std::string& spec, const std::vector<std::string>& header, const std::string& manifest) {
  if (std::find(header.begin(), header.end(), spec) != header.end()) return spec;
  for (std::size_t i = 0; i < header.size(); ++i)
    if (spec == std::to_string(i + 1)) return header[i];
  for (const auto& h : header)
    if (lower_case(h) == lower_case(spec)) return h;
  throw InputError(manifest, 0, 0, "the recording has no column '" + spec + "' (its columns: " + joined(header) + ")",
                   "name one of its columns");
}

// Seconds since 1970 of the manifest's "2026-11-27T13:00:00.123456789Z",
// as whole seconds and the fraction (kept apart: a double of the sum would
// round the fraction to a quarter of a microsecond).
struct UtcTime {
  std::int64_t seconds = 0;
  double fraction = 0.0;
};

UtcTime parse_utc(const std::string& text, const std::string& manifest, int segment) {
  const auto bad = [&]() -> InputError {
    return InputError(manifest, 0, 0,
                      "segment " + std::to_string(segment) + ": start_utc \"" + text +
                          "\" is not a UTC time (2026-11-27T13:00:00.123456789Z)",
                      "the manifest of a cubecal recording directory");
  };
  std::tm tm{};
  int used = 0;
  if (std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%n", &tm.tm_year, &tm.tm_mon, &tm.tm_mday, &tm.tm_hour,
                  &tm.tm_min, &tm.tm_sec, &used) != 6)
    throw bad();
  tm.tm_year -= 1900;
  tm.tm_mon -= 1;
  UtcTime t;
  t.seconds = static_cast<std::int64_t>(::timegm(&tm));
  std::size_t p = static_cast<std::size_t>(used);
  if (p < text.size() && text[p] == '.') {
    double scale = 0.1;
    for (++p; p < text.size() && text[p] >= '0' && text[p] <= '9'; ++p, scale /= 10)
      t.fraction += (text[p] - '0') * scale;
  }
  if (p + 1 != text.size() || text[p] != 'Z') throw bad();
  return t;
}

// start_utc(b) - start_utc(a) in seconds.
double utc_difference(const UtcTime& b, const UtcTime& a) {
  return static_cast<double>(b.seconds - a.seconds) + (b.fraction - a.fraction);
}

std::uint32_t crc32_of(std::string_view bytes) {
  uLong crc = ::crc32(0L, Z_NULL, 0);
  constexpr std::size_t kPiece = std::size_t{1} << 30;
  for (std::size_t at = 0; at < bytes.size(); at += kPiece) {
    const std::size_t len = std::min(kPiece, bytes.size() - at);
    crc = ::crc32(crc, reinterpret_cast<const Bytef*>(bytes.data() + at), static_cast<uInt>(len));
  }
  return static_cast<std::uint32_t>(crc);
}

// How the samples are timed.
enum class Timing {
  column,     // a column's stamps (device time, or host_utc_s)
  host_mono,  // host_mono_s, placed segment by segment by start_utc
  rate,       // evenly spaced at a rate from each segment's first receive stamp
};

struct Plan {
  std::string manifest;             // DIR/manifest.json, for errors
  std::vector<std::string> header;  // host_mono_s, host_utc_s, the data columns
  std::vector<std::string> channels;
  std::vector<std::string> extras;  // SeriesOptions::table.extra_columns, resolved
  bool default_columns = false;
  std::vector<std::string> left_out;
  Timing timing = Timing::host_mono;
  std::string time;      // the column read as time (Timing::column, host_mono)
  double rate_hz = 0.0;  // Timing::rate
};

Plan plan_of(const RecordingManifest& m, const std::string& dir, const SeriesOptions& opt) {
  Plan p;
  p.manifest = dir + "/" + std::string(kManifestName);
  p.header = {std::string(kHostMonoColumn), std::string(kHostUtcColumn)};
  p.header.insert(p.header.end(), m.columns.begin(), m.columns.end());
  for (const auto& e : opt.table.extra_columns) p.extras.push_back(resolve(e, p.header, p.manifest));

  // The device time: named, or the manifest's, or found by its name as a
  // text file's is; a rate given beside one found without --time-col
  // overrides its stamps, as for a text file.
  std::string candidate;
  if (m.time_column) candidate = resolve(*m.time_column, p.header, p.manifest);
  if (candidate.empty()) {
    const auto it = std::find_if(m.columns.begin(), m.columns.end(), looks_like_time_column);
    if (it != m.columns.end()) candidate = *it;
  }
  if (!opt.time_col.empty()) {
    p.time = resolve(opt.time_col, p.header, p.manifest);
    p.timing = p.time == kHostMonoColumn ? Timing::host_mono : Timing::column;
  } else if (!candidate.empty() && opt.rate_hz == 0.0) {
    p.time = candidate;
    p.timing = Timing::column;
  } else if (opt.rate_hz > 0.0 || m.rate_hz) {
    p.timing = Timing::rate;
    p.rate_hz = opt.rate_hz > 0.0 ? opt.rate_hz : *m.rate_hz;
    if (!(p.rate_hz >= kMinRateHz && p.rate_hz <= kMaxRateHz))
      throw InputError(p.manifest, 0, 0,
                       "rate_hz " + number(p.rate_hz) + " is outside the range " + number(kMinRateHz) + " to " +
                           number(kMaxRateHz) + " Hz",
                       "give {rate} HZ");
  } else {
    p.time = std::string(kHostMonoColumn);
    p.timing = Timing::host_mono;
  }

  if (!opt.table.columns.empty()) {
    for (const auto& c : opt.table.columns) p.channels.push_back(resolve(c, p.header, p.manifest));
    return p;
  }
  p.default_columns = true;
  for (const auto& name : m.columns) {
    const bool out = name == p.time || name == candidate ||
                     std::find(p.extras.begin(), p.extras.end(), name) != p.extras.end() ||
                     (opt.skip_temperature && looks_like_temperature_column(name));
    (out ? p.left_out : p.channels).push_back(name);
  }
  if (p.channels.empty())
    throw InputError(p.manifest, 0, 0,
                     "no data columns besides the time and temperature columns (" + joined(p.left_out) + ")",
                     "name the columns to analyze");
  return p;
}

// Where global row `row` was read: its chunk and line.
struct ChunkPlace {
  std::string path;
  std::size_t first_row = 0;   // global row of its first sample
  std::size_t first_line = 0;  // 1-based line of its first sample
};

// The samples of one segment, as read.
struct SegmentData {
  std::vector<std::vector<double>> channels;
  std::vector<std::vector<double>> extra;
  std::vector<double> time;  // the time column's stamps (Timing::column, host_mono), as read
  double host_first = 0.0;   // host_mono_s of the first and last sample
  double host_last = 0.0;
  // Device clock resets (Timing::column): a stamp not after the one before
  // (the sensor restarted while the recorder ran on), with the receive
  // stamps of the two samples.
  struct Reset {
    std::size_t row = 0;  // in the segment
    double host_before = 0.0, host_at = 0.0;
  };
  std::vector<Reset> resets;
  // Reconnects of the source (Timing::rate): samples were lost while it was
  // away, so the even spacing starts again at the receive stamp of the
  // first sample after it.
  struct Restart {
    std::size_t row = 0;  // in the segment
    double host_at = 0.0;
  };
  std::vector<Restart> restarts;
  std::size_t rows() const { return channels.empty() ? 0 : channels[0].size(); }
};

void append(std::vector<double>& to, std::vector<double>& from) {
  if (to.empty())
    to = std::move(from);
  else
    to.insert(to.end(), from.begin(), from.end());
}

// The bytes of a chunk that hold samples: a closed chunk whole, once its
// size and CRC-32 match the manifest's; an open one up to its last complete
// line (the recorder may be writing it, or died in the middle of a line).
std::string_view checked_bytes(const FileBuffer& buf, const RecordingChunk& c, const std::string& path) {
  std::string_view bytes = buf.view();
  if (c.open) {
    const std::size_t end = bytes.rfind('\n');
    return end == std::string_view::npos ? std::string_view() : bytes.substr(0, end + 1);
  }
  const std::string hint =
      "the chunk changed since it was recorded: restore it from a copy, or read the chunks "
      "before it on their own";
  if (bytes.size() != c.bytes)
    throw InputError(path, 0, 0,
                     std::to_string(bytes.size()) + " bytes where the manifest recorded " + std::to_string(c.bytes),
                     hint);
  const std::uint32_t crc = crc32_of(bytes);
  if (crc != *c.crc32)
    throw InputError(path, 0, 0, "CRC-32 " + crc32_hex(crc) + " where the manifest recorded " + crc32_hex(*c.crc32),
                     hint);
  return bytes;
}

SegmentData read_segment(const std::string& dir, const RecordingSegment& seg, const Plan& p, const SeriesOptions& opt,
                         std::vector<ChunkPlace>& places, std::size_t first_row, std::size_t& bytes_read) {
  TableOptions topt;
  topt.columns = p.channels;
  topt.extra_columns = p.extras;
  const std::size_t time_slot = topt.extra_columns.size();
  if (!p.time.empty()) topt.extra_columns.push_back(p.time);
  const std::size_t host_slot = topt.extra_columns.size();
  topt.extra_columns.push_back(std::string(kHostMonoColumn));
  topt.threads = opt.table.threads;
  topt.missing_as_nan = opt.gaps == GapPolicy::skip;

  SegmentData d;
  d.channels.resize(p.channels.size());
  d.extra.resize(p.extras.size());
  bool first = true;
  double last_host_of_previous = 0.0;   // the previous chunk's last receive stamp
  std::vector<std::size_t> reconnects;  // Timing::rate: the rows the source came back at
  if (p.timing == Timing::rate)
    for (const auto& e : seg.events)
      if (e.kind == RecordingEvent::Kind::reconnect && e.sample > 0) reconnects.push_back(e.sample);
  std::sort(reconnects.begin(), reconnects.end());
  for (const auto& c : seg.chunks) {
    const std::string path = dir + "/" + seg.dir + "/" + c.file;
    if (c.open && !std::filesystem::exists(path)) continue;  // created after the manifest's last rewrite
    // The size and CRC first: a damaged closed chunk is named as such, not by
    // the NUL or binary bytes the damage left (parse_layout checks the text).
    const FileBuffer buf = FileBuffer::open(path, Content::raw);
    const std::string_view text = checked_bytes(buf, c, path);
    const std::size_t header_end = text.find('\n');
    if (header_end == std::string_view::npos || header_end + 1 == text.size()) continue;  // no sample yet
    const Table layout = parse_layout(text, path);
    if (layout.header != p.header)
      throw InputError(path, 1, 0, "columns " + joined(layout.header) + " where the manifest has " + joined(p.header),
                       "the chunk does not belong to this recording");
    Table t = parse_table(text, path, topt);
    bytes_read += t.bytes;
    if (t.rows() == 0) continue;
    places.push_back({path, first_row + d.rows(), t.first_data_line});
    std::vector<double>& host = t.extra[host_slot];
    for (std::size_t r : reconnects)
      if (r >= d.rows() && r < d.rows() + host.size()) d.restarts.push_back({r, host[r - d.rows()]});
    if (first) d.host_first = host.front();
    d.host_last = host.back();
    first = false;
    for (std::size_t k = 0; k < d.channels.size(); ++k) append(d.channels[k], t.data[k]);
    for (std::size_t k = 0; k < d.extra.size(); ++k) append(d.extra[k], t.extra[k]);
    if (p.timing == Timing::column && p.time != kHostUtcColumn) {
      const std::vector<double>& stamps = t.extra[time_slot];
      for (std::size_t i = 0; i < stamps.size(); ++i) {
        const bool first_of_chunk = i == 0;
        if (first_of_chunk && d.time.empty()) continue;
        const double before = first_of_chunk ? d.time.back() : stamps[i - 1];
        if (stamps[i] <= before)
          d.resets.push_back({d.time.size() + i, first_of_chunk ? last_host_of_previous : host[i - 1], host[i]});
      }
    }
    last_host_of_previous = host.back();
    if (!p.time.empty()) append(d.time, t.extra[time_slot]);
  }
  return d;
}

struct Reader {
  const std::string& dir;
  const RecordingManifest& m;
  const Plan& p;
  const SeriesOptions& opt;
  std::vector<ChunkPlace> places;
  // The device clock resets placed so far: the record's row, the stamps as read.
  struct ResetNote {
    std::size_t row;
    double before, after;
  };
  mutable std::vector<ResetNote> reset_notes;

  InputError at(std::size_t row, std::string problem, std::string hint) const {
    auto it = std::upper_bound(places.begin(), places.end(), row,
                               [](std::size_t r, const ChunkPlace& c) { return r < c.first_row; });
    if (it == places.begin()) return InputError(dir, 0, 0, std::move(problem), std::move(hint));
    --it;
    return InputError(it->path, it->first_line + (row - it->first_row), 0, std::move(problem), std::move(hint));
  }

  // An empty record named `label` with the recording's channels, extras and units.
  Series empty_series(const std::string& label) const {
    Series s;
    s.file = label;
    s.names = p.channels;
    s.default_columns = p.default_columns;
    s.left_out = p.left_out;
    s.extra_names = p.extras;
    s.channels.resize(p.channels.size());
    s.extra.resize(p.extras.size());
    if (m.unit) {
      s.units.assign(p.channels.size(), *m.unit);
      s.units_from = "the recording's manifest";
    }
    return s;
  }

  // Where the segments' samples lie on the record's time axis: the offset
  // of a device clock that started again, and the previous segment's last
  // stamps.
  struct Placement {
    double offset = 0.0;      // Timing::column: added to the previous segment's stamps
    double last_stamp = 0.0;  // the previous segment's last stamp, as read
    double last_host = 0.0;   // its last receive stamp, on the first segment's monotonic clock
    double first_host = 0.0;  // the first receive stamp of the record, on that clock
    bool any = false;         // a segment with samples placed before
  };

  // The time stamps of segment d (n rows, its first receive stamp
  // host_first on the first segment's clock) placed on the record's axis.
  // row0: the segment's first row in the record, for the errors.
  void place_segment(SegmentData& d, std::size_t n, std::size_t row0, double to_origin, double host_first,
                     Placement& placed) const {
    double& offset = placed.offset;
    double& last_stamp = placed.last_stamp;
    const double last_host = placed.last_host;
    const double first_host = placed.first_host;
    const bool any = placed.any;
    if (p.timing == Timing::host_mono) {
      for (double& t : d.time) t += to_origin;
    } else if (p.timing == Timing::rate) {
      d.time.resize(n);
      double start = host_first;
      std::size_t start_row = 0;
      auto next = d.restarts.begin();
      for (std::size_t i = 0; i < n; ++i) {
        if (next != d.restarts.end() && next->row == i) {
          start = next->host_at + to_origin;
          start_row = i;
          ++next;
        }
        d.time[i] = (start - first_host) + static_cast<double>(i - start_row) / p.rate_hz;
      }
    } else if (any && p.time != kHostUtcColumn) {
      // A device clock that ran on across the break (its interval agrees
      // with the host's) is kept; one that started again is placed where
      // the host clock puts the segment.
      const double host_gap = host_first - last_host;
      const double device_gap = d.time.front() - last_stamp;
      if (!(device_gap > 0.0 && std::fabs(device_gap - host_gap) <= std::max(1.0, 0.01 * host_gap)))
        offset = (last_stamp + offset + host_gap) - d.time.front();
    }
    if (p.timing == Timing::column) {
      // A reset inside the segment: the samples after it placed where the
      // receive stamps put them, as a new segment would be.
      std::size_t from_row = 0;
      for (const auto& r : d.resets) {
        const double before = d.time[r.row - 1];  // as read
        for (std::size_t i = from_row; i < r.row; ++i) d.time[i] += offset;
        const double last = d.time[r.row - 1];  // placed
        if (!(r.host_at > r.host_before))
          throw at(row0 + r.row,
                   "the device clock went back from " + number(before) + " s to " + number(d.time[r.row]) +
                       " s, and the sample after it was received with the one before (same receive stamp): "
                       "nothing places it in time",
                   "read the recording up to the reset, or fix the device's clock");
        reset_notes.push_back({row0 + r.row, before, d.time[r.row]});
        offset = (last + (r.host_at - r.host_before)) - d.time[r.row];
        from_row = r.row;
      }
      last_stamp = d.time.back();
      for (std::size_t i = from_row; i < n; ++i) d.time[i] += offset;
    }
  }

  // Every sample placed: a stamp, and receive stamps that increase.
  void check_times(const std::vector<double>& time) const {
    for (std::size_t row = 0; row < time.size(); ++row)
      if (std::isnan(time[row]))
        throw at(row, "missing time stamp",
                 "a sample cannot be placed without its time: fill in the stamp or remove the row");
    if (p.timing == Timing::host_mono)
      for (std::size_t row = 1; row < time.size(); ++row)
        if (!(time[row] > time[row - 1]))
          throw at(row, "receive stamp " + number(time[row]) + " s is not after the previous one",
                   "the recording has no device time column and no rate: several samples were received at once; "
                   "give {rate} HZ");
  }

  // The segments [from, to) of the manifest as one record named `label`;
  // none when they hold no sample and `skip_empty`.
  std::optional<Series> read(std::size_t from, std::size_t to, const std::string& label, bool skip_empty) {
    places.clear();
    reset_notes.clear();
    const UtcTime origin = parse_utc(m.segments.at(0).start_utc, p.manifest, m.segments[0].index);
    const double origin_mono = m.segments[0].start_mono_s;
    Series s = empty_series(label);
    std::vector<double> time;
    std::size_t bytes = 0;
    Placement placed;
    for (std::size_t k = from; k < to; ++k) {
      const RecordingSegment& seg = m.segments[k];
      SegmentData d = read_segment(dir, seg, p, opt, places, s.samples(), bytes);
      const std::size_t n = d.rows();
      if (n == 0) continue;
      // This segment's monotonic clock on the first segment's: the two
      // clocks differ by the difference of their UTC starts.
      const double to_origin =
          utc_difference(parse_utc(seg.start_utc, p.manifest, seg.index), origin) - (seg.start_mono_s - origin_mono);
      const double host_first = d.host_first + to_origin;
      const double host_last = d.host_last + to_origin;
      if (!placed.any) placed.first_host = host_first;
      place_segment(d, n, s.samples(), to_origin, host_first, placed);
      placed.last_host = host_last;
      placed.any = true;
      for (std::size_t c = 0; c < s.channels.size(); ++c) append(s.channels[c], d.channels[c]);
      for (std::size_t c = 0; c < s.extra.size(); ++c) append(s.extra[c], d.extra[c]);
      append(time, d.time);
    }
    if (!placed.any && skip_empty) return std::nullopt;
    s.gaps = opt.gaps;
    s.bytes = bytes;
    check_values(s);
    check_times(time);
    SeriesOptions so = opt;
    if (p.timing == Timing::rate) so.rate_hz = p.rate_hz;
    const std::string time_name =
        p.timing == Timing::rate ? std::string("(rate ") + number(p.rate_hz) + " Hz)" : p.time;
    // The time axis names placed stamps: at a reset, say which the file holds.
    detail::finish_series(s, std::move(time), time_name, true, so,
                          [this](std::size_t row, std::string problem, std::string hint) {
                            for (const ResetNote& r : reset_notes)
                              if (r.row == row)
                                problem += " (the device clock went back there from " + number(r.before) + " s to " +
                                           number(r.after) + " s: the times after it are placed by the receive stamps)";
                            return at(row, std::move(problem), std::move(hint));
                          });
    return s;
  }

  // The LSB scaling and the magnitudes every statistic can hold, as for a
  // text file.
  void check_values(Series& s) const {
    if (opt.lsb.size() > 1 && opt.lsb.size() != s.channels.size())
      throw UsageError(Field::counts_per_unit, dir + ": " + std::to_string(opt.lsb.size()) + " LSB values for " +
                                                   std::to_string(s.channels.size()) + " columns (" + joined(s.names) +
                                                   "): give one value for every column, or one per column");
    for (std::size_t c = 0; c < s.channels.size(); ++c) {
      std::vector<double>& v = s.channels[c];
      const double lsb = opt.lsb_of(c);
      if (lsb != 1.0)
        for (double& x : v) x /= lsb;
      const double top = largest_magnitude(v).largest;
      const bool huge = top > kMaxMagnitude;
      if (!huge && !(top != 0.0 && top < kMinMagnitude)) continue;
      std::size_t row = 0;
      while (row + 1 < v.size() && std::fabs(v[row]) != top) ++row;
      throw at(row,
               "column " + s.names[c] + ": value " + number(v[row]) +
                   (huge ? " exceeds the magnitude " + number(kMaxMagnitude)
                         : " is the largest of its column, below the magnitude " + number(kMinMagnitude)) +
                   " whose square a variance can hold",
               "rescale the column, e.g. to other units");
    }
  }
};

void check_options(const SeriesOptions& opt, const std::string& dir) {
  if (opt.table.skip_rows != 0)
    throw UsageError(dir + " is a recording directory, whose chunks have no preamble rows: leave out the rows to skip");
  if (!opt.topics.empty()) throw UsageError(dir + " is a recording directory, not a ROS bag: leave out the topics");
  if (!opt.dataset.empty())
    throw UsageError(Field::dataset, dir + " is a recording directory, not an HDF5 file: leave out the dataset");
}

}  // namespace

bool looks_like_recording(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path d(path);
  return std::filesystem::is_directory(d, ec) && std::filesystem::exists(d / kManifestName, ec) &&
         !std::filesystem::exists(d / "metadata.yaml", ec);
}

Series read_recording(const std::string& dir, const SeriesOptions& opt) {
  check_options(opt, dir);
  const RecordingManifest m = read_manifest(dir);
  if (m.segments.empty())
    throw InputError(dir + "/" + std::string(kManifestName), 0, 0, "the recording has no segment yet",
                     "wait for the recorder to write its first samples");
  const Plan p = plan_of(m, dir, opt);
  Reader r{dir, m, p, opt, {}, {}};
  return *r.read(0, m.segments.size(), dir, false);
}

std::vector<Series> read_recording_segments(const std::string& dir, const SeriesOptions& opt) {
  check_options(opt, dir);
  const RecordingManifest m = read_manifest(dir);
  const Plan p = plan_of(m, dir, opt);
  Reader r{dir, m, p, opt, {}, {}};
  std::vector<Series> runs;
  for (std::size_t k = 0; k < m.segments.size(); ++k)
    if (auto s = r.read(k, k + 1, dir + "/" + m.segments[k].dir, true)) runs.push_back(std::move(*s));
  if (runs.empty())
    throw InputError(dir + "/" + std::string(kManifestName), 0, 0, "the recording has no segment with samples",
                     "record some data first");
  return runs;
}

}  // namespace cubecal::io
