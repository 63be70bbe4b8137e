// The reason of the CalibrationError a call throws, as text, for the tests
// that every rejection of the data names the reason the faces map to hints.
#pragma once
#include <string>

#include "cubecal/error.hpp"

namespace cubecal::test {

// to_string(reason) of the CalibrationError f throws; "(none)" when it
// throws none (any other exception propagates and fails the test).
template <class F>
std::string reason_of(F&& f) {
  try {
    f();
  } catch (const CalibrationError& e) {
    return std::string(to_string(e.reason()));
  }
  return "(none)";
}

}  // namespace cubecal::test
