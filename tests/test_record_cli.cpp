// cubecal record as a command (issue 33, items 2 and 8): serial noise that is
// not UTF-8 before the header goes to rejects.csv and the recording goes on;
// a restart never follows a symbolic link or writes outside the directory
// (a link to a file outside it is left untouched); ports are range-checked;
// --chunk-seconds must be a finite positive number; a run without a sample
// records nothing and exits 2.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
using cubecal::test::CliRun;
using cubecal::test::one_error_line;
using cubecal::test::run_cubecal;
using cubecal::test::run_cubecal_piped;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Well-formed UTF-8 without NUL or any control byte but the line feed.
bool clean_text(const std::string& s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      if ((c < 0x20 && c != '\n') || c == 0x7f) return false;
      ++i;
      continue;
    }
    const std::size_t len = c >= 0xc2 && c <= 0xdf ? 2 : c >= 0xe0 && c <= 0xef ? 3 : c >= 0xf0 && c <= 0xf4 ? 4 : 0;
    if (len == 0 || i + len > s.size()) return false;
    for (std::size_t k = 1; k < len; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return false;
    i += len;
  }
  return true;
}

class RecordCli : public cubecal::test::TempDirTest {
 protected:
  // A recording of three samples, then its manifest edited as a crash
  // leaves it: the segment and its chunk open, nothing vouched for.
  std::string crashed_recording(const std::string& name) {
    const std::string d = path(name);
    const CliRun r = run_cubecal_piped("printf 't,gx\\n0,1\\n0.01,2\\n0.02,3\\n'", "record - --out " + d);
    EXPECT_EQ(r.code, 0) << r.err;
    nlohmann::json m = nlohmann::json::parse(slurp(fs::path(d) / "manifest.json"));
    m["segments"][0]["end"] = "open";
    m["segments"][0]["chunks"][0]["open"] = true;
    m["segments"][0]["chunks"][0]["bytes"] = 0;
    std::ofstream(fs::path(d) / "manifest.json") << m.dump(2);
    return d;
  }
  // A file outside the recording whose last line is partial: what recovery
  // would cut off a chunk.
  std::string outside() {
    const std::string p = path("outside.txt");
    std::ofstream(p, std::ios::binary) << "precious line one\nprecious data, no newline";
    return p;
  }
  CliRun restart(const std::string& d) { return run_cubecal_piped("printf 't,gx\\n0,1\\n'", "record - --out " + d); }
};

