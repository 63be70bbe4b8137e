/// @file
/// The errors cubecal reports to its users, as types, under one base,
/// cubecal::Error. Every layer throws these for what a user can fix; each face
/// maps them by type and reason (the CLI to one line and exit code 2 with a
/// hint, Python to an exception class), never by matching message text. A
/// plain std::invalid_argument from the core means a call the caller should
/// not have made (a span of the wrong length, a NaN passed where the data were
/// already checked); it is no cubecal::Error.
///
/// A message names no face's option: it names a request field by a marker
/// (field.hpp), "leave out {stream}". what() reads it in the library's words
/// ("leave out stream"); text() keeps the markers for a face to render in its
/// own (the CLI `--stream`, Python `stream=`).
///
///   UsageError        what was asked cannot be done as asked: an option out
///                     of range, contradictory options, a record too short
///                     for the statistic; no place in a file to point at.
///   InputError        the data are wrong at a place: FILE:LINE:COL.
///   CalibrationError  the data cannot determine the calibration or model
///                     asked for; reason() says why.
#pragma once
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "cubecal/field.hpp"

namespace cubecal {

/// The base of every error cubecal reports to a user.
class Error : public std::runtime_error {
 public:
  /// `text` may hold field markers; what() is it in the library's words.
  explicit Error(const std::string& text) : std::runtime_error(library_words(text)), text_(text) {}
  /// The message with its field markers, for a face to render.
  const std::string& text() const noexcept { return text_; }

 private:
  std::string text_;
};

/// What was asked cannot be done as asked: an option out of range,
/// contradictory options, a record too short for the statistic. Names the
/// request field at fault when there is one.
class UsageError : public Error {
 public:
  /// Where the message names its field: `in_front`, a face puts the field's
  /// name before it (the CLI `--unit: what`); `in_text`, the message names it
  /// itself by its marker (`{noise} must be positive`).
  enum class Named { in_front, in_text };

  /// An error that names no field; `what` may hold field markers.
  explicit UsageError(const std::string& what) : Error(what) {}
  /// `field` is the request field at fault; each face names it in its own
  /// words (the CLI by its flag, Python as the exception's .option).
  UsageError(Field field, const std::string& what, Named named = Named::in_front)
      : Error(what), field_(field), named_(named) {}
  /// The request field at fault; empty when the error names none.
  const std::optional<Field>& field() const noexcept { return field_; }
  /// Where the message names its field (Named::in_front when it names none).
  Named named() const noexcept { return named_; }

 private:
  std::optional<Field> field_;
  Named named_ = Named::in_front;
};

/// The data are wrong at a place in a file: FILE:LINE:COL.
class InputError : public Error {
 public:
  /// line and column are 1-based; 0 means "not applicable" and is omitted
  /// from the formatted message (e.g. "FILE: empty file"). The message reads
  /// "FILE:LINE:COL: what (hint)"; what and hint may hold field markers.
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

/// The data cannot determine what was asked: a usage of the method that is
/// right, on data that do not allow it. Not a UsageError: no option is wrong.
class CalibrationError : public Error {
 public:
  /// `reason` says why; `what` may hold field markers.
  CalibrationError(CalibrationReason reason, const std::string& what) : Error(what), reason_(reason) {}
  /// Why the data cannot determine what was asked.
  CalibrationReason reason() const noexcept { return reason_; }

 private:
  CalibrationReason reason_;
};

}  // namespace cubecal
