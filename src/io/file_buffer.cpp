// Whole-file access. Plain files are memory-mapped so that the parser threads
// read the page cache directly (no copy, no read() buffer management); gzip
// files are recognised by their magic bytes and inflated into one heap block,
// since the parser needs the whole text in memory anyway.
#include "detail/file_buffer.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <utility>
#include <vector>

#include "cubecal/error.hpp"
#include "detail/hdf5_reader.hpp"
#include "cubecal/io/mcap.hpp"
#include "cubecal/io/ros1_bag.hpp"
#include "cubecal/io/ros2_bag.hpp"
#include "cubecal/io/ulog.hpp"
#include "detail/binary_input.hpp"

namespace cubecal::io {

namespace {

// malloc'ed rather than new[]'ed so that growth can use realloc, which moves
// large blocks by remapping pages instead of copying them.
struct HeapBlock {
  char* data = nullptr;
  std::size_t size = 0;
  std::size_t capacity = 0;

  HeapBlock() = default;
  HeapBlock(const HeapBlock&) = delete;
  HeapBlock& operator=(const HeapBlock&) = delete;
  ~HeapBlock() { std::free(data); }

  void reserve(std::size_t n) {
    if (n <= capacity) return;
    auto* p = static_cast<char*>(std::realloc(data, n));
    if (p == nullptr) throw std::bad_alloc();
    data = p;
    capacity = n;
  }
  void swap(HeapBlock& other) noexcept {
    std::swap(data, other.data);
    std::swap(size, other.size);
    std::swap(capacity, other.capacity);
  }
  void shrink_to_fit() {
    if (size == capacity || size == 0) return;
    if (auto* p = static_cast<char*>(std::realloc(data, size))) {
      data = p;
      capacity = size;
    }
  }
};

class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() { ::close(fd_); }
  int get() const { return fd_; }

 private:
  int fd_;
};

[[noreturn]] void throw_os_error(const std::string& path, const char* action, int err) {
  throw InputError(path, 0, 0, std::string(action) + ": " + std::strerror(err));
}

bool is_gzip(std::string_view bytes) {
  return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
         static_cast<unsigned char>(bytes[1]) == 0x8b;
}

// Inflates every gzip member of `in` (gzip allows concatenated members, as
// produced by `cat a.gz b.gz` or by parallel compressors). The size field in
// a member's trailer is never used to allocate: a damaged or hostile file
// can claim any size there (4 GB in five bytes). The block starts from the
// compressed size and grows geometrically with what was actually inflated,
// and the start of the text is checked for binary data as soon as it is out.
// The check of a file's first bytes for what it may hold.
void check_start(std::string_view head, const std::string& label, bool decompressed, Content content) {
  if (content == Content::raw) return;
  if (content == Content::series && is_known_binary_format(head)) return;
  detail::check_text_start(head, label, decompressed);
}

// More text than the budget: refused before it is taken.
[[noreturn]] void refuse_inflated(const std::string& path, std::size_t limit, std::size_t consumed) {
  throw InputError(path, 0, 0,
                   "gzip-compressed text that inflates to more than the memory budget of " +
                       std::to_string((limit + 999'999) / 1'000'000) + " MB ({memory}), " + std::to_string(consumed) +
                       " compressed bytes in",
                   "stream it with {stream}, or give a larger {memory}");
}

void inflate_gzip(const std::string& path, std::string_view in, HeapBlock& out, Content content, std::size_t limit) {
  z_stream zs{};
  // 16 + MAX_WBITS: gzip wrapper only; zlib checks the CRC-32 and length
  // trailer of each member itself.
  if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK) throw std::bad_alloc();
  struct Guard {
    z_stream* zs;
    ~Guard() { inflateEnd(zs); }
  } guard{&zs};

  // Text compresses ~4-10x: four times the compressed size (which is real,
  // unlike the trailer) is reserved, mapped lazily, up to 1 GiB; more grows
  // by realloc, which remaps large blocks rather than copying them. (A 64 MiB
  // cap cost 13 % more user time reading a 86 MB .gz of 212 MB.)
  constexpr std::size_t kMinFirstReserve = std::size_t{1} << 16;
  constexpr std::size_t kMaxFirstReserve = std::size_t{1} << 30;
  // With a limit, never more than one byte past it (that byte says the text
  // is larger).
  const std::size_t cap =
      limit == 0 ? std::numeric_limits<std::size_t>::max() : std::max(limit + 1, detail::kTextProbeBytes);
  out.reserve(std::min(std::clamp(in.size() * 4, kMinFirstReserve, kMaxFirstReserve), cap));
  static_assert(kMinFirstReserve >= detail::kTextProbeBytes);

  // zlib counts in uInt: feed and drain at most 1 GiB per call.
  constexpr std::size_t kStep = std::size_t{1} << 30;
  std::size_t consumed = 0;
  std::size_t member = 1;
  bool head_checked = false;
  // Byte offset in the compressed file of what zlib looks at now.
  const auto at = [&] {
    return "at byte offset " + std::to_string(consumed - zs.avail_in) + ", in gzip member " + std::to_string(member) +
           ", after " + std::to_string(out.size) + " bytes of text";
  };
  const auto check_head = [&] {
    head_checked = true;
    check_start(std::string_view(out.data, out.size), path, true, content);
  };
  for (;;) {
    if (zs.avail_in == 0 && consumed < in.size()) {
      const std::size_t n = std::min(kStep, in.size() - consumed);
      zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data() + consumed));
      zs.avail_in = static_cast<uInt>(n);
      consumed += n;
    }
    if (out.size >= cap) refuse_inflated(path, limit, consumed - zs.avail_in);
    if (out.size == out.capacity) out.reserve(std::min(out.capacity * 2, cap));
    std::size_t room = std::min(kStep, out.capacity - out.size);
    // Until the start of the text is checked, inflate no more than that.
    if (!head_checked) room = std::min(room, detail::kTextProbeBytes - out.size);
    zs.next_out = reinterpret_cast<Bytef*>(out.data + out.size);
    zs.avail_out = static_cast<uInt>(room);

    const int rc = inflate(&zs, Z_NO_FLUSH);
    out.size += room - zs.avail_out;
    if (!head_checked && out.size == detail::kTextProbeBytes) check_head();
    if (limit != 0 && out.size > limit) refuse_inflated(path, limit, consumed - zs.avail_in);

    if (rc == Z_STREAM_END) {
      if (zs.avail_in == 0 && consumed == in.size()) {
        if (!head_checked) check_head();
        return;
      }
      inflateReset(&zs);  // next member
      ++member;
      continue;
    }
    if (rc == Z_OK) continue;
    if (rc == Z_BUF_ERROR && zs.avail_out != 0 && zs.avail_in == 0 && consumed == in.size()) {
      throw InputError(path, 0, 0, "truncated gzip stream: the data end " + at(),
                       "the file is incomplete; copy or download it again");
    }
    if (rc == Z_BUF_ERROR) continue;  // output full: grown at the top of the loop
    if (rc == Z_MEM_ERROR) throw std::bad_alloc();
    throw InputError(path, 0, 0, "corrupt gzip data " + at() + ": " + (zs.msg != nullptr ? zs.msg : "inflate failed"),
                     "the file is damaged; copy or download it again");
  }
}

