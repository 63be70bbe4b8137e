#include "units.hpp"

#include <string>

#include "cubecal/error.hpp"
#include "cubecal/noise/unit_from_name.hpp"

namespace cubecal::python {

std::vector<Unit> announced_units(const io::Series& s) {
  if (!s.units.empty()) {
    std::vector<Unit> units;
    for (std::size_t i = 0; i < s.units.size(); ++i) {
      const auto u = parse_unit(s.units[i]);
      if (!u)
        throw UsageError(Field::unit, s.file + ": channel " + s.names[i] + " is in " + s.units[i] +
                                          ", which is not a unit of noise terms: give unit= (" + known_units() + ")");
      units.push_back(*u);
    }
    return units;
  }
  const InferredUnits inferred = infer_units(s.names);
  if (!inferred.missing.empty()) {
    std::string cols;
    for (const auto& n : inferred.missing) cols += (cols.empty() ? "" : ", ") + n;
    throw UsageError(Field::unit, s.file + ": no unit in the name of " + cols + ": give unit= (" + known_units() +
                                      "; one for all channels or one per channel) or end the names with a unit (" +
                                      known_unit_suffixes() + ")");
  }
  return inferred.units;
}

std::vector<Unit> named_units(const std::vector<std::string>& names) {
  std::vector<Unit> units;
  for (const auto& u : names) {
    const auto unit = parse_unit(u);
    if (!unit) throw UsageError(Field::unit, "unknown unit '" + u + "' (use " + known_units() + ")");
    units.push_back(*unit);
  }
  return units;
}

std::vector<Unit> announced_units_or_none(const io::Series& s) {
  try {
    return announced_units(s);
  } catch (const UsageError&) {
    return {};
  }
}

}  // namespace cubecal::python
