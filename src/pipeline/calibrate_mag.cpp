#include "cubecal/pipeline/calibrate_mag.hpp"

#include <cmath>

#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"

namespace cubecal::pipeline {

std::string_view to_string(FieldNormSource s) noexcept {
  switch (s) {
    case FieldNormSource::given: return "given";
    case FieldNormSource::mean_raw_norm: return "mean_raw_norm";
    case FieldNormSource::column: return "column";
  }
  return "";
}

std::optional<FieldNormSource> parse_field_norm_source(std::string_view s) noexcept {
  for (FieldNormSource f : {FieldNormSource::given, FieldNormSource::mean_raw_norm, FieldNormSource::column})
    if (to_string(f) == s) return f;
  return std::nullopt;
}

namespace {

bool positive(double v) { return v > 0.0 && std::isfinite(v); }

// A magnitude whose square (a variance, a chi-squared weight) a double holds,
// as the readers take values (io/series.hpp).
bool holdable(double v) { return v >= io::kMinMagnitude && v <= io::kMaxMagnitude; }

void check_request(const io::Table& t, const MagRequest& req) {
  if (t.data.size() != 3)
    throw UsageError(Field::mag_columns, t.file + " has " + std::to_string(t.data.size()) +
                                             " data columns: the 3 magnetometer columns are needed");
  req.validate();
  if (req.field_column && t.extra.size() != 1) throw UsageError(Field::field_column, "the field column was not read");
}

}  // namespace

void MagRequest::validate() const {
  constexpr auto in_text = UsageError::Named::in_text;
  if (!positive(counts_per_unit))
    throw UsageError(Field::counts_per_unit, "{counts_per_unit} must be a positive number of counts per unit", in_text);
  if (field_norm && !(positive(*field_norm) && holdable(*field_norm)))
    throw UsageError(Field::field_norm,
                     "{field_norm} must be a positive field magnitude, 1e-100 to 1e100 (in the units of the values "
                     "after {counts_per_unit})",
                     in_text);
  if (noise && !(positive(*noise) && holdable(*noise)))
    throw UsageError(Field::noise,
                     "{noise} must be a positive standard deviation per axis, 1e-100 to 1e100 (leave it out to "
                     "estimate it)",
                     in_text);
  if (!(reject_sigma >= 0.0) || !std::isfinite(reject_sigma))
    throw UsageError(Field::reject_sigma,
                     "{reject_sigma} must be a positive number of standard deviations (0: no rejection)", in_text);
  if (field_column && field_norm)
    throw UsageError(Field::field_column, "give either {field_norm} or {field_column}, not both", in_text);
  if (field_column && method == mag::Method::ellipsoid)
    throw UsageError(Field::field_column,
                     "{field_column} (a field norm per point) needs {method} twostep or twostep-full", in_text);
}

void check_mag_columns(const std::vector<std::string>& columns) {
  if (!columns.empty() && columns.size() != 3)
    throw UsageError(Field::mag_columns, "{mag_columns} takes the 3 magnetometer columns (mx,my,mz or 1,2,3)",
                     UsageError::Named::in_text);
}

MagResult calibrate_mag(const io::Table& table, const MagRequest& req) {
  check_request(table, req);
  MagResult r;
  r.file = table.file;
  r.unit = req.unit.empty() ? std::string("input units") : req.unit;
  r.field_source = req.field_column ? FieldNormSource::column
                   : req.field_norm ? FieldNormSource::given
                                    : FieldNormSource::mean_raw_norm;
  r.first_data_line = table.first_data_line;
  r.points.resize(table.rows());
  const double lsb = req.counts_per_unit;
  for (std::size_t i = 0; i < r.points.size(); ++i)
    r.points[i] = {table.data[0][i] / lsb, table.data[1][i] / lsb, table.data[2][i] / lsb};
  if (req.field_column) r.field_norms = table.extra[0];

  mag::Options opt;
  opt.method = req.method;
  opt.field_norm = req.field_norm.value_or(0.0);
  opt.field_norms = r.field_norms;
  opt.noise = req.noise.value_or(0.0);
  opt.reject_sigma = req.reject_sigma;
  opt.check_coverage = !req.allow_partial;
  r.calibration = mag::calibrate(r.points, opt);
  return r;
}

}  // namespace cubecal::pipeline
