#include "calibration_hints.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace cubecal::cli {

namespace {

std::string rate_table_hint(CalibrationReason reason, const HintContext& ctx) {
  switch (reason) {
    case CalibrationReason::no_plateaus:
      return ctx.reference_columns ? "check --ref-columns and --ref-tolerance, or lower --margin / --min-plateau"
                                   : "check the schedule's times against the log's, or lower --margin / --min-plateau";
    case CalibrationReason::too_few_points:
    case CalibrationReason::degenerate: return "the run must turn the gyro about each of its 3 axes";
    default: return {};
  }
}

std::string mag_hint(CalibrationReason reason, const HintContext& ctx) {
  switch (reason) {
    case CalibrationReason::poor_coverage:
      return ctx.bias_only ? "add --allow-partial to fit anyway"
                           : "add --allow-partial to fit anyway and judge the uncertainties, or use --method twostep";
    case CalibrationReason::field_norm: return ctx.field_col ? "check --field-col" : "check --field-norm";
    case CalibrationReason::bad_option: return "check --noise, --reject and --field-norm";
    default: return {};
  }
}

std::string multiposition_hint(CalibrationReason reason, const HintContext& ctx) {
  switch (reason) {
    case CalibrationReason::too_few_intervals:
    case CalibrationReason::initial_static:
      return "check --init-static (the sensor must be still then) and --rate/--time-col";
    case CalibrationReason::scale_guess:
      return ctx.gyroscope ? "give --gyro-scale in rad/s per count"
                           : "give --acc-bias (raw units) and --acc-scale (calibrated unit per raw unit)";
    case CalibrationReason::bad_data: return "check --time-col";
    default: return {};
  }
}

std::string temperature_hint(CalibrationReason reason) {
  switch (reason) {
    case CalibrationReason::too_few_points:
    case CalibrationReason::degenerate: return "the temperature must vary over the record; or lower --order";
    default: return {};
  }
}

// cubecal model: the GMWM found no fit of the model asked for.
std::string model_hint(CalibrationReason reason) {
  switch (reason) {
    case CalibrationReason::degenerate:
    case CalibrationReason::not_converged:
      return "give a model with fewer terms (--model) or more starting points (--starts)";
    case CalibrationReason::too_few_points: return "the record is too short for the model: give a longer one";
    default: return {};
  }
}

// analyze --composite: the GMWM found no fit of the composite model.
std::string composite_hint(CalibrationReason reason) {
  switch (reason) {
    case CalibrationReason::degenerate:
    case CalibrationReason::not_converged: return "give --composite a model with fewer terms";
    default: return {};
  }
}

}  // namespace

std::string calibration_hint(CalibrationReason reason, const HintContext& ctx) {
  switch (ctx.command) {
    case CalibrationCommand::rate_table: return rate_table_hint(reason, ctx);
    case CalibrationCommand::mag: return mag_hint(reason, ctx);
    case CalibrationCommand::multiposition: return multiposition_hint(reason, ctx);
    case CalibrationCommand::temperature: return temperature_hint(reason);
    case CalibrationCommand::model: return model_hint(reason);
    case CalibrationCommand::composite: return composite_hint(reason);
  }
  return {};
}

std::string field_norm_warning(double field_norm, const std::vector<std::vector<double>>& xyz, double lsb) {
  // Half the 5-95 % range of each axis (0.9 F on points spread over the
  // sphere), so that a few outliers do not inflate it.
  double radius = 0.0;
  for (const auto& axis : xyz) {
    if (axis.size() < 2) continue;
    std::vector<double> v(axis);
    const auto at = [&](double q) {
      const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
      std::nth_element(v.begin(), v.begin() + k, v.end());
      return v[static_cast<std::size_t>(k)];
    };
    const double lo = at(0.05), hi = at(0.95);
    radius = std::max(radius, 0.5 * (hi - lo) / lsb);
  }
  constexpr double kFar = 4.0;
  if (!(radius > 0.0) || !(field_norm > 0.0) || !std::isfinite(radius)) return {};
  const double ratio = field_norm / radius;
  if (ratio <= kFar && ratio >= 1.0 / kFar) return {};
  return fmt::format(
      "--field-norm {:g} is {:.3g}x the data's field magnitude (about {:.3g}: half the spread of the points{}): "
      "give the field norm in the unit of the values{}",
      field_norm, ratio, radius, lsb != 1.0 ? fmt::format(" after --lsb {:g}", lsb) : std::string(),
      lsb != 1.0 ? " after --lsb" : ", or --lsb to convert counts to that unit");
}

}  // namespace cubecal::cli
