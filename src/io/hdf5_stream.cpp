// An HDF5 file streamed (container_streams.hpp): read_hdf5's dataset a
// hyperslab of rows at a time, with read_series' time column, default
// columns, LSB, magnitude and timing checks; the rate from the first slab's
// stamps. Errors name the row and column as read_series does (FILE:ROW:COL).
#include <algorithm>
#include <cmath>
#include <map>

#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "detail/container_streams.hpp"
#include "detail/hdf5_reader.hpp"
#include "detail/shortest_text.hpp"
#include "detail/stream_timing.hpp"

namespace cubecal::io::detail {

namespace {

constexpr std::size_t kSlabRows = std::size_t{1} << 16;

class Hdf5Stream final : public SampleStream {
 public:
  Hdf5Stream(const std::string& path, const SeriesOptions& opt)
      : rows_(path, opt.dataset), opt_(opt), timing_(opt, false, path, "") {
    file_ = path;
    total_bytes_ = rows_.rows();
    Table head = rows_.slab(0, std::min(kSlabRows, rows_.rows()));
    choose_columns(head);
    head = select_columns(std::move(head), topt_);
    if (head.data.empty())
      throw InputError(file_, 0, 0, "no data columns besides the time column", "name the columns to analyze");
    names_ = head.names;
    for (std::size_t k = 0; k < extra_count_; ++k) extra_names_.push_back(head.extra_names[k]);
    check_lsb(opt);
    top_.assign(head.data.size() + head.extra.size(), 0.0);
    std::vector<double> stamps;
    if (!time_spec_.empty()) {
      time_name_ = head.extra_names[extra_count_];
      time_field_ = head.extra_indices[extra_count_];
      stamps = head.extra[extra_count_];
    }
    timing_ = StreamTiming(opt, timing_on_, file_, time_name_);
    timing_.start(stamps, place(0));
    rate_hz_ = timing_.rate_hz();
    rate_from_time_ = timing_.rate_from_time();
    if (!timing_on_) time_name_.clear();
    pending_ = std::move(head);
    have_pending_ = true;
  }

  bool next(SampleChunk& out) override {
    if (!have_pending_) {
      if (next_row_ >= rows_.rows()) return finish();
      pending_ = select_columns(rows_.slab(next_row_, std::min(kSlabRows, rows_.rows() - next_row_)), topt_);
    }
    have_pending_ = false;
    Table& t = pending_;
    const std::size_t rows = t.data.empty() ? 0 : t.data[0].size();
    check_magnitudes(t);
    if (!time_spec_.empty()) timing_.check(t.extra[extra_count_], next_row_, place(next_row_));
    out.channels.resize(t.data.size());
    for (std::size_t c = 0; c < t.data.size(); ++c) {
      out.channels[c] = std::move(t.data[c]);
      if (scale_[c] != 1.0)
        for (double& v : out.channels[c]) v /= scale_[c];
    }
    out.extra.resize(extra_count_);
    for (std::size_t k = 0; k < extra_count_; ++k) out.extra[k] = std::move(t.extra[k]);
    next_row_ += rows;
    rows_read_ = bytes_read_ = next_row_;
    return rows > 0;
  }

 private:
  // The time column and the default columns, as read_series takes them.
  void choose_columns(const Table& all) {
    topt_ = opt_.table;
    if (!opt_.time_col.empty()) {
      time_spec_ = opt_.time_col;
      timing_on_ = true;
    } else {
      const auto it = std::find_if(all.header.begin(), all.header.end(), looks_like_time_column);
      if (it != all.header.end()) {
        time_spec_ = *it;
        timing_on_ = opt_.rate_hz == 0.0;
      } else if (opt_.rate_hz == 0.0) {
        throw UsageError(file_ +
                         ": no sampling rate: no column is named as a time column (t, time, "
                         "t_s, timestamp...): give {rate} HZ or {time_col} NAME");
      }
    }
    if (topt_.columns.empty() && all.has_header) {
      default_columns_ = true;
      for (const std::string& name : all.header) {
        bool out = !time_spec_.empty() && (name == time_spec_ || lower_case(name) == lower_case(time_spec_));
        for (const auto& e : opt_.table.extra_columns) out = out || name == e;
        out = out || (opt_.skip_temperature && looks_like_temperature_column(name));
        (out ? left_out_ : topt_.columns).push_back(name);
      }
      if (topt_.columns.empty())
        throw InputError(file_, 0, 0, "no data columns besides the time column", "name the columns to analyze");
    }
    extra_count_ = topt_.extra_columns.size();
    if (!time_spec_.empty()) topt_.extra_columns.push_back(time_spec_);
  }

