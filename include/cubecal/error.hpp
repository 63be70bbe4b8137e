/// @file
/// The errors cubecal reports to its users, as types. Every layer throws
/// these for what a user can fix; each face maps them by type and reason
/// (the CLI to one line and exit code 2 with a hint, Python to an exception
/// class), never by matching message text. A plain std::invalid_argument
/// from the core means a call the caller should not have made (a span of the
/// wrong length, a NaN passed where the data were already checked).
///
///   UsageError        what was asked cannot be done as asked: an option out
///                     of range, contradictory options, a record too short
///                     for the statistic; no place in a file to point at.
///   InputError        the data are wrong at a place: FILE:LINE:COL.
///   CalibrationError  the data cannot determine the calibration or model
///                     asked for; reason() says why.
#pragma once
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace cubecal {

/// What was asked cannot be done as asked (an option out of range, contradictory options, a record too short for the
/// statistic): no place in a file to point at.
class UsageError : public std::runtime_error {
 public:
  /// A message without a request field (option() is empty).
  explicit UsageError(const std::string& what) : std::runtime_error(what) {}
  /// `option` names the request field at fault, in the library's words
  /// ("units", "lsb", "temp_index", "temp_order", "bias", "columns"); each
  /// face says it in its own (the CLI as "--unit: what"). The message itself
  /// names no flag.
  UsageError(std::string option, const std::string& what) : std::runtime_error(what), option_(std::move(option)) {}
  /// The request field at fault, in the library's words; empty when none was named.
  const std::string& option() const noexcept { return option_; }

 private:
  std::string option_;
};

/// The data are wrong at a place: FILE:LINE:COL (or the row and column of a binary table).
class InputError : public std::runtime_error {
 public:
  /// line and column are 1-based; 0 means "not applicable" and is omitted
  /// from the formatted message (e.g. "FILE: empty file"). The message reads
  /// "FILE:LINE:COL: what (hint)".
  InputError(std::string file, std::size_t line, std::size_t column, std::string what, std::string hint = {});

  /// The file (or label, "<stdin>") the error is in.
  const std::string& file() const noexcept { return file_; }
  /// 1-based line (0: not applicable).
  std::size_t line() const noexcept { return line_; }
  /// 1-based column (0: not applicable).
  std::size_t column() const noexcept { return column_; }
  /// What is wrong, without the place and the hint.
  const std::string& problem() const noexcept { return problem_; }
  /// What to do about it; empty when there is nothing to add.
  const std::string& hint() const noexcept { return hint_; }

 private:
  std::string file_;
  std::size_t line_;
  std::size_t column_;
  std::string problem_;
  std::string hint_;
};

/// Why a calibration or a model fit cannot be done with the data given.
enum class CalibrationReason {
  too_few_points,     ///< fewer points, plateaus or samples than the method needs
  poor_coverage,      ///< the points do not span enough orientations (magnetometer sphere coverage)
  degenerate,         ///< the data do not determine the parameters (rank-deficient, singular, no real solution)
  bad_data,           ///< non-finite values, lengths that do not match, time stamps not increasing
  bad_option,         ///< an option value the method cannot use
  field_norm,         ///< a field norm that is not positive, or per-point norms of the wrong count
  no_plateaus,        ///< rate table: no plateau left after detection and margins
  too_few_intervals,  ///< multi-position: fewer static poses than required
  initial_static,     ///< multi-position: the initial static period is missing, too short or constant
  scale_guess,        ///< multi-position: the scale guess leads nowhere (non-finite or non-positive scale)
  not_converged,      ///< the iteration did not converge
};

/// The reason's name in snake_case ("too_few_points", ...), as the JSON and the faces say it. Throws nothing.
std::string_view to_string(CalibrationReason r) noexcept;

/// Derives from std::invalid_argument: the calibration was given arguments
/// (the data) it cannot work with.
class CalibrationError : public std::invalid_argument {
 public:
  /// An error for `reason`, with a message fit for the user.
  CalibrationError(CalibrationReason reason, const std::string& what) : std::invalid_argument(what), reason_(reason) {}
  /// Why the calibration or fit cannot be done.
  CalibrationReason reason() const noexcept { return reason_; }

 private:
  CalibrationReason reason_;
};

}  // namespace cubecal
