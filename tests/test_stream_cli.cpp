// `dev --stream` through the CLI: a simulated record piped from `simulate
// --format raw --out -` gives the in-memory deviations of the same record
// (exactly where the stride is 1, within the intervals where it is not);
// text through a pipe; the automatic choice under --memory; what a stream
// refuses, as one error line and exit code 2.
#include <gtest/gtest.h>

#include <algorithm>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace {

using cubecal::test::CliRun;
using cubecal::test::one_error_line;
using cubecal::test::run_cubecal;
using cubecal::test::run_cubecal_piped;
using cubecal::test::TempDirTest;
using nlohmann::json;

const std::string kSim =
    std::string(CUBECAL_BINARY) + " simulate --preset sport-gyro --rate 100 --duration 3h --seed 5";
const std::string kFrames = "--binary float64le,float64le,float64le,float64le --rate 100";

class StreamCli : public TempDirTest {};

TEST_F(StreamCli, PipedRawEqualsInMemory) {
  const std::string raw = path("g.raw");
  ASSERT_EQ(
      run_cubecal("simulate --preset sport-gyro --rate 100 --duration 3h --seed 5 --format raw --out " + raw).code, 0);
  const CliRun mem = run_cubecal("dev " + raw + " " + kFrames + " --columns 1,3 --taus log:5 --format json");
  ASSERT_EQ(mem.code, 0) << mem.err;
  const CliRun st =
      run_cubecal_piped(kSim + " --format raw --out -",
                        "dev - " + kFrames + " --columns 1,3 --taus log:5 --format json --stream --memory 16M");
  ASSERT_EQ(st.code, 0) << st.err;
  const json a = json::parse(mem.out), b = json::parse(st.out);
  ASSERT_TRUE(b.contains("stream"));
  EXPECT_FALSE(a.contains("stream"));
  const std::size_t bound = b["stream"]["window_bound"].get<std::size_t>();
  EXPECT_LT(bound, 65536u);  // 16M: strided factors occur
  ASSERT_EQ(b["columns"].size(), 2u);
  std::size_t exact = 0, strided = 0;
  for (std::size_t c = 0; c < 2; ++c) {
    const json& ca = a["columns"][c];
    const json& cb = b["columns"][c];
    ASSERT_EQ(cb["stride"].size(), cb["af"].size());
    for (std::size_t j = 0; j < cb["af"].size(); ++j) {
      const std::size_t m = cb["af"][j].get<std::size_t>();
      // The in-memory point at the same factor.
      std::size_t k = 0;
      while (k < ca["af"].size() && ca["af"][k].get<std::size_t>() != m) ++k;
      const bool found = k < ca["af"].size();
      const std::size_t stride = cb["stride"][j].get<std::size_t>();
      const double dev = cb["dev"][j].get<double>();
      if (stride == 1) {
        ASSERT_TRUE(found) << m;
        ++exact;
        EXPECT_NEAR(dev, ca["dev"][k].get<double>(), 1e-12 * ca["dev"][k].get<double>()) << m;
        EXPECT_EQ(cb["n"][j], ca["n"][k]) << m;
        EXPECT_LE(2 * m, bound);
      } else if (found) {
        ++strided;
        EXPECT_GE(dev, ca["lo"][k].get<double>()) << m;
        EXPECT_LE(dev, ca["hi"][k].get<double>()) << m;
      }
    }
  }
  EXPECT_GT(exact, 10u);
  EXPECT_GT(strided, 3u);
}

TEST_F(StreamCli, PipedTextWithTimeColumn) {
  const std::string csv = path("g.csv");
  ASSERT_EQ(run_cubecal("simulate --preset sport-gyro --rate 100 --duration 1h --seed 6 --out " + csv).code, 0);
  const CliRun mem = run_cubecal("dev " + csv + " --columns gy --format csv");
  const CliRun st = run_cubecal_piped("cat " + csv, "dev - --columns gy --format csv --stream --window 1048576");
  ASSERT_EQ(mem.code, 0) << mem.err;
  ASSERT_EQ(st.code, 0) << st.err;
  // A bound above every factor of this hour: the same rows with a stride of
  // 1, alpha, EDF and interval included (below 30 averages both identify by
  // B1 from the same averages).
  const auto rows = [](const std::string& text) {
    std::vector<std::vector<std::string>> out;
    std::size_t pos = 0;
    while (pos < text.size()) {
      const std::size_t nl = text.find('\n', pos);
      std::vector<std::string> f;
      std::size_t b = pos;
      while (true) {
        const std::size_t comma = text.find(',', b);
        if (comma == std::string::npos || comma > nl) {
          f.push_back(text.substr(b, nl - b));
          break;
        }
        f.push_back(text.substr(b, comma - b));
        b = comma + 1;
      }
      out.push_back(f);
      pos = nl + 1;
    }
    return out;
  };
  const auto ra = rows(mem.out), rb = rows(st.out);
  ASSERT_EQ(ra.size(), rb.size());
  ASSERT_EQ(rb[0].back(), "stride");
  std::size_t short_rows = 0;
  for (std::size_t i = 1; i < ra.size(); ++i) {
    ASSERT_EQ(rb[i].size(), ra[i].size() + 1);
    EXPECT_EQ(rb[i].back(), "1");
    const std::size_t m = std::stoul(ra[i][1]);
    EXPECT_EQ(std::vector<std::string>(rb[i].begin(), rb[i].end() - 1), ra[i]) << m;
    if (360000 / m < 30) ++short_rows;
  }
  EXPECT_EQ(short_rows, 3u);  // AF 16384, 32768, 65536: under 30 averages
}

