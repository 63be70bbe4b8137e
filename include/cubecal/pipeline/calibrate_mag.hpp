/// @file
/// `calibrate mag` as one call: the magnetometer points (a table already
/// read) and the request in, the hard- and soft-iron calibration with what
/// its outputs show out (h_cal = A^-1 (h - b), |h_cal| = F). JSON form:
/// calibrate_mag_json.hpp.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/calib/mag_calibration.hpp"
#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/math/vec3.hpp"

namespace cubecal::pipeline {

/// Where the field norm F came from.
enum class FieldNormSource { given, mean_raw_norm, column };
std::string_view to_string(FieldNormSource s) noexcept;  ///< "given", "mean_raw_norm", "column"
/// The source named `s` ("given", "mean_raw_norm", "column"), or nullopt. Throws nothing.
std::optional<FieldNormSource> parse_field_norm_source(std::string_view s) noexcept;

/// What `calibrate mag` is asked to do (the points already read).
struct MagRequest {
  /// The method run.
  mag::Method method = mag::Method::ellipsoid;
  double counts_per_unit = 1.0;      ///< the 3 columns are divided by this (not the field column)
  std::optional<double> field_norm;  ///< F; unset: the field column, else the mean raw |h|
  bool field_column = false;         ///< Table::extra[0] holds |H_k| of each point (TWOSTEP only)
  std::optional<double> noise;       ///< per-axis 1 sigma; unset: estimated from the residuals
  double reject_sigma = 0.0;         ///< Magneto's outlier rule at this level; 0: none
  bool allow_partial = false;        ///< fit even when the points cover too little of the sphere
  std::string unit;                  ///< name of the unit after counts_per_unit; empty: none given

  /// A UsageError naming the field at fault for a request no data can make
  /// right (a scale that is not positive, a field column with the ellipsoid).
  void validate() const;
};

/// A UsageError unless `columns` is empty (every column of the file) or names
/// the 3 magnetometer columns.
void check_mag_columns(const std::vector<std::string>& columns);

/// `cubecal calibrate-mag`'s result: the points read and their calibration.
struct MagResult {
  /// The input's path, as given.
  std::string file;
  std::string unit = "input units";  ///< the request's, or "input units"
  /// Where F came from.
  FieldNormSource field_source = FieldNormSource::mean_raw_norm;
  std::size_t first_data_line = 0;  ///< line of the first point in the file
  std::vector<Vec3> points;         ///< every input point, divided by counts_per_unit (not in the JSON)
  std::vector<double> field_norms;  ///< F of each point (field column); empty otherwise
  mag::Result calibration;          ///< rejected: indices into `points`
};

/// `table`: the 3 magnetometer columns as data, and with request.field_column
/// the field column as extra[0]. Throws UsageError naming the request field
/// at fault ("mag_columns", "counts_per_unit", "field_norm", "field_column",
/// "noise", "reject_sigma"); what mag::calibrate throws (CalibrationError with
/// its reason, or std::invalid_argument) passes through.
MagResult calibrate_mag(const io::Table& table, const MagRequest& request);

}  // namespace cubecal::pipeline
