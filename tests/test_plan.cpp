// cubecal plan's pipeline (pipeline/plan.hpp): datasheet terms read in their
// units (the inverse of units.hpp's display), each model source, the rows
// and curves of a plan, its JSON, and the unreachable targets with reasons.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/pipeline/plan.hpp"
#include "cubecal/pipeline/plan_json.hpp"

namespace cubecal::pipeline {
namespace {

// The field a UsageError names, and its message, for a call that must throw one.
template <class F>
std::pair<std::optional<Field>, std::string> usage_error(F&& f) {
  try {
    f();
  } catch (const UsageError& e) {
    return {e.field(), e.what()};
  }
  ADD_FAILURE() << "no UsageError";
  return {std::nullopt, ""};
}

TEST(PlanDatasheet, ReadsAGyroDatasheetInDegPerSecond) {
  const Datasheet d = parse_datasheet("N=0.15deg/rth,B=6deg/h,K=0.02deg/h/rth");
  EXPECT_EQ(d.unit.name, "deg/s");
  EXPECT_EQ(d.unit.kind, SensorKind::rate);
  // 0.15 deg/sqrt(h) = 0.15 / 60 (deg/s) sqrt(s); 6 deg/h = 6 / 3600 deg/s;
  // 0.02 deg/h/sqrt(h) = 0.02 / 3600 / 60 (deg/s) / sqrt(s).
  EXPECT_DOUBLE_EQ(d.terms.N, 0.15 / 60.0);
  EXPECT_DOUBLE_EQ(d.terms.B, 6.0 / 3600.0);
  EXPECT_DOUBLE_EQ(d.terms.K, 0.02 / 216000.0);
  EXPECT_EQ(d.terms.Q, 0.0);
  EXPECT_EQ(d.terms.R, 0.0);
}

TEST(PlanDatasheet, EverySpellingOfWhiteNoiseIsTheSameN) {
  const double n = 0.15 / 60.0;
  for (const char* text :
       {"N=0.15deg/sqrt(h)", "N=0.15 deg/rt(h)", "N=0.15deg/\u221ah", "N=0.15\u00b0/\u221ahr", "N=9deg/h/rtHz",
        "N=9 dph/sqrt(Hz)", "N=0.0025deg/s/sqrt(Hz)", "N=2.5mdps/rtHz", "N=0.0025deg/sqrt(s)", "n=0.15deg/h^0.5"})
    EXPECT_NEAR(parse_datasheet(text).terms.N, n, 1e-15) << text;
  // rad: 1e-4 rad/s/sqrt(Hz) = 1e-4 * 180/pi (deg/s) sqrt(s).
  EXPECT_NEAR(parse_datasheet("N=1e-4rad/s/sqrt(Hz)").terms.N, 1e-4 * 180.0 / std::numbers::pi, 1e-15);
  // R in deg/h^2 and deg/h/h; Q in deg and arcsec.
  EXPECT_NEAR(parse_datasheet("R=36deg/h^2").terms.R, 36.0 / 3600.0 / 3600.0, 1e-18);
  EXPECT_NEAR(parse_datasheet("R=36deg/h/h").terms.R, 36.0 / 3600.0 / 3600.0, 1e-18);
  EXPECT_NEAR(parse_datasheet("Q=36arcsec").terms.Q, 0.01, 1e-15);
}

TEST(PlanDatasheet, ReadsBackWhatAnalyzeDisplays) {
  // The display units of analyze (units.hpp), read back, give the value in
  // the data unit and seconds: parse_datasheet inverts display.
  const std::pair<PlanTerm, Term> terms[] = {{PlanTerm::Q, Term::Q},
                                             {PlanTerm::N, Term::N},
                                             {PlanTerm::B, Term::B},
                                             {PlanTerm::K, Term::K},
                                             {PlanTerm::R, Term::R}};
  for (const char* unit_name : {"deg/s", "mGauss", "uT", "nT", "g", "m/s^2"}) {
    const Unit unit = *parse_unit(unit_name);
    for (const auto& [pt, t] : terms) {
      TermEstimate e;
      e.valid = true;
      e.value = 0.0123;
      const Quantity q = display(e, t, unit);
      std::ostringstream text_stream;
      text_stream.precision(17);
      text_stream << to_string(pt) << '=' << q.value << q.unit;
      const std::string text = text_stream.str();
      const Datasheet d = parse_datasheet(text);
      EXPECT_EQ(d.unit.name, unit.name) << text;
      const double got = pt == PlanTerm::Q   ? d.terms.Q
                         : pt == PlanTerm::N ? d.terms.N
                         : pt == PlanTerm::B ? d.terms.B
                         : pt == PlanTerm::K ? d.terms.K
                                             : d.terms.R;
      EXPECT_NEAR(got, 0.0123, 1e-12) << text;
    }
  }
}

TEST(PlanDatasheet, MagnetometerAndAccelerometerUnits) {
  const Datasheet mag = parse_datasheet("N=0.1uT/rtHz, B=0.05uT");
  EXPECT_EQ(mag.unit.name, "uT");
  EXPECT_DOUBLE_EQ(mag.terms.N, 0.1);
  EXPECT_DOUBLE_EQ(mag.terms.B, 0.05);
  // A first term in pT gives nT data (the unit cubecal knows), the rest converted.
  const Datasheet pt = parse_datasheet("B=500pT,N=2nT/rtHz");
  EXPECT_EQ(pt.unit.name, "nT");
  EXPECT_NEAR(pt.terms.B, 0.5, 1e-12);
  EXPECT_NEAR(pt.terms.N, 2.0, 1e-12);
  // mGauss sqrt(h) = 60 mGauss sqrt(s).
  EXPECT_NEAR(parse_datasheet("N=1mGauss*sqrt(h)").terms.N, 60.0, 1e-12);
  const Datasheet acc = parse_datasheet("N=60ug/rtHz,B=20ug");
  EXPECT_EQ(acc.unit.name, "g");
  EXPECT_NEAR(acc.terms.N, 60e-6, 1e-15);
  EXPECT_NEAR(acc.terms.B, 20e-6, 1e-15);
  // Velocity random walk: 0.06 m/s/sqrt(h) = 0.001 (m/s^2) sqrt(s).
  const Datasheet vrw = parse_datasheet("N=0.06m/s/sqrt(h)");
  EXPECT_EQ(vrw.unit.name, "m/s^2");
  EXPECT_NEAR(vrw.terms.N, 0.001, 1e-15);
}

TEST(PlanDatasheet, BadTermsAndUnitsNameTheItem) {
  const auto bad = [](const char* text) { return usage_error([&] { (void)parse_datasheet(text); }); };
  for (const char* text : {"N=0.15deg/h", "B=6deg/rth", "K=0.02deg/h", "N=1uT", "Q=1deg/s"}) {
    const auto [field, msg] = bad(text);
    EXPECT_EQ(field, Field::datasheet) << text;
    EXPECT_NE(msg.find("is not a unit of"), std::string::npos) << msg;
    EXPECT_NE(msg.find(text), std::string::npos) << msg;
  }
  EXPECT_NE(bad("N=0.15deg/h").second.find("deg/sqrt(h)"), std::string::npos);  // says what to give
  EXPECT_NE(bad("X=1deg").second.find("not a term"), std::string::npos);
  EXPECT_NE(bad("T=100s").second.find("leave it out"), std::string::npos);
  EXPECT_NE(bad("N=0.15").second.find("give the unit"), std::string::npos);
  EXPECT_NE(bad("N=-1deg/rth").second.find("0 or more"), std::string::npos);
  EXPECT_NE(bad("N=1deg/rth,N=2deg/rth").second.find("twice"), std::string::npos);
  EXPECT_NE(bad("N=1deg/rth,B=3uT").second.find("not a unit of the sensor"), std::string::npos);
  EXPECT_NE(bad("N=1furlong/rth").second.find("'furlong' is not a quantity"), std::string::npos);
  EXPECT_NE(bad("N=1deg/fortnight").second.find("'fortnight'"), std::string::npos);
  EXPECT_NE(bad(" , ").second.find("no terms"), std::string::npos);
  for (const char* text : {"X=1deg", "N=0.15", "N=1deg/rth,B=3uT", " , "}) EXPECT_EQ(bad(text).first, Field::datasheet);
}

TEST(PlanRequest, SourcesAndTheirErrors) {
  PlanRequest r;
  EXPECT_EQ(usage_error([&] { r.validate(); }).first, Field::model);
  // A datasheet needs the rate.
  EXPECT_EQ(usage_error([&] { set_plan_datasheet(r, "N=0.15deg/rth", std::nullopt); }).first, Field::rate);
  set_plan_datasheet(r, "N=0.15deg/rth", 100.0);
  EXPECT_EQ(r.source, PlanSource::datasheet);
  EXPECT_EQ(r.rate_hz, 100.0);
  // One source only.
  EXPECT_EQ(usage_error([&] { set_plan_presets(r, {"sport-gyro"}, std::nullopt); }).first, Field::model);
  PlanRequest p;
  const auto unknown = usage_error([&] { set_plan_presets(p, {"no-such-sensor"}, std::nullopt); });
  EXPECT_EQ(unknown.first, Field::model);
  EXPECT_NE(unknown.second.find("sport-gyro"), std::string::npos);  // names the known ones
  set_plan_presets(p, {"sport-gyro", "sport-mag"}, std::nullopt);
  EXPECT_EQ(p.rate_hz, 10.0);  // kPresetRateHz
  EXPECT_EQ(p.triads.size(), 2u);
  EXPECT_EQ(p.source_name, "sport-gyro,sport-mag");
  // Targets: a precision outside (0, 1), a term twice.
  p.targets = {{PlanTerm::B, 0.0}};
  EXPECT_EQ(usage_error([&] { p.validate(); }).first, Field::target);
  p.targets = {{PlanTerm::B, 1.0}};
  EXPECT_EQ(usage_error([&] { p.validate(); }).first, Field::target);
  p.targets = {{PlanTerm::B, 0.1}, {PlanTerm::B, 0.2}};
  EXPECT_EQ(usage_error([&] { p.validate(); }).first, Field::target);
  p.targets = {{PlanTerm::B, 0.1}};
  p.ci = 1.0;
  EXPECT_EQ(usage_error([&] { p.validate(); }).first, Field::ci);
  p.ci = 0.683;
  p.duration_s = 0.1;  // less than three samples at 10 Hz
  EXPECT_EQ(usage_error([&] { p.validate(); }).first, Field::duration);
}

// A white-noise-only datasheet: N is read where the curve falls at -1/2 and
// is the datasheet's N exactly; its precision improves with the length.
TEST(PlanRun, WhiteNoiseTargetAndDuration) {
  PlanRequest r;
  set_plan_datasheet(r, "N=0.15deg/rth", 100.0);
  r.targets = {{PlanTerm::N, 0.01}};
  r.duration_s = 3600.0;
  const PlanResult res = run_plan(r);
  ASSERT_EQ(res.channels.size(), 1u);
  const PlanChannel& ch = res.channels[0];
  EXPECT_EQ(ch.name, "datasheet");
  ASSERT_EQ(ch.targets.size(), 1u);
  const PlanRow& t = ch.targets[0];
  EXPECT_EQ(t.at.reason, PlanReason::none) << t.at.why;
  EXPECT_EQ(t.target, 0.01);
  ASSERT_TRUE(std::isfinite(t.duration_s));
  EXPECT_LE(t.at.precision, 0.01);
  EXPECT_EQ(t.display.unit, "deg/sqrt(h)");
  EXPECT_NEAR(t.display.value, 0.15, 0.15 * 1e-3);
  ASSERT_EQ(ch.at_duration.size(), 1u);
  const PlanRow& d = ch.at_duration[0];
  EXPECT_FALSE(d.target.has_value());
  EXPECT_EQ(d.duration_s, 3600.0);
  // The length that meets 1 % is longer than an hour exactly when an hour gives more than 1 %.
  EXPECT_EQ(t.duration_s > 3600.0, d.at.precision > 0.01);
  // The curve: 40 ascending lengths spanning the planned ones, N's precision falling along it.
  ASSERT_EQ(ch.curves.size(), 1u);
  const PlanCurve& c = ch.curves[0];
  ASSERT_EQ(c.duration_s.size(), 40u);
  EXPECT_LE(c.duration_s.front(), std::min(t.duration_s, 3600.0));
  EXPECT_GE(c.duration_s.back(), std::max(t.duration_s, 3600.0));
  for (std::size_t i = 1; i < c.duration_s.size(); ++i) {
    EXPECT_GT(c.duration_s[i], c.duration_s[i - 1]);
    if (std::isfinite(c.precision[i]) && std::isfinite(c.precision[i - 1])) {
      EXPECT_LE(c.precision[i], c.precision[i - 1] * 1.0001) << i;
    }
  }
}

TEST(PlanRun, UnreachableTargetsCarryTheirReasons) {
  // No random walk in the datasheet: K is not in the model at any length,
  // nor is B (a flicker floor alone never turns the curve up into a
  // minimum); T at 1 % is finer than the tau grid lets the minimum be placed.
  PlanRequest r;
  set_plan_datasheet(r, "N=0.15deg/rth,B=6deg/h", 100.0);
  r.targets = {{PlanTerm::K, 0.2}, {PlanTerm::T, 0.01}, {PlanTerm::B, 0.1}, {PlanTerm::N, 0.01}};
  const PlanResult res = run_plan(r);
  const auto& rows = res.channels.at(0).targets;
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0].at.reason, PlanReason::not_in_model);
  EXPECT_EQ(rows[1].at.reason, PlanReason::finer_than_model) << rows[1].at.why;
  EXPECT_EQ(rows[2].at.reason, PlanReason::not_in_model) << rows[2].at.why;
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_TRUE(std::isnan(rows[k].duration_s)) << k;
    EXPECT_FALSE(rows[k].at.why.empty()) << k;
  }
  EXPECT_EQ(rows[3].at.reason, PlanReason::none) << rows[3].at.why;
  EXPECT_GT(rows[3].duration_s, 0.0);
  // In the JSON: duration_s null, the reason and why given; the target as the precision.
  const nlohmann::json j = to_json(res);
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 4u);
  EXPECT_TRUE(j[0].at("duration_s").is_null());
  EXPECT_EQ(j[0].at("reason"), "not in model");
  EXPECT_EQ(j[0].at("why"), rows[0].at.why);
  EXPECT_EQ(j[0].at("precision"), 0.2);
  EXPECT_EQ(j[1].at("reason"), "finer than model");
  EXPECT_TRUE(j[3].at("reason").is_null());
  EXPECT_TRUE(j[3].at("why").is_null());
  EXPECT_EQ(j[3].at("duration_s").get<double>(), rows[3].duration_s);
}

