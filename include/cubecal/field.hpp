/// @file
/// The request fields an error message may name, as a type. A UsageError
/// carries the field at fault; a message that refers to another field writes
/// a marker, the field's name in braces ("leave out {stream}"). The library
/// renders a marker in its own words (the field's name), each face in its own:
/// the CLI as the flag (`--stream`), Python as the keyword (`stream=`).
#pragma once
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace cubecal {

/// One enumerator per field, named as the request member it stands for.
enum class Field {
  acc_bias,
  acc_columns,
  acc_scale,
  allow_partial,
  alpha,
  baud,
  bias,
  binary,
  bins_per_decade,
  bootstrap,
  chunk_bytes,
  chunk_seconds,
  ci,
  columns,
  composite,
  composite_bootstrap,
  counts_per_unit,
  dataset,
  datasheet,
  delimiter,
  detrend,
  drift_window,
  duration,
  earth_axis,
  edf,
  efficiency,
  estimators,
  exponents,
  field_column,
  field_norm,
  fit_range,
  flicker,
  force,
  format,
  frame,
  from_signal,
  g,
  gaps,
  gnuplot,
  gyro_columns,
  gyro_scale,
  header_bytes,
  inflate,
  init_static,
  interval_samples,
  keep_scripts,
  lsb,
  mag_columns,
  margin,
  max_samples,
  memory,
  method,
  min_frequency,
  min_intervals,
  min_plateau,
  model,
  noise,
  order,
  out,
  overlap,
  plateaus,
  polynomial_order,
  psd,
  rate,
  reference_columns,
  reference_tolerance,
  reject,
  reject_sigma,
  report,
  samples,
  sampling,
  scales,
  schedule,
  segment_length,
  segments,
  skip_rows,
  source,
  starts,
  stat,
  step,
  stream,
  sync,
  taus,
  target,
  temp_index,
  temp_order,
  time_col,
  topics,
  twin_check,
  type,
  unit,
  units,
  wic_replicates,
  window,
};

/// The number of Field enumerators (Field::window is the last), for the faces'
/// exhaustiveness tests.
inline constexpr std::size_t kFieldCount = static_cast<std::size_t>(Field::window) + 1;

/// The library's word for a field: the request member's name ("stream").
std::string_view field_name(Field f) noexcept;

/// The field named `name`, if any.
std::optional<Field> field_from_name(std::string_view name) noexcept;

/// The marker a message writes for `f`: "{stream}".
std::string marker(Field f);

/// `text` with every marker of a known field replaced by `word(field)`; braces
/// around anything else are left as they are.
std::string render_fields(std::string_view text, const std::function<std::string(Field)>& word);

/// `text` in the library's words: each marker becomes the field's name.
std::string library_words(std::string_view text);

/// The words of the face the library runs under, for the text the library
/// writes into its results and files (a report page's "add {force}", an
/// estimator file's "{inflate}"): the face sets them once, before its first
/// call (the CLI its flags, Python its keywords); until then, the library's.
/// Errors carry their markers instead (Error::text()), for the face to render.
void set_face_words(std::function<std::string(Field)> words);

/// `text` in the face's words (set_face_words).
std::string face_words(std::string_view text);

}  // namespace cubecal
