/// @file
/// The unit a column announces in its name, as loggers and people name their
/// columns: a suffix after '_' or '.' (gyro_x_dps, acc_x_g, mag_x_uT), or a
/// unit in brackets or parentheses at the end (gx[deg/s], mag x (uT)).
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/noise/units.hpp"

namespace cubecal {

/// The unit of a column from its name, or nullopt when the name announces
/// none. Suffixes (case-insensitive unless noted):
///   deg/s   _dps _degps _deg_s _degs _deg_per_s        rad/s  _rads _rad_s _radps _rad_per_s
///   deg/h   _dph _degph _deg_h _deg_per_h              g      _g (lower case only: _G may be gauss)
///   m/s^2   _mps2 _ms2 _m_s2 _mpss _m_s_2              uT     _ut _utesla _microtesla
///   mGauss  _mG (that case only: _mg may be milli-g) _mgauss _milligauss
///   nT      _nt _ntesla _nanotesla                     counts _counts _cnt _lsb
/// and every spelling parse_unit() knows, in brackets or parentheses.
std::optional<Unit> unit_from_column_name(std::string_view name);

/// The units a list of column names announces.
struct InferredUnits {
  std::vector<Unit> units;           ///< one per name when `missing` is empty
  std::vector<std::string> missing;  ///< names that announce no unit
};

/// unit_from_column_name() over every name.
InferredUnits infer_units(const std::vector<std::string>& names);

/// The common suffixes, as a message lists them: "_dps, _rads, ...".
std::string known_unit_suffixes();

}  // namespace cubecal