TEST_F(StreamCli, ChosenWhenTheFileExceedsTheBudget) {
  const std::string raw = path("big.raw");
  ASSERT_EQ(
      run_cubecal("simulate --preset sport-gyro --rate 100 --duration 2h --seed 7 --format raw --out " + raw).code, 0);
  const CliRun r = run_cubecal("dev " + raw + " " + kFrames + " --columns 2 --memory 8M --format csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("streaming it in one pass"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.rfind("column,af,tau,n,alpha,edf,lo,dev,hi,stride\n", 0), 0u) << r.out.substr(0, 80);
  const CliRun whole = run_cubecal("dev " + raw + " " + kFrames + " --columns 2 --memory 1G --format csv");
  EXPECT_TRUE(whole.err.empty()) << whole.err;
  EXPECT_EQ(whole.out.rfind("column,af,tau,n,alpha,edf,lo,dev,hi\n", 0), 0u);
}

TEST_F(StreamCli, RefusalsAreOneLine) {
  const std::string bad = write("bad.csv", "t,gx\n0,1\n0.1,2\n0.2,zz\n0.3,4\n");
  for (const std::string& args : {std::string("dev ") + bad + " --stream",     // a bad field
                                  "dev " + bad + " --stream --stat mdev",      // not streamed
                                  "dev " + bad + " --stream --taus all",       // not streamed
                                  "dev " + bad + " --stream --gaps split",     // not cut
                                  "dev " + bad + " --stream --memory 12Q"}) {  // not a size
    const CliRun r = run_cubecal(args);
    EXPECT_TRUE(one_error_line(r)) << args << ": " << r.code << " " << r.err;
  }
  const CliRun partial = run_cubecal_piped("head -c 8003 /dev/zero", "dev - --binary float64le --rate 10 --stream");
  EXPECT_TRUE(one_error_line(partial)) << partial.err;
  EXPECT_NE(partial.err.find("byte offset 8000"), std::string::npos) << partial.err;
  const CliRun line = run_cubecal("dev " + bad + " --stream");
  EXPECT_NE(line.err.find("bad.csv:4:"), std::string::npos) << line.err;
}

}  // namespace

namespace {

// --window sets the stream's bound: factors up to half of it exact, the
// others strided, inside the in-memory intervals; a bound that is not a
// power of two from 16 is refused in one line.
TEST_F(StreamCli, WindowSetsTheExactBound) {
  const std::string raw = path("w.raw");
  ASSERT_EQ(
      run_cubecal("simulate --preset sport-gyro --rate 100 --duration 1h --seed 9 --format raw --out " + raw).code, 0);
  const CliRun mem = run_cubecal("dev " + raw + " " + kFrames + " --columns 1 --taus octave --format json");
  const CliRun st =
      run_cubecal("dev " + raw + " " + kFrames + " --columns 1 --taus octave --format json --stream --window 64");
  ASSERT_EQ(mem.code, 0) << mem.err;
  ASSERT_EQ(st.code, 0) << st.err;
  const json a = json::parse(mem.out)["columns"][0], b = json::parse(st.out);
  EXPECT_EQ(b["stream"]["window_bound"].get<std::size_t>(), 64u);
  const json& c = b["columns"][0];
  ASSERT_EQ(c["af"].size(), a["af"].size());
  for (std::size_t j = 0; j < c["af"].size(); ++j) {
    const std::size_t m = c["af"][j].get<std::size_t>();
    ASSERT_EQ(m, a["af"][j].get<std::size_t>());
    if (2 * m <= 64) {
      EXPECT_EQ(c["stride"][j].get<std::size_t>(), 1u) << m;
      EXPECT_NEAR(c["dev"][j].get<double>(), a["dev"][j].get<double>(), 1e-12 * a["dev"][j].get<double>()) << m;
    } else {
      EXPECT_GT(c["stride"][j].get<std::size_t>(), 1u) << m;
      EXPECT_GE(c["dev"][j].get<double>(), a["lo"][j].get<double>()) << m;
      EXPECT_LE(c["dev"][j].get<double>(), a["hi"][j].get<double>()) << m;
    }
  }
  for (const char* w : {"12", "100", "8"}) {
    const CliRun r = run_cubecal("dev " + raw + " " + kFrames + " --columns 1 --stream --window " + w);
    EXPECT_EQ(r.code, 2) << w;
    EXPECT_EQ(r.err.rfind("cubecal: error: --window: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

}  // namespace
