// The hostile-input corpus: a small record of every format cubecal reads
// (delimited text, gzip, .npy, raw binary, HDF5, ROS 1 bag, MCAP, .db3, PX4
// ULog, a recording directory, analysis.json), each also cut short and with
// bytes changed at seeded places, and the hand-made cases of the hostile run
// (invalid UTF-8, non-finite and extreme values, clocks that run backwards,
// a gzip that inflates far beyond its size, a .npy whose header lies), run
// through every command that reads a file. For each run:
//   - no signal, and no hang (a 60 s alarm is a signal);
//   - no "internal error";
//   - exit 0 or 2, and after exit 2 a last line "cubecal: error: ...";
//   - every line of standard error printable (no raw bytes of the input);
//   - after exit 0, no non-finite number (nan, inf) in what was printed;
//   - a peak resident memory under kPeakBoundKiB (100 MB for the gzip that
//     inflates beyond its --memory).
// A failure names the input and the command, so a case is reproduced with
// `cubecal <command> <input>` on the file the test wrote (kept under
// /tmp/cubecal_corpus_<pid> when CUBECAL_KEEP_CORPUS is set).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cubecal/printable_text.hpp"
#include "ros2_bag_writer.hpp"
#include "gzip_text.hpp"

namespace {

using cubecal::test::gzip;
namespace fs = std::filesystem;
namespace ros2 = cubecal::test::ros2;

constexpr long kPeakBoundKiB = 300L << 10;         // peak resident memory of one run
constexpr rlim_t kAddressLimit = rlim_t{2} << 30;  // address space: a runaway fails fast
constexpr unsigned kAlarmSeconds = 60;

// One input of the corpus: a file or directory and the reader options it needs.
struct Input {
  std::string name;               // what it is, for the failure message
  std::string path;               // file or directory
  std::vector<std::string> args;  // --rate, --binary, --dataset ...
  bool json = false;              // an analysis.json (simulate --model, report)
  long peak_kib = kPeakBoundKiB;  // the bound on a run's peak resident memory
};

struct Outcome {
  bool signaled = false;
  int signal = 0;
  int code = -1;
  long peak_kib = 0;
  std::string out, err;
};

std::string slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void spit(const std::string& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

// Runs the binary with `args`, stdout and stderr to files in `dir`, under an
// address-space limit and an alarm; the peak RSS from wait4.
Outcome run_limited(const std::vector<std::string>& args, const fs::path& dir, const std::string& stdin_path) {
  const std::string out_path = (dir / "stdout.txt").string(), err_path = (dir / "stderr.txt").string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    const rlimit lim{kAddressLimit, kAddressLimit};
    ::setrlimit(RLIMIT_AS, &lim);
    const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int in = ::open(stdin_path.c_str(), O_RDONLY);
    ::dup2(in, 0);
    ::dup2(out, 1);
    ::dup2(err, 2);
    ::chdir(dir.c_str());
    ::alarm(kAlarmSeconds);
    std::vector<char*> argv{const_cast<char*>(CUBECAL_BINARY)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(CUBECAL_BINARY, argv.data());
    ::_exit(127);
  }
  int status = 0;
  rusage usage{};
  ::wait4(pid, &status, 0, &usage);
  Outcome r;
  r.signaled = WIFSIGNALED(status);
  r.signal = r.signaled ? WTERMSIG(status) : 0;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.peak_kib = usage.ru_maxrss;
  r.out = slurp(out_path);
  r.err = slurp(err_path);
  return r;
}

// A 100 Hz gyro log with a temperature column: white noise plus a slow walk.
std::vector<std::vector<double>> gyro_rows(std::size_t rows) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<std::vector<double>> out;
  double walk = 0.0;
  for (std::size_t i = 0; i < rows; ++i) {
    walk += 1e-3 * n(rng);
    const double t = static_cast<double>(i) / 100.0;
    out.push_back({t, 0.01 * n(rng) + walk, -0.02 + 0.01 * n(rng), 0.003 * n(rng), 25.0 + 0.001 * t});
  }
  return out;
}

std::string csv(const std::vector<std::vector<double>>& rows, bool header, std::size_t first_col = 0) {
  std::ostringstream s;
  s.precision(9);
  if (header) s << (first_col == 0 ? "t,gx,gy,gz,temp\n" : "gx,gy,gz,temp\n");
  for (const auto& r : rows) {
    for (std::size_t c = first_col; c < r.size(); ++c) s << (c > first_col ? "," : "") << r[c];
    s << '\n';
  }
  return s.str();
}

// A NumPy .npy of float64 rows x cols, C order, with `shape` as the header says it.
std::string npy(const std::vector<std::vector<double>>& rows, std::size_t first_col, const std::string& shape) {
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': " + shape + ", }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(header.size() & 0xff);
  out += static_cast<char>(header.size() >> 8);
  out += header;
  for (const auto& r : rows)
    for (std::size_t c = first_col; c < r.size(); ++c) out.append(reinterpret_cast<const char*>(&r[c]), 8);
  return out;
}

std::string raw_int16(const std::vector<std::vector<double>>& rows) {
  std::string out;
  for (const auto& r : rows)
    for (std::size_t c = 1; c < 4; ++c) {
      const auto v = static_cast<std::int16_t>(std::lround(r[c] * 1000.0));
      out.append(reinterpret_cast<const char*>(&v), 2);
    }
  return out;
}

void hdf5(const std::string& p, const std::vector<std::vector<double>>& rows) {
  const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  std::vector<double> v;
  for (const auto& r : rows) v.insert(v.end(), r.begin() + 1, r.begin() + 4);
  const hsize_t dims[2] = {rows.size(), 3};
  const hid_t space = H5Screate_simple(2, dims, nullptr);
  const hid_t ds = H5Dcreate2(f, "gyro", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Dclose(ds);
  H5Sclose(space);
  H5Fclose(f);
}

void db3(const fs::path& dir, const std::vector<std::vector<double>>& rows) {
  fs::create_directories(dir);
  ros2::Db3Writer w((dir / "imu_0.db3").string());
  w.topic(1, "/imu/data", "sensor_msgs/msg/Imu");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double g[3] = {rows[i][1], rows[i][2], rows[i][3]}, a[3] = {0.0, 0.0, 9.81};
    const std::int64_t ns = 1'000'000'000 + static_cast<std::int64_t>(i) * 10'000'000;
    w.message(1, ns,
              ros2::imu_cdr(true, static_cast<std::int32_t>(ns / 1'000'000'000),
                            static_cast<std::uint32_t>(ns % 1'000'000'000), g, a));
  }
}

// Hand-made text cases of the hostile run: (name, bytes, needs --rate).
struct TextCase {
  std::string name, bytes;
  bool rate;
};

std::vector<TextCase> text_cases() {
  const std::string ok = "0.01,2\n0.02,1.5\n0.03,1.7\n0.04,1.6\n0.05,1.9\n0.06,1.8\n0.07,2.1\n0.08,1.4\n";
  // 200 rows of two or three columns after t = 0, enough for every command to reach its output.
  std::string rows2, rows3;
  for (int r = 1; r <= 200; ++r) {
    const std::string t = std::to_string(r * 0.01), v = std::to_string((r * 37 % 11) * 0.1);
    rows2 += t + "," + v + "\n";
    rows3 += t + "," + v + "," + std::to_string((r * 17 % 7) * 0.2) + "\n";
  }
  std::string wide = "t";
  for (int c = 0; c < 3000; ++c) wide.append(",c").append(std::to_string(c));
  wide += '\n';
  for (int r = 0; r < 12; ++r) {
    wide += std::to_string(r * 0.01);
    for (int c = 0; c < 3000; ++c) wide.append(",").append(std::to_string((r * 31 + c * 7) % 13));
    wide += '\n';
  }
  return {
      {"invalid_utf8_name.csv", "t,g\xe9x\n0,1\n" + rows2, false},
      {"invalid_utf8_names.csv", "t,g\xe9x,\xff\xfe\n0,1,2\n" + rows3, false},
      {"invalid_utf8_value.csv", "t,gx\n0,1\n0.01,\xe9\n" + rows2, false},
      {"nan_value.csv", "t,gx\n0,1\n" + ok + "0.09,nan\n0.10,1.5\n", false},
      {"inf_value.csv", "t,gx\n0,1\n" + ok + "0.09,-inf\n0.10,1.5\n", false},
      {"overflow_value.csv", "t,gx\n0,1\n" + ok + "0.09,1e400\n0.10,1.5\n", false},
      {"huge_values.csv", "t,gx\n0,1e308\n0.01,-1e308\n0.02,1e308\n0.03,-1e308\n0.04,1e308\n0.05,-1e308\n", false},
      {"subnormal_values.csv", "t,gx\n0,1e-310\n0.01,3e-310\n0.02,2e-310\n0.03,5e-310\n0.04,1e-311\n0.05,4e-310\n",
       false},
      {"constant.csv", "t,gx\n0,5\n0.01,5\n0.02,5\n0.03,5\n0.04,5\n0.05,5\n0.06,5\n0.07,5\n", false},
      {"time_backwards.csv", "t,gx\n0,1\n0.01,2\n0.02,1.5\n0.01,1.7\n0.03,1.6\n0.04,1.9\n", false},
      {"time_backwards_with_rate.csv", "t,gx\n0,1\n0.01,2\n0.02,1.5\n0.01,1.7\n0.03,1.6\n0.04,1.9\n", true},
      {"time_repeated.csv", "t,gx\n0,1\n0,2\n0,1.5\n0,1.7\n0,1.6\n", false},
      {"time_jump.csv", "t,gx\n0,1\n0.01,2\n1e15,1.5\n1e15,1.7\n", false},
      {"time_tiny_step.csv", "t,gx\n0,1\n1e-300,2\n2e-300,1.5\n3e-300,1.7\n4e-300,1.6\n", false},
      {"time_nan.csv", "t,gx\n0,1\nnan,2\n0.02,1.5\n0.03,1.7\n", false},
      {"one_row.csv", "t,gx\n0,1\n", false},
      {"two_rows.csv", "t,gx\n0,1\n0.01,2\n", false},
      {"header_only.csv", "t,gx,gy\n", false},
      {"empty.csv", "", true},
      {"bom_only.csv", "\xef\xbb\xbf", true},
      {"blank_lines.csv", "\n\n\n\n", true},
      {"carriage_returns.csv", "t,gx\r0,1\r0.01,2\r0.02,3\r", false},
      {"nul_bytes.csv", std::string("t,gx\n0,1\n0.01,2\0\0\n0.02,3\n", 24), false},
      {"ragged.csv", "t,gx,gy\n0,1,2\n0.01,2\n0.02,1,2,3\n0.03,1,2\n", false},
      {"quoted.csv", "\"t\",\"gx\"\n\"0\",\"1\"\n\"0.01\",\"2,5\"\n", false},
      {"hex_floats.csv", "t,gx\n0,0x1p3\n0.01,0x1p4\n0.02,0x1.8p3\n", false},
      {"long_line.csv", "t,gx\n0," + std::string(200000, '9') + "\n0.01,2\n", false},
      {"wide.csv", wide, false},
      {"no_header_letters.txt", "a b c\nd e f\n", true},
      {"negative_zero.txt", "-0\n-0\n-0\n-0\n-0\n-0\n-0\n-0\n", true},
  };
}

// Copies of `seed` cut short and with bytes changed (seeded): the mutants
// keep the seed's extension, so each is read by the seed's reader.
std::vector<std::pair<std::string, std::string>> mutants(const std::string& bytes, unsigned seed) {
  std::vector<std::pair<std::string, std::string>> out;
  if (bytes.size() < 8) return out;
  out.emplace_back("cut_third", bytes.substr(0, bytes.size() / 3));
  out.emplace_back("cut_two_thirds", bytes.substr(0, 2 * bytes.size() / 3));
  out.emplace_back("cut_last_byte", bytes.substr(0, bytes.size() - 1));
  std::mt19937 rng(seed);
  for (int k = 0; k < 3; ++k) {
    std::string m = bytes;
    std::uniform_int_distribution<std::size_t> at(0, m.size() - 1);
    std::uniform_int_distribution<int> flip(1, 255);
    for (int f = 0; f < 6; ++f) m[at(rng)] ^= static_cast<char>(flip(rng));
    out.emplace_back("flipped_" + std::to_string(k), std::move(m));
  }
  return out;
}

// The corpus, written once per test process into its own directory.
class Corpus {
 public:
  Corpus() : dir_(fs::temp_directory_path() / ("cubecal_corpus_" + std::to_string(::getpid()))) {
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "in");
    build();
  }
  ~Corpus() {
    if (std::getenv("CUBECAL_KEEP_CORPUS") == nullptr) fs::remove_all(dir_);
  }
  const std::vector<Input>& inputs() const { return inputs_; }
  const fs::path& dir() const { return dir_; }

 private:
  std::string file(const std::string& name) const { return (dir_ / "in" / name).string(); }

  // A seed file and its mutants.
  void seed(const std::string& name, const std::string& bytes, const std::vector<std::string>& args,
            bool json = false) {
    spit(file(name), bytes);
    inputs_.push_back({name, file(name), args, json});
    unsigned k = static_cast<unsigned>(inputs_.size());
    for (auto& [how, m] : mutants(bytes, k * 7919u)) {
      const std::string mname = how + "_" + name;
      spit(file(mname), m);
      inputs_.push_back({mname, file(mname), args, json});
    }
  }
  // A seed directory, and copies in which `inner` (one of its files) is mutated.
  void seed_dir(const std::string& name, const std::string& inner, const std::vector<std::string>& args) {
    const fs::path d = dir_ / "in" / name;
    inputs_.push_back({name, d.string(), args, false});
    const std::string bytes = slurp((d / inner).string());
    for (auto& [how, m] : mutants(bytes, static_cast<unsigned>(inputs_.size()) * 104729u)) {
      const fs::path copy = dir_ / "in" / (how + "_" + fs::path(inner).filename().string() + "_" + name);
      fs::copy(d, copy, fs::copy_options::recursive);
      spit((copy / inner).string(), m);
      inputs_.push_back({copy.filename().string() + " (" + inner + ")", copy.string(), args, false});
    }
  }

  void build() {
    const auto rows = gyro_rows(3000);
    const std::vector<std::string> rate{"--rate", "100"};
    seed("gyro.csv", csv(rows, true), {});
    seed("gyro_no_time.txt", csv(rows, false, 1), rate);
    seed("gyro.csv.gz", gzip(csv(rows, true)), {});
    seed("gyro.npy", npy(rows, 1, "(3000, 4)"), rate);
    seed("gyro.bin", raw_int16(rows), {"--binary", "int16le,int16le,int16le", "--rate", "100"});
    hdf5(file("gyro.h5"), rows);
    seed("gyro.h5", slurp(file("gyro.h5")), {"--dataset", "gyro", "--rate", "100"});
    for (const char* bag :
         {"ros1_bag/three_chunks.bag", "mcap/none_le_summary.mcap", "mcap/zstd_be_summary.mcap", "ulog/small.ulg"}) {
      const fs::path p = fs::path(CUBECAL_SOURCE_DIR) / "fuzz" / "corpus" / bag;
      seed(p.filename().string(), slurp(p.string()), {});
    }
    for (const char* json : {"gyro_1ch_100hz.json", "gyro_3ch_temp.json"})
      seed(json, slurp((fs::path(CUBECAL_SOURCE_DIR) / "fuzz" / "corpus" / "analysis_json" / json).string()), {}, true);
    db3(dir_ / "in" / "imu_db3", std::vector<std::vector<double>>(rows.begin(), rows.begin() + 600));
    seed_dir("imu_db3", "imu_0.db3", {});
    record(csv(std::vector<std::vector<double>>(rows.begin(), rows.begin() + 600), true));
    seed_dir("recording", "manifest.json", {});
    seed_dir("recording", "seg-001/chunk-000001.csv", {});
    for (const TextCase& c : text_cases()) {
      spit(file(c.name), c.bytes);
      inputs_.push_back({c.name, file(c.name), c.rate ? rate : std::vector<std::string>{}, false});
    }
    // A 16 kB gzip stream that inflates to 16 MB of text, 8 M samples, read
    // under a memory budget of 8 MB: streamed, or refused, within 100 MB (read
    // whole, the text and the samples alone take 80 MB). And a .npy whose
    // header claims 10^9 rows.
    std::string zeros = "gx\n";
    for (int i = 0; i < (8 << 20); ++i) zeros += "0\n";
    spit(file("inflates_16M.csv.gz"), gzip(zeros, 1));
    inputs_.push_back(
        {"inflates_16M.csv.gz", file("inflates_16M.csv.gz"), {"--rate", "100", "--memory", "8M"}, false, 100L << 10});
    spit(file("lying_shape.npy"),
         npy(std::vector<std::vector<double>>(rows.begin(), rows.begin() + 10), 1, "(1000000000, 4)"));
    inputs_.push_back({"lying_shape.npy", file("lying_shape.npy"), rate});
  }

  // A recording directory written by `cubecal record` from a file on its standard input.
  void record(const std::string& text) {
    const std::string src = file("recording_source.csv");
    spit(src, text);
    const std::string cmd = std::string(CUBECAL_BINARY) + " record - --quiet --out " + file("recording") + " < " + src +
                            " > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    ASSERT_TRUE(fs::exists(file("recording") + "/seg-001/chunk-000001.csv"));
  }

  fs::path dir_;
  std::vector<Input> inputs_;
};

const Corpus& corpus() {
  static const Corpus c;
  return c;
}

// A command over an input: its arguments, or none when it does not read this kind of input.
struct Command {
  std::string name;
  std::function<std::vector<std::string>(const Input&, const fs::path& work)> args;
  bool reads_stdin = false;  // the input is the standard input (record -)
};

std::vector<std::string> with(std::vector<std::string> head, const Input& in, std::vector<std::string> tail = {}) {
  head.push_back(in.path);
  head.insert(head.end(), in.args.begin(), in.args.end());
  head.insert(head.end(), tail.begin(), tail.end());
  return head;
}

std::vector<Command> commands() {
  auto data = [](std::vector<std::string> head, std::vector<std::string> tail = {}) {
    return [head, tail](const Input& in, const fs::path&) { return with(head, in, tail); };
  };
  return {
      {"dev", data({"dev"})},
      {"dev_stream", data({"dev"}, {"--stream"})},
      {"dev_json", data({"dev"}, {"--format", "json"})},
      {"analyze", data({"analyze"})},
      {"analyze_json", data({"analyze"}, {"--format", "json"})},
      {"psd", data({"psd"})},
      {"davar", data({"davar"})},
      {"model", data({"model"})},
      {"turnon", data({"turnon"})},
      {"compare", data({"compare"})},
      {"calibrate_temperature", data({"calibrate", "temperature"}, {"--temp-col", "temp"})},
      {"calibrate_rate_table", data({"calibrate", "rate-table"}, {"--ref-columns", "gx,gy,gz"})},
      {"calibrate_multiposition", data({"calibrate", "multiposition"})},
      {"calibrate_mag",
       [](const Input& in, const fs::path&) {
         return std::vector<std::string>{"calibrate", "mag", in.path};
       }},
      {"record",
       [](const Input&, const fs::path& work) {
         fs::remove_all(work / "rec");
         return std::vector<std::string>{"record", "-", "--quiet", "--out", (work / "rec").string()};
       },
       true},
      {"simulate",
       [](const Input& in, const fs::path& work) {
         return std::vector<std::string>{
             "simulate", "--model", in.path, "--duration", "20s", "--out", (work / "sim.csv").string(), "--force"};
       }},
      {"report",
       [](const Input& in, const fs::path& work) {
         const fs::path d = work / "report_dir";
         fs::remove_all(d);
         fs::create_directories(d);
         if (in.json) fs::copy_file(in.path, d / "analysis.json");
         return std::vector<std::string>{"report", d.string()};
       }},
  };
}

// A number printed as not finite: nan, inf, infinity as a word of its own.
bool prints_non_finite(const std::string& out) {
  static const std::regex re("(^|[^A-Za-z_])[-+]?(nan|inf|infinity)([^A-Za-z_]|$)", std::regex::icase);
  return std::regex_search(out, re);
}

bool printable_lines(const std::string& s) {
  std::istringstream in(s);
  for (std::string line; std::getline(in, line);)
    if (cubecal::printable_text(line) != line) return false;
  return true;
}

std::string last_line(const std::string& s) {
  const std::string t = s.empty() || s.back() != '\n' ? s : s.substr(0, s.size() - 1);
  const auto nl = t.rfind('\n');
  return nl == std::string::npos ? t : t.substr(nl + 1);
}

void PrintTo(const Command& c, std::ostream* os) { *os << c.name; }

class HostileCorpus : public ::testing::TestWithParam<Command> {};

TEST_P(HostileCorpus, EveryInputEndsCleanly) {
  const Command& cmd = GetParam();
  const fs::path work = corpus().dir() / ("work_" + cmd.name);
  fs::create_directories(work);
  std::size_t runs = 0;
  for (const Input& in : corpus().inputs()) {
    const bool json_command = cmd.name == "simulate" || cmd.name == "report";
    if (json_command != in.json || (cmd.reads_stdin && fs::is_directory(in.path))) continue;
    const std::vector<std::string> args = cmd.args(in, work);
    std::string shown = "cubecal";
    for (const auto& a : args) shown += " " + a;
    SCOPED_TRACE(in.name + ": " + shown);
    const Outcome r = run_limited(args, work, cmd.reads_stdin ? in.path : "/dev/null");
    ++runs;
    const std::string err = cubecal::printable_text(r.err.substr(0, 2000));
    ASSERT_FALSE(r.signaled) << "signal " << r.signal << " (" << strsignal(r.signal) << "); stderr: " << err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << err;
    EXPECT_TRUE(r.code == 0 || r.code == 2) << "exit " << r.code << "; stderr: " << err;
    EXPECT_TRUE(printable_lines(r.err)) << "unprintable bytes on stderr: " << err;
    if (r.code == 2) {
      EXPECT_EQ(last_line(r.err).rfind("cubecal: error: ", 0), 0u) << err;
    }
    if (r.code == 0) {
      EXPECT_FALSE(prints_non_finite(r.out)) << cubecal::printable_text(r.out.substr(0, 4000));
    }
    EXPECT_LT(r.peak_kib, in.peak_kib) << "peak RSS " << r.peak_kib / 1024 << " MiB; stderr: " << err;
  }
  EXPECT_GT(runs, 10u);
}

// The checks themselves: a non-finite number is seen as a word of its own.
TEST(HostileCorpusChecks, NonFiniteNumbersAreSeen) {
  EXPECT_TRUE(prints_non_finite("gx  1.5e-03  nan  2.0\n"));
  EXPECT_TRUE(prints_non_finite("N = -inf deg/sqrt(h)"));
  EXPECT_TRUE(prints_non_finite("1,Infinity,3"));
  EXPECT_FALSE(prints_non_finite("info: banana, infant, 1.5e-03\n"));
  EXPECT_FALSE(printable_lines("g\xe9x\n"));
  EXPECT_TRUE(printable_lines("cubecal: error: a.csv:1:3: bad\n"));
}

INSTANTIATE_TEST_SUITE_P(Commands, HostileCorpus, ::testing::ValuesIn(commands()),
                         [](const ::testing::TestParamInfo<Command>& p) { return p.param.name; });

}  // namespace
