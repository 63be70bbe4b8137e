#include "output.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <streambuf>
#include <string_view>

#include "cubecal/error.hpp"
#include "cubecal/io/atomic_file.hpp"
#include "cubecal/io/output_path.hpp"

namespace cubecal::cli {

namespace {

std::string g(double v) { return fmt::format("{:.6e}", v); }

}  // namespace

std::string rate_text(double hz) { return fmt::format("{:.6g}", hz); }

std::string excluded_taus_warning(const TauListOutcome& t, const std::vector<ExcludedTau>& model) {
  if (t.excluded.empty() && model.empty()) return {};
  const auto list = [](const std::vector<ExcludedTau>& ex) {
    std::string s;
    for (const auto& e : ex) s += fmt::format("{}{:.6g} s ({})", s.empty() ? "" : "; ", e.tau, e.reason);
    return s;
  };
  std::string line = "cubecal: warning: --taus:";
  if (!t.excluded.empty())
    line += fmt::format(" {} listed tau{} not evaluated: {}", t.excluded.size(), t.excluded.size() == 1 ? "" : "s",
                        list(t.excluded));
  if (!model.empty())
    line += fmt::format("{} {} listed tau{} left out of the model fit: {}", t.excluded.empty() ? "" : ";", model.size(),
                        model.size() == 1 ? "" : "s", list(model));
  return line + " (record longer data or list smaller taus)";
}

std::string merged_taus_note(const TauListOutcome& t) {
  if (t.merged.empty()) return {};
  std::string items;
  for (const auto& m : t.merged)
    items += fmt::format("{}{:.6g} s with {:.6g} s (m = {})", items.empty() ? "" : ", ", m.tau, m.kept_tau, m.m);
  return "cubecal: note: --taus: listed taus on the same averaging factor are one point: " + items;
}

void write_dev_table(std::ostream& out, const pipeline::DevResult& r, const DevContext& ctx) {
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    const auto& ch = r.channels[c];
    if (c > 0) out << '\n';
    fmt::print(out, "{} — {} ({} data), {} samples at {} Hz", ch.name, to_string(r.stat), to_string(r.type), r.samples,
               rate_text(r.rate_hz));
    if (r.segments > 1) fmt::print(out, ", {} segments split at gaps ({} long enough)", r.segments, r.segments_used);
    if (ctx.intervals)
      fmt::print(out, "\n{:>8} {:>13} {:>9} {:>6} {:>9} {:>13} {:>13} {:>13}\n", "AF", "tau [s]", "n", "alpha", "edf",
                 "min", to_string(r.stat), "max");
    else
      fmt::print(out, "\n{:>8} {:>13} {:>9} {:>13}\n", "AF", "tau [s]", "n", to_string(r.stat));
    for (const auto& p : ch.points) {
      if (ctx.intervals)
        fmt::print(out, "{:>8} {:>13.6g} {:>9} {:>6} {:>9.4g} {:>13.5e} {:>13.5e} {:>13.5e}\n", p.m, p.tau, p.n,
                   p.alpha, p.edf, p.interval.lo, p.dev, p.interval.hi);
      else
        fmt::print(out, "{:>8} {:>13.6g} {:>9} {:>13.5e}\n", p.m, p.tau, p.n, p.dev);
    }
  }
  if (ctx.intervals)
    fmt::print(out, "\nmin/max: {:.1f} % confidence interval, {} EDF, noise type alpha per tau\n", 100.0 * ctx.ci,
               ctx.edf_method);
  if (r.window_bound > 0 && !r.channels.empty()) {
    // Which factors were summed at which stride (the same for every channel).
    const auto& ch = r.channels[0];
    std::size_t first_strided = 0;
    while (first_strided < ch.strides.size() && ch.strides[first_strided] == 1) ++first_strided;
    if (first_strided < ch.strides.size() && (r.stat == Stat::oadev || r.stat == Stat::ohdev))
      fmt::print(out,
                 "streamed in one pass (window bound {} samples): AF up to {} fully overlapping, from {} on "
                 "at a stride of 2^L samples ({} at AF {}), AF rounded to a multiple of the stride\n",
                 r.window_bound, first_strided > 0 ? ch.points[first_strided - 1].m : 0, ch.points[first_strided].m,
                 ch.strides.back(), ch.points.back().m);
    else
      fmt::print(out, "streamed in one pass (window bound {} samples): every AF {}\n", r.window_bound,
                 r.stat == Stat::oadev || r.stat == Stat::ohdev ? "fully overlapping" : "non-overlapping");
  }
}