TEST(PlanRun, ATargetPastTenYearsIsTooLongWithItsValue) {
  // A random walk so small it turns the curve up only after years: B is in
  // the model, read where analyze reads it (6 deg/h from the floor of 0.664 B),
  // but 10 % needs more than ten years of record.
  PlanRequest r;
  set_plan_datasheet(r, "N=0.15deg/rth,B=6deg/h,K=0.02deg/h/rth", 100.0);
  r.targets = {{PlanTerm::B, 0.1}};
  const PlanRow row = run_plan(r).channels.at(0).targets.at(0);
  EXPECT_EQ(row.at.reason, PlanReason::too_long) << row.at.why;
  EXPECT_TRUE(std::isnan(row.duration_s));
  EXPECT_EQ(row.display.unit, "deg/h");
  EXPECT_NEAR(row.display.value, 6.0, 0.06);
}

TEST(PlanRun, PresetDefaultsAndJsonShape) {
  PlanRequest r;
  set_plan_presets(r, {"sport-gyro"}, std::nullopt);
  const PlanResult res = run_plan(r);
  EXPECT_TRUE(res.defaults);
  ASSERT_EQ(res.targets.size(), 4u);  // B:10%,N:1%,K:20%,T:30%
  ASSERT_TRUE(res.duration_s.has_value());
  EXPECT_EQ(*res.duration_s, 72.0 * 3600.0);
  ASSERT_EQ(res.channels.size(), 3u);
  EXPECT_EQ(res.channels[0].name, "gx");
  EXPECT_EQ(res.channels[2].name, "gz");
  const nlohmann::json j = to_json(res);
  ASSERT_EQ(j.size(), 3u * (4u + 4u));  // per channel 4 target rows and N, B, K, T at 72 h
  for (const auto& row : j) {
    for (const char* key : {"channel", "term", "kind", "precision", "duration_s", "achieved", "value", "unit", "tau_lo",
                            "tau_hi", "reason", "why"})
      EXPECT_TRUE(row.contains(key)) << key;
    if (row.at("kind") == "duration") {
      EXPECT_EQ(row.at("duration_s"), 72.0 * 3600.0);
    }
  }
  // The paper's gyro has a random walk (sigma_mu) on every axis: K is planned.
  for (const auto& ch : res.channels)
    for (const auto& row : ch.targets)
      if (row.at.term == PlanTerm::K) {
        EXPECT_EQ(row.at.reason, PlanReason::none) << ch.name << ": " << row.at.why;
      }
  const nlohmann::json doc = plan_document(res);
  EXPECT_EQ(doc.at("command"), "plan");
  EXPECT_EQ(doc.at("source"), "preset");
  EXPECT_EQ(doc.at("rows"), j);
  EXPECT_EQ(doc.at("curves").size(), 3u * 4u);
  EXPECT_EQ(doc.at("curves")[0].at("duration_s").size(), 40u);
}

