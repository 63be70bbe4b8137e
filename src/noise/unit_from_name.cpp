#include "cubecal/noise/unit_from_name.hpp"

namespace cubecal {

namespace {

struct Suffix {
  std::string_view text;  // after the separator
  std::string_view unit;  // as parse_unit() knows it
  bool exact_case;        // only in this case (another case means another unit)
};

constexpr Suffix kSuffixes[] = {
    {"dps", "deg/s", false},         {"degps", "deg/s", false},
    {"deg_s", "deg/s", false},       {"degs", "deg/s", false},
    {"deg_per_s", "deg/s", false},   {"rads", "rad/s", false},
    {"rad_s", "rad/s", false},       {"radps", "rad/s", false},
    {"rad_per_s", "rad/s", false},   {"dph", "deg/h", false},
    {"degph", "deg/h", false},       {"deg_h", "deg/h", false},
    {"deg_per_h", "deg/h", false},   {"g", "g", true},
    {"mps2", "m/s^2", false},        {"ms2", "m/s^2", false},
    {"m_s2", "m/s^2", false},        {"mpss", "m/s^2", false},
    {"m_s_2", "m/s^2", false},       {"ut", "uT", false},
    {"utesla", "uT", false},         {"microtesla", "uT", false},
    {"mG", "mGauss", true},          {"mgauss", "mGauss", false},
    {"milligauss", "mGauss", false}, {"nt", "nT", false},
    {"ntesla", "nT", false},         {"nanotesla", "nT", false},
    {"counts", "counts", false},     {"cnt", "counts", false},
    {"lsb", "counts", false},        {"count", "counts", false},
    {"raw_counts", "counts", false}, {"degpersec", "deg/s", false},
    {"radpersec", "rad/s", false},
};

char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (lower(a[i]) != lower(b[i])) return false;
  return true;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// A unit written out in brackets: parse_unit()'s spellings, exactly or
// ignoring case when that is unambiguous, or one of the suffix spellings.
std::optional<Unit> bracketed_unit(std::string_view u) {
  u = trim(u);
  if (auto unit = parse_unit(u)) return unit;
  for (std::string_view known : {"deg/s", "rad/s", "deg/h", "m/s^2", "uT", "nT", "counts", "m/s2", "m/s/s"})
    if (iequals(u, known)) return parse_unit(known == "m/s2" || known == "m/s/s" ? "m/s^2" : known);
  for (const auto& s : kSuffixes)
    if (s.exact_case ? u == s.text : iequals(u, s.text)) return parse_unit(s.unit);
  return std::nullopt;
}

}  // namespace

std::optional<Unit> unit_from_column_name(std::string_view name) {
  name = trim(name);
  if (name.size() >= 3 && (name.back() == ']' || name.back() == ')')) {
    const char open = name.back() == ']' ? '[' : '(';
    const auto at = name.rfind(open);
    if (at != std::string_view::npos && at > 0) return bracketed_unit(name.substr(at + 1, name.size() - at - 2));
    return std::nullopt;
  }
  // The longest suffix that follows a separator wins (gyro_x_deg_s: deg_s, not s).
  std::optional<Unit> best;
  std::size_t best_len = 0;
  for (const auto& s : kSuffixes) {
    if (name.size() <= s.text.size() || s.text.size() <= best_len) continue;
    const std::string_view tail = name.substr(name.size() - s.text.size());
    const char sep = name[name.size() - s.text.size() - 1];
    if (sep != '_' && sep != '.') continue;
    if (s.exact_case ? tail != s.text : !iequals(tail, s.text)) continue;
    best = parse_unit(s.unit);
    best_len = s.text.size();
  }
  return best;
}

InferredUnits infer_units(const std::vector<std::string>& names) {
  InferredUnits r;
  for (const auto& n : names) {
    if (auto u = unit_from_column_name(n))
      r.units.push_back(*u);
    else
      r.missing.push_back(n);
  }
  if (!r.missing.empty()) r.units.clear();
  return r;
}

std::string known_unit_suffixes() { return "_dps, _rads, _dph, _g, _mps2, _uT, _mG, _nT, _counts, or gx[deg/s]"; }

}  // namespace cubecal