void write_dev_csv(std::ostream& out, const pipeline::DevResult& r, const DevContext& ctx) {
  // A streamed run adds the stride of each point's terms as a last column.
  const bool streamed = r.window_bound > 0;
  out << (streamed ? "column,af,tau,n,alpha,edf,lo,dev,hi,stride\n" : "column,af,tau,n,alpha,edf,lo,dev,hi\n");
  for (const auto& ch : r.channels)
    for (std::size_t k = 0; k < ch.points.size(); ++k) {
      const auto& p = ch.points[k];
      fmt::print(out, "{},{},{},{},{},{},{},{},{}", ch.name, p.m, p.tau, p.n,
                 ctx.intervals ? std::to_string(p.alpha) : "", ctx.intervals ? g(p.edf) : "",
                 ctx.intervals ? g(p.interval.lo) : "", g(p.dev), ctx.intervals ? g(p.interval.hi) : "");
      if (streamed) fmt::print(out, ",{}", k < ch.strides.size() ? ch.strides[k] : 1);
      out << '\n';
    }
}

std::vector<std::string> write_analysis_files(const std::string& dir, const pipeline::AnalysisResult& r,
                                              const pipeline::OutputContext& ctx) {
  namespace fs = std::filesystem;
  const auto files = pipeline::analysis_files(r, ctx);  // every text first: an error writes nothing
  fs::create_directories(dir);
  std::vector<std::string> written;
  for (const auto& file : files) {
    io::write_file((fs::path(dir) / file.name).string(), file.text);
    written.push_back(file.name);
    if (!file.missing.empty())
      std::cerr << "cubecal: note: " << file.name << " has no " << file.missing << " terms (no " << file.missing
                << " channel in the record): the keys are commented out, fill them before use\n";
  }
  return written;
}

// An ostream's buffer over the AtomicFile: full buffers are written as they
// fill; a failed write sets the stream's badbit.
class AtomicFileBuf : public std::streambuf {
 public:
  explicit AtomicFileBuf(io::AtomicFile& file) : file_(file) { setp(buf_, buf_ + sizeof buf_); }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    const bool ok = file_.write(std::string_view(pbase(), static_cast<std::size_t>(pptr() - pbase())));
    setp(buf_, buf_ + sizeof buf_);
    return ok;
  }
  io::AtomicFile& file_;
  char buf_[1 << 16];
};

struct OutputFile::Impl {
  explicit Impl(const std::string& path) : file(path), buf(file), out(&buf) {}
  io::AtomicFile file;
  AtomicFileBuf buf;
  std::ostream out;
};

OutputFile::OutputFile(std::string path, bool force) : path_(std::move(path)) {
  io::check_output_file(path_, force);
  impl_ = std::make_unique<Impl>(path_);
  if (!impl_->file.is_open())
    throw UsageError("cannot write " + path_ + " (check the directory exists and is writable)");
}

OutputFile::~OutputFile() = default;

std::ostream& OutputFile::stream() { return impl_->out; }

void OutputFile::commit() {
  impl_->out.flush();
  if (!impl_->out || !impl_->file.commit()) throw UsageError("could not finish writing " + path_ + " (disk full?)");
}

}  // namespace cubecal::cli

namespace cubecal::cli {

ResultOutput::ResultOutput(const std::string& path, bool force) : path_(path) {
  if (!path_.empty()) file_ = std::make_unique<OutputFile>(path_, force);
}

std::ostream& ResultOutput::stream() { return file_ ? file_->stream() : std::cout; }

void ResultOutput::finish() {
  if (!file_) return;
  file_->commit();
  std::cerr << "cubecal: wrote " << path_ << '\n';
}

}  // namespace cubecal::cli