// Item 2: bytes that are not UTF-8 (and a NUL) before the header: rejects,
// the header after them sets the layout, rejects.csv stays clean text that
// gives the bytes back, and the directory is taken up by the next run.
TEST_F(RecordCli, NoiseThatIsNotUtf8BeforeTheHeaderIsARejectAndRecordingGoesOn) {
  const std::string d = path("noise");
  const std::string feed =
      "printf '\\377\\376\\000garbage\\351 \\\\x41\\n\\351\\377\\nt,gx\\n0,1\\n0.01,2\\n0.02,3\\n'";
  const CliRun r = run_cubecal_piped(feed, "record - --out " + d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
  const nlohmann::json m = nlohmann::json::parse(slurp(fs::path(d) / "manifest.json"));
  EXPECT_EQ(m["columns"], (std::vector<std::string>{"t", "gx"}));
  EXPECT_EQ(m["segments"][0]["samples"], 3);
  EXPECT_EQ(m["segments"][0]["rejects"], 2);
  const std::string rejects = slurp(fs::path(d) / "seg-001" / "rejects.csv");
  EXPECT_TRUE(clean_text(rejects)) << rejects;
  EXPECT_NE(rejects.find(R"("\xff\xfe\x00garbage\xe9 \x5cx41")"), std::string::npos) << rejects;
  EXPECT_NE(rejects.find(R"("\xe9\xff")"), std::string::npos) << rejects;
  EXPECT_EQ(std::count(rejects.begin(), rejects.end(), '\n'), 3) << rejects;
  const CliRun again = run_cubecal_piped(feed, "record - --out " + d);
  EXPECT_EQ(again.code, 0) << again.err;
  EXPECT_TRUE(fs::exists(fs::path(d) / "seg-002" / "chunk-000001.csv"));
}

// Item 8: a restart on a recording whose open chunk is a symbolic link to a
// file outside it: refused, naming the link; the file is untouched.
TEST_F(RecordCli, ARestartNeverFollowsAChunkThatIsASymbolicLink) {
  const std::string d = crashed_recording("rec");
  const std::string victim = outside();
  const std::string before = slurp(victim);
  const fs::path chunk = fs::path(d) / "seg-001" / "chunk-000001.csv";
  fs::remove(chunk);
  fs::create_symlink(victim, chunk);
  const CliRun r = restart(d);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find(chunk.string() + " is a symbolic link"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(victim), before);
  EXPECT_TRUE(fs::is_symlink(chunk));
}

// The same for the segment's rejects.csv (appended to, its partial last
// line cut off), the segment directory and the manifest.
TEST_F(RecordCli, ARestartNeverFollowsRejectsSegmentOrManifestLinks) {
  const std::string victim = outside();
  const std::string before = slurp(victim);
  {
    const std::string d = crashed_recording("rejects");
    const fs::path rej = fs::path(d) / "seg-001" / "rejects.csv";
    fs::create_symlink(victim, rej);
    const CliRun r = restart(d);
    EXPECT_TRUE(one_error_line(r)) << r.err;
    EXPECT_NE(r.err.find(rej.string() + " is a symbolic link"), std::string::npos) << r.err;
  }
  {
    const std::string d = crashed_recording("segment");
    fs::rename(fs::path(d) / "seg-001", path("elsewhere"));
    fs::create_symlink(path("elsewhere"), fs::path(d) / "seg-001");
    const CliRun r = restart(d);
    EXPECT_TRUE(one_error_line(r)) << r.err;
    EXPECT_NE(r.err.find("seg-001 is a symbolic link"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("elsewhere/rejects.csv")));
  }
  {
    const std::string d = crashed_recording("manifest");
    fs::rename(fs::path(d) / "manifest.json", path("manifest-elsewhere.json"));
    fs::create_symlink(path("manifest-elsewhere.json"), fs::path(d) / "manifest.json");
    const CliRun r = restart(d);
    EXPECT_TRUE(one_error_line(r)) << r.err;
    EXPECT_NE(r.err.find("manifest.json is a symbolic link"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_symlink(fs::path(d) / "manifest.json"));
  }
  EXPECT_EQ(slurp(victim), before);
}

// The next segment's directory is made afresh: one found there (a link to
// a directory elsewhere) is refused, nothing is written into it.
TEST_F(RecordCli, TheNextSegmentDirectoryIsNeverOneFoundThere) {
  const std::string d = path("rec");
  ASSERT_EQ(run_cubecal_piped("printf 't,gx\\n0,1\\n'", "record - --out " + d).code, 0);
  fs::create_directories(path("elsewhere"));
  fs::create_symlink(path("elsewhere"), fs::path(d) / "seg-002");
  const CliRun r = restart(d);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("seg-002 exists but the manifest does not name it"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(path("elsewhere")));
}

// A segment the manifest names whose directory was never made (a crash
// between the two) is dropped, and the run records.
TEST_F(RecordCli, ASegmentNamedButNeverMadeIsDroppedOnRestart) {
  const std::string d = crashed_recording("rec");
  fs::remove_all(fs::path(d) / "seg-001");
  const CliRun r = restart(d);
  EXPECT_EQ(r.code, 0) << r.err;
  const nlohmann::json m = nlohmann::json::parse(slurp(fs::path(d) / "manifest.json"));
  ASSERT_EQ(m["segments"].size(), 1u) << m.dump(2);
  EXPECT_EQ(m["segments"][0]["samples"], 1);
  EXPECT_EQ(m["segments"][0]["end"], "clean");
}

TEST_F(RecordCli, PortsOutOfRangeAreRefused) {
  for (const std::string src :
       {"udp:99999", "udp:0", "udp:65536", "udp:5x", "tcp:127.0.0.1:99999", "tcp:127.0.0.1:0", "udp:0.0.0.0:70000"}) {
    const CliRun r = run_cubecal("record " + src + " --out " + path("p") + " --duration 1s");
    EXPECT_TRUE(one_error_line(r)) << src << ": " << r.err;
    EXPECT_NE(r.err.find("the port is a number from 1 to 65535"), std::string::npos) << src << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(path("p")));
}

TEST_F(RecordCli, ChunkSecondsMustBeAFinitePositiveNumber) {
  for (const std::string v : {"nan", "inf", "-inf", "-1", "0"}) {
    const CliRun r =
        run_cubecal_piped("printf 't,gx\\n0,1\\n'", "record - --out " + path("c") + " --chunk-seconds " + v);
    EXPECT_TRUE(one_error_line(r)) << v << ": " << r.err;
    EXPECT_NE(r.err.find("--chunk-seconds"), std::string::npos) << v << ": " << r.err;
    EXPECT_FALSE(fs::exists(path("c/manifest.json"))) << v;
  }
}

// docs/record.md: a run in which no data line arrives records nothing and
// exits 2 (no input at all, or a header line only).
TEST_F(RecordCli, ARunWithoutASampleExits2AndRecordsNothing) {
  const CliRun none = run_cubecal("record - --out " + path("none") + " </dev/null");
  EXPECT_TRUE(one_error_line(none)) << none.err;
  EXPECT_NE(none.err.find("no input arrived"), std::string::npos) << none.err;
  EXPECT_FALSE(fs::exists(path("none/manifest.json")));
  const CliRun header = run_cubecal_piped("printf 't,gx\\n'", "record - --out " + path("header"));
  EXPECT_TRUE(one_error_line(header)) << header.err;
  EXPECT_NE(header.err.find("no data line"), std::string::npos) << header.err;
  EXPECT_FALSE(fs::exists(path("header/manifest.json")));
  EXPECT_FALSE(fs::exists(path("header/seg-001")));
  // The directory is still empty: a later run records into it.
  EXPECT_EQ(run_cubecal_piped("printf 'a,b\\n0,1\\n'", "record - --out " + path("header")).code, 0);
}

}  // namespace
