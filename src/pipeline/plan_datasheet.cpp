// Datasheet terms for `cubecal plan --datasheet`: "N=0.15deg/rth,B=6deg/h"
// into PlanTerms in the data unit and seconds. A unit is read as a quantity
// times powers of time, u s^p: deg/rth is deg h^-1/2 = (1/60) (deg/s) s^1/2,
// the white noise N in (deg/s) sqrt(s); each term has its power (Q 1, N 1/2,
// B 0, K -1/2, R -1), which is how a unit of another term is told apart.
// The inverse of units.hpp's display(): its units read back here.
#include <charconv>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/pipeline/plan.hpp"

namespace cubecal::pipeline {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kStandardGravity = 9.80665;

// A quantity: what it measures, its factor to the family's SI unit (deg/s
// for rates: a rate sensor's data unit is deg/s), and its power of time in
// the data unit (deg = (deg/s) s: 1; m = (m/s^2) s^2: 2).
struct Quantity0 {
  std::string_view name;
  SensorKind kind;
  double to_si;
  double time_power;
  std::string_view data_unit;  // the data unit it makes when it comes first
};

constexpr Quantity0 kQuantities[] = {
    {"deg", SensorKind::rate, 1.0, 1.0, "deg/s"},
    {"mdeg", SensorKind::rate, 1e-3, 1.0, "deg/s"},
    {"arcsec", SensorKind::rate, 1.0 / 3600.0, 1.0, "deg/s"},
    {"rad", SensorKind::rate, kDegPerRad, 1.0, "deg/s"},
    {"mrad", SensorKind::rate, 1e-3 * kDegPerRad, 1.0, "deg/s"},
    {"dps", SensorKind::rate, 1.0, 0.0, "deg/s"},
    {"mdps", SensorKind::rate, 1e-3, 0.0, "deg/s"},
    {"dph", SensorKind::rate, 1.0 / 3600.0, 0.0, "deg/s"},
    {"mGauss", SensorKind::field, 1e-7, 0.0, "mGauss"},
    {"mG", SensorKind::field, 1e-7, 0.0, "mGauss"},
    {"G", SensorKind::field, 1e-4, 0.0, "mGauss"},
    {"Gauss", SensorKind::field, 1e-4, 0.0, "mGauss"},
    {"T", SensorKind::field, 1.0, 0.0, "T"},
    {"uT", SensorKind::field, 1e-6, 0.0, "uT"},
    {"nT", SensorKind::field, 1e-9, 0.0, "nT"},
    {"pT", SensorKind::field, 1e-12, 0.0, "nT"},
    {"g", SensorKind::acceleration, kStandardGravity, 0.0, "g"},
    {"mg", SensorKind::acceleration, kStandardGravity * 1e-3, 0.0, "g"},
    {"ug", SensorKind::acceleration, kStandardGravity * 1e-6, 0.0, "g"},
    {"m", SensorKind::acceleration, 1.0, 2.0, "m/s^2"},
    {"counts", SensorKind::generic, 1.0, 0.0, "counts"},
    {"LSB", SensorKind::generic, 1.0, 0.0, "counts"},
};

// A time: its length in s and its power of s (Hz: s^-1).
struct Time0 {
  std::string_view name;
  double seconds;
  double power;
};

constexpr Time0 kTimes[] = {{"s", 1.0, 1.0},     {"sec", 1.0, 1.0},     {"min", 60.0, 1.0},  {"h", 3600.0, 1.0},
                            {"hr", 3600.0, 1.0}, {"hour", 3600.0, 1.0}, {"d", 86400.0, 1.0}, {"Hz", 1.0, -1.0}};

constexpr const char* kKnownUnits =
    "quantities deg, rad, mdeg, arcsec, dps, dph, mGauss, G, uT, nT, g, mg, ug, m, counts; times s, min, h, Hz, "
    "as sqrt(h), rth, rtHz or with a power h^2";

// A unit read: value [in it] = factor [data unit] s^power.
struct ReadUnit {
  const Quantity0* quantity = nullptr;
  double factor = 1.0;
  double power = 0.0;
};

// (A new string, not std::string::replace: GCC 12 warns falsely on it at -O3.)
std::string replace_all(const std::string& s, std::string_view from, std::string_view to) {
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    if (s.compare(i, from.size(), from) == 0) {
      out.append(to);
      i += from.size();
    } else {
      out += s[i++];
    }
  }
  return out;
}

