// Internal to cubecal_report: the figure of a one-sided power spectral
// density with its fitted power-law terms, drawn by the `psd` page and by the
// analysis page's spectral view (docs/formulas/spectral.md).
#pragma once
#include <string>

#include "cubecal/noise/units.hpp"
#include "cubecal/report/command_report.hpp"
#include "cubecal/spectral/power_law_fit.hpp"
#include "cubecal/spectral/psd.hpp"

namespace cubecal::report::detail {

// "f^0 (white noise N)", "f^-2 (rate random walk K)", ...: a term h f^alpha
// by its exponent and the IEEE 952 noise it stands for.
std::string power_law_term_name(int alpha);

// The density of `channel` (unit: its data unit, empty name: u) on log-log
// axes, averaged over 20 log bands per decade when `spectrum` holds the raw
// bins; over the fitted band each valid term h f^alpha dashed and their sum
// black; the caption says the Welch plan and why there is no fit (fit_error)
// when there is none. `plot_name`: the plot's file stem.
ReportFigure spectrum_figure(const std::string& plot_name, const std::string& channel, const Unit& unit,
                             const Psd& spectrum, const PowerLawFit& fit, const std::string& fit_error);

}  // namespace cubecal::report::detail