  void check_lsb(const SeriesOptions& opt) {
    if (opt.lsb.size() > 1 && opt.lsb.size() != names_.size()) {
      std::string list;
      for (const auto& n : names_) list += (list.empty() ? "" : ",") + n;
      throw UsageError(Field::counts_per_unit, file_ + ": " + std::to_string(opt.lsb.size()) + " LSB values for " +
                                                   std::to_string(names_.size()) + " columns (" + list +
                                                   "): give one value for every column, or one per column");
    }
    for (std::size_t c = 0; c < names_.size(); ++c) scale_.push_back(opt.lsb_of(c));
  }

  // Values whose squares no variance can hold (read_series' check_magnitudes).
  void check_magnitudes(const Table& t) {
    const auto check = [&](const std::vector<double>& v, std::size_t field, double scale, double& top) {
      for (std::size_t i = 0; i < v.size(); ++i) {
        const double a = std::fabs(v[i]) / scale;
        if (a > kMaxMagnitude)
          throw InputError(file_, next_row_ + i + 1, field + 1,
                           "value " + shortest_text(v[i]) +
                               (scale != 1.0 ? " (" + shortest_text(v[i] / scale) + " after the LSB)" : "") +
                               " exceeds the magnitude " + shortest_text(kMaxMagnitude) +
                               " whose square a variance can hold",
                           "rescale the column, e.g. to other units");
        if (a > top) {
          top = a;
          top_at_[field] = next_row_ + i;
        }
      }
    };
    for (std::size_t c = 0; c < t.data.size(); ++c) check(t.data[c], t.indices[c], scale_[c], top_[c]);
    for (std::size_t c = 0; c < t.extra.size(); ++c)
      check(t.extra[c], t.extra_indices[c], 1.0, top_[t.data.size() + c]);
    fields_ = t.indices;
    fields_.insert(fields_.end(), t.extra_indices.begin(), t.extra_indices.end());
  }

  // At the end: no column too small for a variance.
  bool finish() {
    for (std::size_t c = 0; c < top_.size() && c < fields_.size(); ++c) {
      if (top_[c] == 0.0 || top_[c] >= kMinMagnitude) continue;
      throw InputError(file_, top_at_[fields_[c]] + 1, fields_[c] + 1,
                       "value " + shortest_text(top_[c]) + " is the largest of its column, below the magnitude " +
                           shortest_text(kMinMagnitude) + " whose square a variance can hold",
                       "rescale the column, e.g. to other units");
    }
    return false;
  }

  PlaceError place(std::size_t) const {
    return [this](std::size_t row, std::string what, std::string hint) {
      return InputError(file_, row + 1, time_field_ + 1, std::move(what), std::move(hint));
    };
  }

  Hdf5Rows rows_;
  SeriesOptions opt_;
  StreamTiming timing_;
  TableOptions topt_;
  std::string time_spec_;
  bool timing_on_ = false, have_pending_ = false;
  std::size_t extra_count_ = 0, time_field_ = 0, next_row_ = 0;
  std::vector<double> scale_, top_;
  std::vector<std::size_t> fields_;
  std::map<std::size_t, std::size_t> top_at_;
  Table pending_;
};

}  // namespace

std::unique_ptr<SampleStream> open_hdf5_stream(const std::string& path, const SeriesOptions& opt) {
  if (!opt.binary.channels.empty() || !looks_like_hdf5(file_head(path, std::size_t{1} << 16))) return nullptr;
  return std::make_unique<Hdf5Stream>(path, opt);
}

}  // namespace cubecal::io::detail