// Spellings people type: spaces, the degree sign, micro signs, root signs.
std::string normalized(std::string_view unit) {
  std::string s;
  for (const char c : unit)
    if (c != ' ') s += c;
  s = replace_all(s, "\u00b0", "deg");
  s = replace_all(s, "\u00b5", "u");
  s = replace_all(s, "\u03bc", "u");
  s = replace_all(s, "\u221a", "rt");
  s = replace_all(s, "\u00b2", "^2");
  return s;
}

// A time factor: "h", "h^2", "sqrt(h)", "rth", "rt(h)", "rtHz"; nullopt otherwise.
std::optional<std::pair<double, double>> time_factor(std::string token) {
  double exponent = 1.0;
  if (token.rfind("sqrt(", 0) == 0 && token.back() == ')') {
    token = token.substr(5, token.size() - 6);
    exponent = 0.5;
  } else if (token.rfind("rt(", 0) == 0 && token.back() == ')') {
    token = token.substr(3, token.size() - 4);
    exponent = 0.5;
  } else if (token.rfind("rt", 0) == 0 && token.size() > 2) {
    token = token.substr(2);
    exponent = 0.5;
  } else if (const std::size_t hat = token.find('^'); hat != std::string::npos) {
    const std::string p = token.substr(hat + 1);
    double e = 0.0;
    const auto [end, ec] = std::from_chars(p.data(), p.data() + p.size(), e);
    if (ec != std::errc() || end != p.data() + p.size() || !(e > 0.0) || e > 4.0) return std::nullopt;
    token = token.substr(0, hat);
    exponent = e;
  }
  for (const Time0& t : kTimes)
    if (t.name == token) return std::make_pair(std::pow(t.seconds, exponent), t.power * exponent);
  return std::nullopt;
}

// Splits at '/' and '*' outside parentheses: ("deg", '*'), ("h", '/'), ("sqrt(h)", '/').
std::vector<std::pair<std::string, char>> factors(const std::string& unit) {
  std::vector<std::pair<std::string, char>> out{{"", '*'}};
  int depth = 0;
  for (const char c : unit) {
    if (depth == 0 && (c == '/' || c == '*')) {
      out.emplace_back("", c);
      continue;
    }
    depth += c == '(' ? 1 : c == ')' ? -1 : 0;
    out.back().first += c;
  }
  return out;
}

ReadUnit read_unit(const std::string& item, const std::string& unit_text) {
  const std::string unit = normalized(unit_text);
  const auto parts = factors(unit);
  ReadUnit r;
  for (const Quantity0& q : kQuantities)
    if (q.name == parts.front().first) r.quantity = &q;
  if (r.quantity == nullptr)
    throw UsageError(Field::datasheet,
                     item + ": '" + parts.front().first + "' is not a quantity cubecal knows (" + kKnownUnits + ")");
  r.power = r.quantity->time_power;
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const auto t = time_factor(parts[i].first);
    if (!t)
      throw UsageError(Field::datasheet, item + ": '" + parts[i].first + "' in " + unit_text +
                                             " is not a time cubecal knows (" + kKnownUnits + ")");
    const double sign = parts[i].second == '/' ? -1.0 : 1.0;
    r.factor *= std::pow(t->first, sign);
    r.power += sign * t->second;
  }
  return r;
}

// The power of s of each term in u s^p, its name and the units to give it in.
struct TermShape {
  char letter;
  double power;
  std::string_view name;
  std::string_view rate_example;
};

constexpr TermShape kShapes[] = {
    {'Q', 1.0, "quantization", "deg or rad"},
    {'N', 0.5, "white noise", "deg/sqrt(h), deg/rth or deg/s/sqrt(Hz)"},
    {'B', 0.0, "bias instability", "deg/h or deg/s"},
    {'K', -0.5, "rate random walk", "deg/h/sqrt(h) or deg/s/sqrt(s)"},
    {'R', -1.0, "rate ramp", "deg/h^2 or deg/s^2"},
};

std::string other_example(const TermShape& t, std::string_view u) {
  const std::string unit(u);
  switch (t.letter) {
    case 'Q': return unit + "*s";
    case 'N': return unit + "/sqrt(Hz) or " + unit + "*sqrt(h)";
    case 'B': return unit;
    case 'K': return unit + "/sqrt(h) or " + unit + "/sqrt(s)";
    default: return unit + "/h or " + unit + "/s";
  }
}