// A binary file is refused from its first bytes, before a large one is
// mapped (a 2 GB file of zeros costs no more than a small one). A gzip file
// is checked once its start is inflated.
void check_plain_start(const std::string& path, int fd, std::size_t size, Content content) {
  const std::size_t want = std::min(size, detail::kTextProbeBytes);
  std::vector<char> head(want);
  std::size_t got = 0;
  while (got < want) {
    const ssize_t n = ::pread(fd, head.data() + got, want - got, static_cast<off_t>(got));
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      throw_os_error(path, "cannot read file", errno);
    }
    got += static_cast<std::size_t>(n);
  }
  const std::string_view start(head.data(), got);
  if (!is_gzip(start)) check_start(start, path, false, content);
}

// Pipes and character devices cannot be mapped: read them to the end, into a
// block that grows geometrically. Their start is checked as soon as it is in
// (an endless stream of zeros is refused, not read until memory runs out).
void read_all(const std::string& path, int fd, HeapBlock& out, Content content) {
  out.reserve(std::size_t{1} << 20);
  static_assert((std::size_t{1} << 20) >= detail::kTextProbeBytes);
  bool head_checked = false;
  const auto check_head = [&] {
    head_checked = true;
    const std::string_view head(out.data, out.size);
    if (!is_gzip(head)) check_start(head, path, false, content);
  };
  for (;;) {
    if (out.size == out.capacity) out.reserve(out.capacity * 2);
    const ssize_t n = ::read(fd, out.data + out.size, out.capacity - out.size);
    if (n == 0) {
      if (!head_checked) check_head();
      return;
    }
    if (n < 0) {
      if (errno == EINTR) continue;
      throw_os_error(path, "cannot read file", errno);
    }
    out.size += static_cast<std::size_t>(n);
    if (!head_checked && out.size >= detail::kTextProbeBytes) check_head();
  }
}

}  // namespace

bool is_known_binary_format(std::string_view head) noexcept {
  return (head.size() >= 6 && head.substr(0, 6) == std::string_view("\x93NUMPY", 6)) ||
         head.starts_with(kRos1BagMagic) || looks_like_mcap(head) || looks_like_sqlite(head) || looks_like_ulog(head) ||
         looks_like_hdf5(head);
}

struct FileBuffer::Impl {
  void* map = nullptr;
  std::size_t map_size = 0;
  int fd = -1;  // the mapped file, for copy()
  HeapBlock heap;
  std::string_view text;

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() { unmap(); }

