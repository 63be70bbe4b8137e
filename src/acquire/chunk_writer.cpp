// Chunk files (chunk_writer.hpp).
#include "cubecal/acquire/chunk_writer.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "cubecal/acquire/write_failure.hpp"
#include "cubecal/error.hpp"
#include "detail/append_file.hpp"

namespace cubecal::acquire {

std::string chunk_file_name(std::size_t index) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "chunk-%06zu.csv", index);
  return buf;
}

std::string chunk_header(const std::vector<std::string>& columns) {
  std::string h(io::kHostMonoColumn);
  h += ',';
  h += io::kHostUtcColumn;
  for (const auto& c : columns) {
    h += ',';
    h += c;
  }
  return h;
}

ChunkWriter::ChunkWriter(const std::string& dir, std::string file, const std::vector<std::string>& columns) {
  file_ = std::make_unique<detail::AppendFile>(dir + "/" + file);
  synced_.file = std::move(file);
  synced_.open = true;
  file_->append(chunk_header(columns));
  file_->append("\n");
}

ChunkWriter::~ChunkWriter() = default;

const std::string& ChunkWriter::path() const noexcept { return file_->path(); }
std::size_t ChunkWriter::bytes() const noexcept { return file_->size(); }

void ChunkWriter::add(std::string_view prefix, std::string_view fields, double host_utc_s) {
  std::string& b = file_->buffer();
  b.append(prefix);
  b.append(fields);
  b.push_back('\n');
  if (samples_ == 0) first_utc_ = host_utc_s;
  last_utc_ = host_utc_s;
  ++samples_;
  file_->maybe_flush();
}

void ChunkWriter::flush() { file_->flush(); }

void ChunkWriter::sync() {
  file_->sync();
  synced_.samples = samples_;
  synced_.bytes = file_->written();
  synced_.first_host_utc_s = first_utc_;
  synced_.last_host_utc_s = last_utc_;
}

io::RecordingChunk ChunkWriter::close() {
  file_->close();
  io::RecordingChunk c = synced_;
  c.samples = samples_;
  c.bytes = file_->written();
  c.first_host_utc_s = first_utc_;
  c.last_host_utc_s = last_utc_;
  c.crc32 = file_->crc();
  c.open = false;
  synced_ = c;
  return c;
}

namespace {

double host_utc_of(std::string_view line) {
  const auto c1 = line.find(',');
  if (c1 == std::string_view::npos) return 0.0;
  const auto c2 = line.find(',', c1 + 1);
  const std::string_view f = line.substr(c1 + 1, c2 == std::string_view::npos ? std::string_view::npos : c2 - c1 - 1);
  double v = 0.0;
  std::from_chars(f.data(), f.data() + f.size(), v);
  return v;
}

}  // namespace

RecoveredChunk recover_chunk(const std::string& dir, const io::RecordingChunk& as_manifest, std::size_t columns) {
  const std::string path = dir + "/" + as_manifest.file;
  // Read, cut and fsync'd through one descriptor of the regular file itself:
  // a symbolic link (to a file outside the recording) is never followed.
  const int fd = detail::open_regular(path, O_RDWR);
  if (fd < 0)
    throw InputError(path, 0, 0,
                     errno == ELOOP || errno == EINVAL
                         ? "the chunk the manifest names is not a regular file (a symbolic link?); a recording holds "
                           "regular files only: put the file itself there or record into a new directory"
                         : "the chunk the manifest names cannot be read (" + std::string(std::strerror(errno)) + ")");
  std::string text;
  {
    char buf[1 << 16];
    for (;;) {
      const ssize_t n = ::read(fd, buf, sizeof buf);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        const int err = errno;
        ::close(fd);
        throw InputError(path, 0, 0, std::string("the chunk cannot be read (") + std::strerror(err) + ")");
      }
      if (n == 0) break;
      text.append(buf, static_cast<std::size_t>(n));
    }
  }
  const std::size_t commas = columns + 1;  // host_mono_s,host_utc_s,<columns>
  // The header line, then every complete line; past the vouched-for part a
  // line must look like a sample.
  std::size_t cut = 0, samples = 0;
  std::size_t p = 0;
  bool header = true;
  std::string_view first, last;
  while (p < text.size()) {
    const auto nl = text.find('\n', p);
    if (nl == std::string::npos) break;
    const std::string_view line(text.data() + p, nl - p);
    if (nl >= as_manifest.bytes) {
      const bool nul = line.find('\0') != std::string_view::npos;
      const auto n = static_cast<std::size_t>(std::count(line.begin(), line.end(), ','));
      if (nul || (!header && n != commas)) break;
    }
    if (!header) {
      if (samples == 0) first = line;
      last = line;
      ++samples;
    }
    header = false;
    p = nl + 1;
    cut = p;
  }
  RecoveredChunk r;
  r.tail = text.substr(cut);
  const int rc = cut < text.size() ? ::ftruncate(fd, static_cast<off_t>(cut)) : 0;
  const int rc2 = rc == 0 ? ::fsync(fd) : -1;
  const int err = errno;
  ::close(fd);
  if (rc != 0 || rc2 != 0) throw WriteFailure(path, err);
  r.chunk = as_manifest;
  r.chunk.samples = samples;
  r.chunk.bytes = cut;
  r.chunk.crc32 = static_cast<std::uint32_t>(::crc32_z(0L, reinterpret_cast<const Bytef*>(text.data()), cut));
  r.chunk.first_host_utc_s = samples > 0 ? host_utc_of(first) : 0.0;
  r.chunk.last_host_utc_s = samples > 0 ? host_utc_of(last) : 0.0;
  r.chunk.open = false;
  r.had_header = cut > 0;
  r.last_stamps = ",,";
  if (samples > 0) {
    const auto c1 = last.find(',');
    const auto c2 = c1 == std::string_view::npos ? c1 : last.find(',', c1 + 1);
    if (c2 != std::string_view::npos) r.last_stamps = std::string(last.substr(0, c2 + 1));
  }
  return r;
}

}  // namespace cubecal::acquire
