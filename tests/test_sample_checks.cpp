// The readers' rate and magnitude rules on records held in memory
// (io/sample_checks.hpp), which the Python module applies to its arrays, and
// the options whose extreme values made a non-finite result or an overflowed
// number in a message (issue 33, item 10).
#include "cubecal/io/sample_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"

namespace {

using cubecal::InputError;
using cubecal::UsageError;
using cubecal::io::check_rate;
using cubecal::io::check_samples;

TEST(SampleChecks, RateOutsideTheReadersRangeIsAUsageErrorOnRate) {
  for (const double r : {1e300, 1e-300, 0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    try {
      check_rate(r);
      ADD_FAILURE() << r << " accepted";
    } catch (const UsageError& e) {
      ASSERT_TRUE(e.field().has_value());
      EXPECT_EQ(*e.field(), cubecal::Field::rate);
    }
  }
  try {
    check_rate(1e300);
  } catch (const UsageError& e) {
    EXPECT_STREQ(e.what(), "the sampling rate 1e+300 Hz is outside the range 1e-09 to 1e+09 Hz");
  }
  EXPECT_NO_THROW(check_rate(cubecal::io::kMinRateHz));
  EXPECT_NO_THROW(check_rate(cubecal::io::kMaxRateHz));
  EXPECT_NO_THROW(check_rate(100.0));
}

// The place of the error: (line, column) = (sample + 1, column).
std::pair<std::size_t, std::size_t> place_of(const std::vector<double>& v, bool missing = false) {
  try {
    check_samples(v, "<arrays>", 2, "gx", missing);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "<arrays>");
    EXPECT_FALSE(e.hint().empty());
    return {e.line(), e.column()};
  }
  return {0, 0};
}

TEST(SampleChecks, ValuesTheReadersRefuseAreInputErrorsAtTheirPlace) {
  std::vector<double> v(50);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::sin(0.3 * static_cast<double>(i));
  EXPECT_EQ(place_of(v), (std::pair<std::size_t, std::size_t>{0, 0}));
  auto with = [&](std::size_t i, double x) {
    auto w = v;
    w[i] = x;
    return w;
  };
  EXPECT_EQ(place_of(with(7, std::nan(""))), (std::pair<std::size_t, std::size_t>{8, 2}));
  EXPECT_EQ(place_of(with(7, std::nan("")), true), (std::pair<std::size_t, std::size_t>{0, 0}));
  EXPECT_EQ(place_of(with(9, -std::numeric_limits<double>::infinity()), true),
            (std::pair<std::size_t, std::size_t>{10, 2}));
  EXPECT_EQ(place_of(with(11, 1e200)), (std::pair<std::size_t, std::size_t>{12, 2}));
  // Subnormal samples: every variance would be 0/0. Refused at the largest.
  std::vector<double> tiny(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) tiny[i] = v[i] * 1e-310;
  std::size_t top = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (std::fabs(v[i]) > std::fabs(v[top])) top = i;
  EXPECT_EQ(place_of(tiny), (std::pair<std::size_t, std::size_t>{top + 1, 2}));
  EXPECT_EQ(place_of(std::vector<double>(10, 0.0)), (std::pair<std::size_t, std::size_t>{0, 0}));
}

class ExtremeOptions : public cubecal::test::TempDirTest {};

TEST_F(ExtremeOptions, MagNoiseAndFieldNormAVarianceCannotHoldAreRefused) {
  // --noise 1e-300 was an "internal error" from the chi-squared test.
  const std::string csv = path("m.csv");
  {
    std::ofstream out(csv);
    out << "x,y,z\n";
    for (int i = 0; i < 200; ++i) {
      const double a = 0.1 * i, b = 0.37 * i;
      out << 30 * std::cos(a) * std::cos(b) + 5 << "," << 30 * std::sin(a) * std::cos(b) - 3 << ","
          << 30 * std::sin(b) + 1 << "\n";
    }
  }
  for (const std::string opt : {"--noise 1e-300", "--noise 1e300", "--field-norm 1e-300"}) {
    const auto r = cubecal::test::run_cubecal("calibrate mag " + csv + " --allow-partial " + opt);
    EXPECT_EQ(r.code, 2) << opt << ": " << r.err;
    EXPECT_TRUE(cubecal::test::one_error_line(r)) << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("1e-100 to 1e100"), std::string::npos) << r.err;
  }
}

TEST_F(ExtremeOptions, PsdFminBeyondAnyRecordSaysSoWithoutAnOverflowedCount) {
  const std::string csv = path("y.csv");
  {
    std::ofstream out(csv);
    out << "g\n";
    for (int i = 0; i < 2000; ++i) out << std::sin(0.7 * i) << "\n";
  }
  const auto r = cubecal::test::run_cubecal("psd " + csv + " --rate 100 --fmin 1e-300");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.err.find("-9223372036854775808"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("segments of 2^"), std::string::npos) << r.err;
}

}  // namespace
