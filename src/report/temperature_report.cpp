// The page of `cubecal calibrate temperature`: the polynomial bias(T) of every
// channel with 1σ per coefficient, the fit quality, and the coefficient
// covariance.
#include "command_util.hpp"
#include "cubecal/report/command_reports.hpp"
#include "cubecal/report/html.hpp"

namespace cubecal::report {

using namespace detail;

CommandReport temperature_report(const pipeline::TemperatureResult& t, const std::string& command) {
  CommandReport rep;
  rep.title = "Temperature calibration: " + base_name(t.file);
  rep.lead_html =
      "Polynomial bias(T) per channel by <code>cubecal calibrate temperature</code>, in the form a flight "
      "computer applies: corrected = raw − Σ<sub>p≥1</sub> c<sub>p</sub> (T − T<sub>ref</sub>)<sup>p</sup>.";
  rep.command = command;
  rep.input = {{"file", t.file, true},
               {"temperature column", t.temperature_column, true},
               {"samples", std::to_string(t.samples), false},
               {"polynomial order", std::to_string(t.order), false},
               {"unit", t.unit, false}};

  ReportTable fit;
  fit.title = "Fit per channel";
  fit.header = {"channel", "T_ref [degC]", "R²", "residual RMS [" + t.unit + "]"};
  for (const auto& c : t.channels)
    fit.rows.push_back(
        {c.name, format_num(c.fit.t_ref, 5), format_num(c.fit.r2, 4), format_num(c.fit.residual_rms, 4)});
  ReportSection fit_sec{"fit", "Fit", {}};
  fit_sec.blocks.push_back({{}, std::move(fit), {}});
  rep.sections.push_back(std::move(fit_sec));

  ReportSection coeff_sec{"coefficients", "Coefficients", {}};
  for (const auto& c : t.channels) {
    ReportTable tab;
    tab.title = c.name;
    tab.header = {"coefficient", "value ± 1σ", "unit"};
    tab.numeric = {false, true, false};
    for (std::size_t p = 0; p < c.fit.coeff.size(); ++p)
      tab.rows.push_back({"c" + std::to_string(p), format_pm(c.fit.coeff[p], c.fit.coeff_sigma[p]),
                          p < c.coeff_units.size() ? c.coeff_units[p] : std::string()});
    coeff_sec.blocks.push_back({{}, std::move(tab), {}});
  }
  if (!coeff_sec.blocks.empty())
    coeff_sec.blocks.back().table->note =
        "Uncertainties: sandwich covariance with batch means (robust to a drifting bias).";
  rep.sections.push_back(std::move(coeff_sec));
  return rep;
}

}  // namespace cubecal::report