double* term_slot(PlanTerms& terms, char letter) {
  switch (letter) {
    case 'Q': return &terms.Q;
    case 'N': return &terms.N;
    case 'B': return &terms.B;
    case 'K': return &terms.K;
    default: return &terms.R;
  }
}

// "N=0.15deg/rth": the term's letter, its value and unit; adds it to `d`.
void add_item(Datasheet& d, const std::string& item, const Quantity0*& first, std::vector<char>& seen) {
  const std::size_t eq = item.find('=');
  const std::string name = eq == std::string::npos ? item : item.substr(0, eq);
  const TermShape* shape = nullptr;
  for (const TermShape& t : kShapes)
    if (name.size() == 1 && (name[0] == t.letter || name[0] == t.letter + ('a' - 'A'))) shape = &t;
  if (name == "T" || name == "t")
    throw UsageError(Field::datasheet, "'" + item +
                                           "': T, the tau of the Allan curve's minimum, follows from the other terms: "
                                           "leave it out");
  if (eq == std::string::npos || shape == nullptr)
    throw UsageError(Field::datasheet, "'" + item +
                                           "' is not a term: give TERM=VALUE UNIT items, TERM one of Q, N, B, K, R "
                                           "(e.g. N=0.15deg/rth,B=6deg/h,K=0.02deg/h/rth)");
  for (const char c : seen)
    if (c == shape->letter) throw UsageError(Field::datasheet, std::string(1, c) + " is given twice");
  seen.push_back(shape->letter);
  const std::string rest = item.substr(eq + 1);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), value);
  if (ec != std::errc() || !std::isfinite(value) || value < 0.0)
    throw UsageError(Field::datasheet, item + ": the value must be a number, 0 or more");
  std::string unit_text(end, rest.data() + rest.size());
  while (!unit_text.empty() && unit_text.front() == ' ') unit_text.erase(0, 1);
  if (unit_text.empty())
    throw UsageError(Field::datasheet,
                     item + ": give the unit (e.g. " + std::string(1, shape->letter) + "=" + rest + "deg/h)");
  const ReadUnit u = read_unit(item, unit_text);
  if (first == nullptr) first = u.quantity;
  if (u.quantity->kind != first->kind)
    throw UsageError(Field::datasheet, item + ": " + unit_text +
                                           " is not a unit of the sensor the other terms are of (" +
                                           std::string(first->name) + ")");
  if (std::abs(u.power - shape->power) > 1e-9) {
    const std::string examples =
        first->kind == SensorKind::rate ? std::string(shape->rate_example) : other_example(*shape, first->data_unit);
    throw UsageError(Field::datasheet, item + ": " + unit_text + " is not a unit of " + std::string(1, shape->letter) +
                                           " (" + std::string(shape->name) + "): give it in " + examples);
  }
  // value [unit] = value factor [quantity] s^p, the quantity in its family's
  // base (deg for rates, SI for the others): divided by the data unit's factor at the end.
  *term_slot(d.terms, shape->letter) = value * u.factor * u.quantity->to_si;
}

}  // namespace

Datasheet parse_datasheet(std::string_view text) {
  Datasheet d;
  d.text = std::string(text);
  const Quantity0* first = nullptr;
  std::vector<char> seen;
  std::string item;
  const auto flush = [&] {
    while (!item.empty() && item.back() == ' ') item.pop_back();
    if (!item.empty()) add_item(d, item, first, seen);
    item.clear();
  };
  for (const char c : text) {
    if (c == ',' || c == ';') {
      flush();
    } else if (!(item.empty() && c == ' ')) {
      item += c;
    }
  }
  flush();
  if (first == nullptr)
    throw UsageError(Field::datasheet, "no terms: give e.g. N=0.15deg/rth,B=6deg/h,K=0.02deg/h/rth");
  // The data unit: deg/s for a rate sensor, else the first term's unit (nT for pT, g for mg and ug).
  const std::string data_unit(first->data_unit);
  const auto parsed = parse_unit(data_unit);
  d.unit = parsed ? *parsed : Unit{data_unit, first->kind, 1.0, data_unit};
  const double base = first->kind == SensorKind::rate ? 1.0 : d.unit.to_si;
  for (const char c : {'Q', 'N', 'B', 'K', 'R'}) *term_slot(d.terms, c) /= base;
  return d;
}

}  // namespace cubecal::pipeline