  void unmap() {
    if (map != nullptr) ::munmap(map, map_size);
    map = nullptr;
    map_size = 0;
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
};

FileBuffer FileBuffer::open(const std::string& path_arg, Content content, std::size_t max_inflated) {
  FileBuffer fb;
  const bool stdin_input = path_arg == kStdinPath;
  const std::string path = stdin_input ? std::string(kStdinLabel) : path_arg;
  fb.path_ = path;
  fb.impl_ = std::make_unique<Impl>();
  Impl& impl = *fb.impl_;

  const int raw_fd = stdin_input ? ::dup(STDIN_FILENO) : ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (raw_fd < 0) throw_os_error(path, "cannot open file", errno);
  const Fd fd(raw_fd);
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) throw_os_error(path, "cannot open file", errno);
  if (S_ISDIR(st.st_mode)) throw_os_error(path, "cannot open file", EISDIR);

  std::string_view raw;
  // A regular file of size 0 may still have content (/proc, /sys): read to its end.
  if (S_ISREG(st.st_mode) && st.st_size > 0) {
    check_plain_start(path, fd.get(), static_cast<std::size_t>(st.st_size), content);
    impl.map_size = static_cast<std::size_t>(st.st_size);
    // Not MAP_POPULATE: the parser maps a window at a time (populate) and
    // drops it behind (release), so that a large file never sits in this
    // process's memory at once.
    impl.map = ::mmap(nullptr, impl.map_size, PROT_READ, MAP_PRIVATE, fd.get(), 0);
    if (impl.map == MAP_FAILED) {
      impl.map = nullptr;
      throw_os_error(path, "cannot read file", errno);
    }
    raw = std::string_view(static_cast<const char*>(impl.map), impl.map_size);
    impl.fd = ::dup(fd.get());  // copy() reads through it; -1 (no copies) is only slower
  } else {
    read_all(path, fd.get(), impl.heap, content);
    raw = std::string_view(impl.heap.data, impl.heap.size);
  }

  if (!is_gzip(raw)) {
    // The parser threads each walk their own part of the file: ask the
    // kernel to read ahead so they don't stall on page faults one by one.
    if (impl.map != nullptr) ::madvise(impl.map, impl.map_size, MADV_WILLNEED);
    impl.text = raw;
    return fb;
  }

  fb.gzip_ = true;
  HeapBlock inflated;
  if (impl.map != nullptr) ::madvise(impl.map, impl.map_size, MADV_SEQUENTIAL);
  inflate_gzip(path, raw, inflated, content, max_inflated);
  inflated.shrink_to_fit();
  impl.unmap();
  impl.heap.swap(inflated);
  impl.text = std::string_view(impl.heap.data, impl.heap.size);
  return fb;
}

FileBuffer::FileBuffer(FileBuffer&&) noexcept = default;
FileBuffer& FileBuffer::operator=(FileBuffer&&) noexcept = default;
FileBuffer::~FileBuffer() = default;

std::string_view FileBuffer::view() const noexcept { return impl_ ? impl_->text : std::string_view{}; }

namespace {

// The whole pages of a mapping that hold [b, e), or nothing when [b, e) is
// not in the mapping (the text of a gzip file or of the standard input).
std::pair<char*, std::size_t> pages_of(const void* map, std::size_t map_size, std::string_view part) noexcept {
  if (map == nullptr || part.empty()) return {nullptr, 0};
  const auto base = reinterpret_cast<std::uintptr_t>(map);
  const auto b = reinterpret_cast<std::uintptr_t>(part.data());
  const std::uintptr_t e = b + part.size();
  if (e <= base || b >= base + map_size) return {nullptr, 0};
  static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  const std::uintptr_t first = std::max(b, base) / page * page;
  const std::uintptr_t last = (std::min(e, base + map_size) + page - 1) / page * page;
  return {reinterpret_cast<char*>(first), static_cast<std::size_t>(last - first)};
}

}  // namespace

// Advice only: a kernel without MADV_POPULATE_READ (before Linux 5.14) maps
// the pages on first touch instead; a failed release leaves them mapped.
void FileBuffer::populate(std::string_view part) const noexcept {
  if (!impl_) return;
  const auto [p, n] = pages_of(impl_->map, impl_->map_size, part);
#ifdef MADV_POPULATE_READ
  if (n != 0) ::madvise(p, n, MADV_POPULATE_READ);
#endif
}

bool FileBuffer::copy(std::string_view part, char* out) const noexcept {
  if (!impl_ || impl_->map == nullptr || impl_->fd < 0 || part.empty()) return false;
  const auto base = reinterpret_cast<std::uintptr_t>(impl_->map);
  const auto b = reinterpret_cast<std::uintptr_t>(part.data());
  if (b < base || b + part.size() > base + impl_->map_size) return false;
  auto offset = static_cast<off_t>(b - base);
  std::size_t done = 0;
  while (done < part.size()) {
    const ssize_t n = ::pread(impl_->fd, out + done, part.size() - done, offset);
    if (n <= 0) {
      if (n < 0 && errno == EINTR) continue;
      return false;
    }
    done += static_cast<std::size_t>(n);
    offset += n;
  }
  return true;
}

void FileBuffer::release(std::string_view part) const noexcept {
  if (!impl_) return;
  const auto [p, n] = pages_of(impl_->map, impl_->map_size, part);
  if (n != 0) ::madvise(p, n, MADV_DONTNEED);
}

}  // namespace cubecal::io
