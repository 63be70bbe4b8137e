// Field names and the rendering of field markers (field.hpp).
#include "cubecal/field.hpp"

#include <utility>

namespace cubecal {

std::string_view field_name(Field f) noexcept {
  switch (f) {
    case Field::acc_bias: return "acc_bias";
    case Field::acc_columns: return "acc_columns";
    case Field::acc_scale: return "acc_scale";
    case Field::allow_partial: return "allow_partial";
    case Field::alpha: return "alpha";
    case Field::baud: return "baud";
    case Field::bias: return "bias";
    case Field::binary: return "binary";
    case Field::bins_per_decade: return "bins_per_decade";
    case Field::bootstrap: return "bootstrap";
    case Field::chunk_bytes: return "chunk_bytes";
    case Field::chunk_seconds: return "chunk_seconds";
    case Field::ci: return "ci";
    case Field::columns: return "columns";
    case Field::composite: return "composite";
    case Field::composite_bootstrap: return "composite_bootstrap";
    case Field::counts_per_unit: return "counts_per_unit";
    case Field::dataset: return "dataset";
    case Field::datasheet: return "datasheet";
    case Field::delimiter: return "delimiter";
    case Field::detrend: return "detrend";
    case Field::drift_window: return "drift_window";
    case Field::duration: return "duration";
    case Field::earth_axis: return "earth_axis";
    case Field::edf: return "edf";
    case Field::efficiency: return "efficiency";
    case Field::estimators: return "estimators";
    case Field::exponents: return "exponents";
    case Field::field_column: return "field_column";
    case Field::field_norm: return "field_norm";
    case Field::fit_range: return "fit_range";
    case Field::flicker: return "flicker";
    case Field::force: return "force";
    case Field::format: return "format";
    case Field::frame: return "frame";
    case Field::from_signal: return "from_signal";
    case Field::g: return "g";
    case Field::gaps: return "gaps";
    case Field::gnuplot: return "gnuplot";
    case Field::gyro_columns: return "gyro_columns";
    case Field::gyro_scale: return "gyro_scale";
    case Field::header_bytes: return "header_bytes";
    case Field::inflate: return "inflate";
    case Field::init_static: return "init_static";
    case Field::interval_samples: return "interval_samples";
    case Field::keep_scripts: return "keep_scripts";
    case Field::lsb: return "lsb";
    case Field::mag_columns: return "mag_columns";
    case Field::margin: return "margin";
    case Field::max_samples: return "max_samples";
    case Field::memory: return "memory";
    case Field::method: return "method";
    case Field::min_frequency: return "min_frequency";
    case Field::min_intervals: return "min_intervals";
    case Field::min_plateau: return "min_plateau";
    case Field::model: return "model";
    case Field::noise: return "noise";
    case Field::order: return "order";
    case Field::out: return "out";
    case Field::overlap: return "overlap";
    case Field::plateaus: return "plateaus";
    case Field::polynomial_order: return "polynomial_order";
    case Field::psd: return "psd";
    case Field::rate: return "rate";
    case Field::reference_columns: return "reference_columns";
    case Field::reference_tolerance: return "reference_tolerance";
    case Field::reject: return "reject";
    case Field::reject_sigma: return "reject_sigma";
    case Field::report: return "report";
    case Field::samples: return "samples";
    case Field::sampling: return "sampling";
    case Field::scales: return "scales";
    case Field::schedule: return "schedule";
    case Field::segment_length: return "segment_length";
    case Field::segments: return "segments";
    case Field::skip_rows: return "skip_rows";
    case Field::source: return "source";
    case Field::starts: return "starts";
    case Field::stat: return "stat";
    case Field::step: return "step";
    case Field::stream: return "stream";
    case Field::sync: return "sync";
    case Field::taus: return "taus";
    case Field::target: return "target";
    case Field::temp_index: return "temp_index";
    case Field::temp_order: return "temp_order";
    case Field::time_col: return "time_col";
    case Field::topics: return "topics";
    case Field::twin_check: return "twin_check";
    case Field::type: return "type";
    case Field::unit: return "unit";
    case Field::units: return "units";
    case Field::wic_replicates: return "wic_replicates";
    case Field::window: return "window";
  }
  return {};
}

std::optional<Field> field_from_name(std::string_view name) noexcept {
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    if (field_name(f) == name) return f;
  }
  return std::nullopt;
}

std::string marker(Field f) {
  std::string m = "{";
  m += field_name(f);
  m += '}';
  return m;
}

std::string render_fields(std::string_view text, const std::function<std::string(Field)>& word) {
  std::string out;
  out.reserve(text.size());
  std::size_t i = 0;
  while (i < text.size()) {
    const std::size_t open = text.find('{', i);
    if (open == std::string_view::npos) break;
    const std::size_t close = text.find('}', open + 1);
    if (close == std::string_view::npos) break;
    out.append(text, i, open - i);
    const std::optional<Field> f = field_from_name(text.substr(open + 1, close - open - 1));
    if (f) {
      out += word(*f);
      i = close + 1;
    } else {
      out += '{';
      i = open + 1;
    }
  }
  out.append(text, i);
  return out;
}

namespace {

std::function<std::string(Field)>& face_vocabulary() {
  static std::function<std::string(Field)> words;
  return words;
}

}  // namespace

void set_face_words(std::function<std::string(Field)> words) { face_vocabulary() = std::move(words); }

std::string face_words(std::string_view text) {
  const auto& words = face_vocabulary();
  return words ? render_fields(text, words) : library_words(text);
}

std::string library_words(std::string_view text) {
  return render_fields(text, [](Field f) { return std::string(field_name(f)); });
}

}  // namespace cubecal
