#include "calibration_hints.hpp"

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

}  // namespace

std::string calibration_hint(CalibrationReason reason, const HintContext& ctx) {
  switch (ctx.command) {
    case CalibrationCommand::rate_table: return rate_table_hint(reason, ctx);
    case CalibrationCommand::mag: return mag_hint(reason, ctx);
    case CalibrationCommand::multiposition: return multiposition_hint(reason, ctx);
    case CalibrationCommand::temperature: return temperature_hint(reason);
  }
  return {};
}

}  // namespace cubecal::cli
