// How the configuration files of estimators and simulators write numbers
// (estimator_config.cpp, simulator_export_files.cpp). Not an installed header.
#pragma once
#include <cstdio>
#include <string>

namespace cubecal::pipeline::detail {

// Scientific notation with a decimal point, which YAML 1.1 readers (PyYAML,
// hence Kalibr) need to take "1e-05" as a number rather than a string.
inline std::string config_number(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.9e", v);
  return b;
}

// Plain numbers for rates, gravity and times: "%.9g" with ".0" appended when
// it reads as an integer.
inline std::string config_plain(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", v);
  std::string s = b;
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

}  // namespace cubecal::pipeline::detail
