#include "field_flags.hpp"

namespace cubecal::cli {

FieldFlag field_flag(Field f) noexcept {
  using Prefix = FieldFlag::Prefix;
  switch (f) {
    case Field::acc_bias: return {"--acc-bias", Prefix::no};
    case Field::acc_columns: return {"--acc-columns", Prefix::no};
    case Field::acc_scale: return {"--acc-scale", Prefix::no};
    case Field::allow_partial: return {"--allow-partial", Prefix::no};
    case Field::alpha: return {"--alpha", Prefix::no};
    case Field::baud: return {"--baud", Prefix::no};
    case Field::bias: return {"--bias", Prefix::yes};
    case Field::binary: return {"--binary", Prefix::yes};
    case Field::bins_per_decade: return {"--bins-per-decade", Prefix::yes};
    case Field::bootstrap: return {"--bootstrap", Prefix::yes};
    case Field::chunk_bytes: return {"--chunk-bytes", Prefix::no};
    case Field::chunk_seconds: return {"--chunk-seconds", Prefix::no};
    case Field::ci: return {"--ci", Prefix::yes};
    case Field::columns: return {"--columns", Prefix::yes};
    case Field::composite: return {"--composite", Prefix::no};
    case Field::composite_bootstrap: return {"--composite-bootstrap", Prefix::no};
    case Field::counts_per_unit: return {"--lsb", Prefix::yes};
    case Field::dataset: return {"--dataset", Prefix::yes};
    case Field::datasheet: return {"--datasheet", Prefix::yes};
    case Field::delimiter: return {"--delimiter", Prefix::no};
    case Field::detrend: return {"--detrend", Prefix::no};
    case Field::drift_window: return {"--drift-window", Prefix::no};
    case Field::duration: return {"--duration", Prefix::yes};
    case Field::earth_axis: return {"--earth-axis", Prefix::no};
    case Field::edf: return {"--edf", Prefix::no};
    case Field::efficiency: return {"--efficiency", Prefix::yes};
    case Field::estimators: return {"--for", Prefix::yes};
    case Field::exponents: return {};  // Python's psd(fit=...): the CLI fits fixed exponents
    case Field::field_column: return {"--field-col", Prefix::yes};
    case Field::field_norm: return {"--field-norm", Prefix::yes};
    case Field::fit_range: return {"--fit-min/--fit-max", Prefix::yes};
    case Field::flicker: return {"--flicker", Prefix::no};
    case Field::force: return {"--force", Prefix::no};
    case Field::format: return {"--format", Prefix::no};
    case Field::frame: return {"--frame", Prefix::no};
    case Field::from_signal: return {"--from-signal", Prefix::no};
    case Field::g: return {"--g", Prefix::no};
    case Field::gaps: return {"--gaps", Prefix::yes};
    case Field::gnuplot: return {"--gnuplot", Prefix::yes};
    case Field::gyro_columns: return {"--gyro-columns", Prefix::no};
    case Field::gyro_scale: return {"--gyro-scale", Prefix::no};
    case Field::header_bytes: return {"--header-bytes", Prefix::no};
    case Field::inflate: return {"--inflate", Prefix::yes};
    case Field::init_static: return {"--init-static", Prefix::no};
    case Field::interval_samples: return {"--interval-samples", Prefix::no};
    case Field::keep_scripts: return {"--keep-scripts", Prefix::no};
    case Field::lsb: return {"--model-lsb", Prefix::yes};
    case Field::mag_columns: return {"--columns", Prefix::yes};
    case Field::margin: return {"--margin", Prefix::no};
    case Field::max_samples: return {"--max-samples", Prefix::no};
    case Field::memory: return {"--memory", Prefix::yes};
    case Field::method: return {"--method", Prefix::no};
    case Field::min_frequency: return {"--fmin", Prefix::yes};
    case Field::min_intervals: return {"--min-intervals", Prefix::no};
    case Field::min_plateau: return {"--min-plateau", Prefix::no};
    case Field::model: return {"--model", Prefix::yes};
    case Field::noise: return {"--noise", Prefix::yes};
    case Field::order: return {"--order", Prefix::no};
    case Field::out: return {"--out", Prefix::yes};
    case Field::overlap: return {"--overlap", Prefix::yes};
    case Field::plateaus: return {"--margin/--min-plateau/--ref-tolerance/--window", Prefix::yes};
    case Field::polynomial_order: return {"--order", Prefix::yes};
    case Field::psd: return {"--psd", Prefix::yes};
    case Field::rate: return {"--rate", Prefix::yes};
    case Field::reference_columns: return {"--ref-columns", Prefix::yes};
    case Field::reference_tolerance: return {"--ref-tolerance", Prefix::no};
    case Field::reject: return {"--reject", Prefix::no};
    case Field::reject_sigma: return {"--reject", Prefix::yes};
    case Field::report: return {"--report", Prefix::yes};
    case Field::samples: return {};  // the record itself
    case Field::sampling: return {"--time-col/--rate", Prefix::yes};
    case Field::scales: return {};  // the wavelet scales follow from the record
    case Field::schedule: return {"--schedule", Prefix::yes};
    case Field::segment_length: return {"--segment", Prefix::yes};
    case Field::segments: return {};  // the record's pieces at gaps
    case Field::skip_rows: return {"--skip-rows", Prefix::no};
    case Field::source: return {"SOURCE", Prefix::no};
    case Field::starts: return {"--starts", Prefix::no};
    case Field::stat: return {"--stat", Prefix::yes};
    case Field::step: return {"--step", Prefix::yes};
    case Field::stream: return {"--stream", Prefix::no};
    case Field::sync: return {};  // the recorder's sync interval is fixed by the CLI
    case Field::taus: return {"--taus", Prefix::yes};
    case Field::target: return {"--target", Prefix::no};
    case Field::temp_index: return {"--temp-col", Prefix::yes};
    case Field::temp_order: return {"--temp-order", Prefix::yes};
    case Field::time_col: return {"--time-col", Prefix::yes};
    case Field::topics: return {"--topic", Prefix::yes};
    case Field::twin_check: return {"--twin-check", Prefix::no};
    case Field::type: return {"--type", Prefix::yes};
    case Field::unit: return {"--unit", Prefix::yes};
    case Field::units: return {"--unit", Prefix::yes};
    case Field::wic_replicates: return {"--wic-replicates", Prefix::yes};
    case Field::window: return {"--window", Prefix::yes};
  }
  return {};
}

std::string flag_of(Field f) {
  const FieldFlag ff = field_flag(f);
  return std::string(ff.flag.empty() ? field_name(f) : ff.flag);
}

std::string flag_words(std::string_view text) { return render_fields(text, flag_of); }

std::string cli_message(const Error& e) {
  std::string msg = flag_words(e.text());
  if (const auto* u = dynamic_cast<const UsageError*>(&e);
      u != nullptr && u->field() && u->named() == UsageError::Named::in_front) {
    const FieldFlag ff = field_flag(*u->field());
    if (ff.prefix == FieldFlag::Prefix::yes) msg = std::string(ff.flag) + ": " + msg;
  }
  return msg;
}

}  // namespace cubecal::cli