TEST(PlanRun, ARateRescalesThePresetKeepingN) {
  PlanRequest slow, fast;
  set_plan_presets(slow, {"sport-gyro"}, std::nullopt);
  set_plan_presets(fast, {"sport-gyro"}, 100.0);
  slow.targets = fast.targets = {{PlanTerm::N, 0.05}};
  const PlanResult a = run_plan(slow), b = run_plan(fast);
  const double na = a.channels[0].targets[0].display.value, nb = b.channels[0].targets[0].display.value;
  EXPECT_NEAR(nb, na, 0.02 * na);  // the sensor's N, whatever the rate
  EXPECT_EQ(b.rate_hz, 100.0);
}

ModelResult white_plus_walk_model() {
  ModelResult m;
  m.rate_hz = 10.0;
  m.model = "WN+RW";
  ModelChannel ch;
  ch.name = "gx";
  ch.unit = *parse_unit("deg/s");
  ch.fit.model.processes = {{ProcessKind::wn, 0.05 * 0.05}, {ProcessKind::rw, 1e-10}};
  m.channels.push_back(ch);
  return m;
}

TEST(PlanRun, ModelResultAndAnalysisSources) {
  PlanRequest r;
  set_plan_model_result(r, white_plus_walk_model(), "model.json", std::nullopt);
  EXPECT_EQ(r.source, PlanSource::model);
  EXPECT_EQ(r.rate_hz, 10.0);
  r.targets = {{PlanTerm::N, 0.05}};
  const PlanResult res = run_plan(r);
  // N = sigma sqrt(dt) = 0.05 sqrt(0.1) deg/s sqrt(s), x 60 in deg/sqrt(h).
  EXPECT_NEAR(res.channels.at(0).targets.at(0).display.value, 0.05 * std::sqrt(0.1) * 60.0, 0.01);

  // An analysis with a twin on every channel plans the twin; without, the random-walk model, said so.
  AnalysisResult a;
  a.rate_hz = 10.0;
  ChannelAnalysis ch;
  ch.name = "gx";
  ch.unit = *parse_unit("deg/s");
  ch.model.ok = true;
  ch.model.random_walk = {0.05, 1e-5, 0.1, 0.0};
  a.channels.push_back(ch);
  PlanRequest rw;
  set_plan_analysis(rw, a, "analysis.json", std::nullopt);
  EXPECT_EQ(rw.source, PlanSource::random_walk);
  EXPECT_NE(rw.source_note.find("no twin"), std::string::npos);
  a.channels[0].model.composite = white_plus_walk_model().channels[0];
  PlanRequest twin;
  set_plan_analysis(twin, a, "analysis.json", 20.0);
  EXPECT_EQ(twin.source, PlanSource::twin);
  EXPECT_EQ(twin.rate_hz, 20.0);
  EXPECT_EQ(twin.triads.at(0).axis_names[0], "gx");
  EXPECT_TRUE(twin.triads.at(0).axis_names[1].empty());  // one channel: a partial triad
  twin.targets = {{PlanTerm::N, 0.05}};
  EXPECT_EQ(run_plan(twin).channels.size(), 1u);
}

TEST(PlanWords, DurationsAndPercentages) {
  EXPECT_EQ(duration_words(50.0), "50 s");
  EXPECT_EQ(duration_words(12 * 60.0), "12 min");
  EXPECT_EQ(duration_words(3 * 3600.0 + 20 * 60.0), "3 h 20 min");
  EXPECT_EQ(duration_words(5 * 3600.0), "5 h");
  EXPECT_EQ(duration_words(72 * 3600.0), "72 h");
  EXPECT_EQ(duration_words(4.2 * 86400.0), "4.2 d");
  EXPECT_EQ(duration_words(40 * 86400.0), "40 d");
  EXPECT_EQ(duration_words(2 * 365.25 * 86400.0), "2.0 years");
  EXPECT_EQ(duration_words(std::nan("")), "-");
  EXPECT_EQ(percent_words(0.1), "10 %");
  EXPECT_EQ(percent_words(0.015), "1.5 %");
  EXPECT_EQ(percent_words(1.5), "150 %");
}

}  // namespace
}  // namespace cubecal::pipeline
