// Tests of the input layer: file access (plain, gzip), the delimited-text
// reader and the uniformly sampled series built on it. Every error a user can
// meet is provoked once, with its message and location checked.
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/error.hpp"
#include "../src/io/detail/file_buffer.hpp"
#include "cubecal/io/series.hpp"

namespace fs = std::filesystem;
using namespace cubecal::io;
using cubecal::InputError;
using cubecal::UsageError;

namespace {

const std::string kData = CUBECAL_SHARED_DATA;

// A fresh directory per test, removed afterwards.
class Reader : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> counter{0};
    dir_ = fs::temp_directory_path() /
           ("cubecal_test_reader_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& content) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }

  // Appends one gzip member per piece (gzopen "ab" starts a new member).
  std::string write_gzip(const std::string& name, const std::vector<std::string>& pieces) const {
    const std::string path = (dir_ / name).string();
    for (const std::string& piece : pieces) {
      gzFile gz = gzopen(path.c_str(), "ab");
      EXPECT_NE(gz, nullptr);
      EXPECT_EQ(gzwrite(gz, piece.data(), static_cast<unsigned>(piece.size())), static_cast<int>(piece.size()));
      EXPECT_EQ(gzclose(gz), Z_OK);
    }
    return path;
  }

  std::string bytes_of(const std::string& path) const {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

  fs::path dir_;
};

// Runs `f`, which must throw InputError, and returns it.
template <class F>
InputError input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError thrown";
  return InputError("", 0, 0, "");
}

// A time column at `rate_hz` with one value column.
std::string timed_csv(const std::vector<double>& t) {
  std::string s = "t,gx\n";
  for (std::size_t i = 0; i < t.size(); ++i) {
    char line[64];
    std::snprintf(line, sizeof line, "%.4f,%zu\n", t[i], i);
    s += line;
  }
  return s;
}

std::vector<double> regular_times(std::size_t n, double period) {
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i) t[i] = static_cast<double>(i) * period;
  return t;
}

// ---------------------------------------------------------------------------
// Error messages

TEST(InputErrorFormat, OmitsWhatIsNotKnown) {
  EXPECT_STREQ(InputError("f.csv", 3, 7, "bad", "fix it").what(), "f.csv:3:7: bad (fix it)");
  EXPECT_STREQ(InputError("f.csv", 3, 0, "bad", "fix it").what(), "f.csv:3: bad (fix it)");
  EXPECT_STREQ(InputError("f.csv", 0, 0, "bad").what(), "f.csv: bad");
  EXPECT_STREQ(InputError("f.csv", 0, 5, "bad").what(), "f.csv: bad");
  const InputError e("f.csv", 2, 4, "bad", "fix it");
  EXPECT_EQ(e.file(), "f.csv");
  EXPECT_EQ(e.line(), 2u);
  EXPECT_EQ(e.column(), 4u);
  EXPECT_EQ(e.problem(), "bad");
  EXPECT_EQ(e.hint(), "fix it");
}

// ---------------------------------------------------------------------------
// Layout: delimiters, header, comments, preamble, line endings

TEST_F(Reader, EveryDelimiter) {
  struct Case {
    const char* text;
    Delimiter delimiter;
  };
  const Case cases[] = {
      {"a,b,c\n1,2,3\n4,5,6\n", Delimiter::comma},
      {"a\tb\tc\n1\t2\t3\n4\t5\t6\n", Delimiter::tab},
      {"a;b;c\n1;2;3\n4;5;6\n", Delimiter::semicolon},
      {"a b  c\n1 2  3\n4\t5 \t 6\n", Delimiter::whitespace},
  };
  for (const Case& c : cases) {
    const Table t = read_table(write("d.txt", c.text));
    SCOPED_TRACE(c.text);
    EXPECT_EQ(t.delimiter, c.delimiter);
    EXPECT_TRUE(t.has_header);
    EXPECT_EQ(t.header, (std::vector<std::string>{"a", "b", "c"}));
    EXPECT_EQ(t.total_columns, 3u);
    ASSERT_EQ(t.rows(), 2u);
    EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{1, 4}, {2, 5}, {3, 6}}));
  }
}

TEST_F(Reader, WithoutHeaderColumnsAreNumbered) {
  const Table t = read_table(write("n.csv", "1,2\n3,4\n"));
  EXPECT_FALSE(t.has_header);
  EXPECT_TRUE(t.header.empty());
  EXPECT_EQ(t.names, (std::vector<std::string>{"col1", "col2"}));
  EXPECT_EQ(t.first_data_line, 1u);
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{1, 3}, {2, 4}}));
}

TEST_F(Reader, CommentsAndBlankLinesAnywhere) {
  const Table t = read_table(write("c.csv",
                                   "# logger v2\n\n  # indented comment\nx,y\n# between\n1,2\n\n   \n"
                                   "#x,y\n3,4\n# trailing comment"));
  EXPECT_TRUE(t.has_header);
  EXPECT_EQ(t.first_data_line, 6u);
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{1, 3}, {2, 4}}));
}

TEST_F(Reader, SkipRowsDropsAPreamble) {
  const std::string text = "Fs,100\nLogging Type,0\nInitialization time,36.5\nWaiting time,3\nax,ay\n1,2\n3,4\n";
  TableOptions opt;
  opt.skip_rows = 4;
  const Table t = read_table(write("p.csv", text), opt);
  EXPECT_EQ(t.header, (std::vector<std::string>{"ax", "ay"}));
  EXPECT_EQ(t.first_data_line, 6u);
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{1, 3}, {2, 4}}));
}

TEST_F(Reader, CrlfLineEndings) {
  const Table t = read_table(write("w.csv", "a,b\r\n1,2\r\n3,4\r\n"));
  EXPECT_EQ(t.header, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{1, 3}, {2, 4}}));
}

TEST_F(Reader, SingleColumnStable32Style) {
  const Table t = read_table(write("s.dat", "# phase data\n#\n  1.5e-09\n 2.0e-09\r\n-3.25e-09\n"));
  EXPECT_FALSE(t.has_header);
  EXPECT_EQ(t.total_columns, 1u);
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{1.5e-9, 2.0e-9, -3.25e-9}}));
}

TEST_F(Reader, WhitespaceWithLeadingSpaces) {
  const Table t = read_table(write("x.txt", "   2.98e-02   3.3108e+04\n   3.98e-02   3.3096e+04   \n"));
  EXPECT_EQ(t.delimiter, Delimiter::whitespace);
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{2.98e-2, 3.98e-2}, {3.3108e4, 3.3096e4}}));
}

TEST_F(Reader, NumberForms) {
  const Table t = read_table(write("f.csv", "+1, 1e-3 ,.5,5.\n-2,+2.5E+2,-.25,0\n"));
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{1, -2}, {1e-3, 250}, {0.5, -0.25}, {5, 0}}));
}

TEST_F(Reader, ByteOrderMarkIsIgnored) {
  const Table t = read_table(write("bom.csv", "\xEF\xBB\xBFt,x\n1,2\n"));
  EXPECT_EQ(t.header, (std::vector<std::string>{"t", "x"}));
}

TEST_F(Reader, ParseTableFromMemory) {
  const Table t = parse_table("a b\n1 2\n", "mem");
  EXPECT_EQ(t.file, "mem");
  EXPECT_EQ(t.bytes, 8u);
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{1}, {2}}));
}

TEST_F(Reader, ParseLayoutReadsNoData) {
  const Table t = parse_layout("# c\nt;x;y\n1;2;3\n", "mem");
  EXPECT_EQ(t.delimiter, Delimiter::semicolon);
  EXPECT_EQ(t.header, (std::vector<std::string>{"t", "x", "y"}));
  EXPECT_EQ(t.total_columns, 3u);
  EXPECT_EQ(t.first_data_line, 3u);
  EXPECT_TRUE(t.data.empty());
}

// ---------------------------------------------------------------------------
// Column selection

TEST_F(Reader, SelectByNameIndexAndIgnoringCase) {
  const std::string path = write("sel.csv", "t,gx,gy,GZ\n0,1,2,3\n1,4,5,6\n");
  TableOptions opt;
  opt.columns = {"gy", "2", "gz"};
  opt.extra_columns = {"T"};
  const Table t = read_table(path, opt);
  EXPECT_EQ(t.names, (std::vector<std::string>{"gy", "gx", "GZ"}));
  EXPECT_EQ(t.indices, (std::vector<std::size_t>{2, 1, 3}));
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{2, 5}, {1, 4}, {3, 6}}));
  EXPECT_EQ(t.extra_names, (std::vector<std::string>{"t"}));
  EXPECT_EQ(t.extra_indices, (std::vector<std::size_t>{0}));
  EXPECT_EQ(t.extra, (std::vector<std::vector<double>>{{0, 1}}));
}

TEST_F(Reader, AllColumnsExceptTheExtraOnes) {
  TableOptions opt;
  opt.extra_columns = {"t"};
  const Table t = read_table(write("all.csv", "t,a,b\n0,1,2\n"), opt);
  EXPECT_EQ(t.names, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(t.extra, (std::vector<std::vector<double>>{{0}}));
}

TEST_F(Reader, ColumnSelectedTwiceIsCopied) {
  TableOptions opt;
  opt.columns = {"2", "b"};
  opt.extra_columns = {"b"};
  const Table t = read_table(write("dup.csv", "a,b\n1,2\n3,4\n"), opt);
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{2, 4}, {2, 4}}));
  EXPECT_EQ(t.extra, (std::vector<std::vector<double>>{{2, 4}}));
}

TEST_F(Reader, UnselectedFieldsAreNotConverted) {
  TableOptions opt;
  opt.columns = {"1"};
  const Table t = read_table(write("skip.csv", "x,label\n1,note\n2,other\n"), opt);
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{1, 2}}));
}

// ---------------------------------------------------------------------------
// gzip

TEST_F(Reader, GzipRoundTripDetectedByMagicBytes) {
  const std::string text = "t,x\n0,1.5\n1,2.5\n";
  const std::string path = write_gzip("data.bin", {text});
  const FileBuffer buf = FileBuffer::open(path);
  EXPECT_TRUE(buf.was_gzip());
  EXPECT_EQ(buf.view(), text);
  const Table t = read_table(path);
  EXPECT_EQ(t.bytes, text.size());
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{0, 1}, {1.5, 2.5}}));
}

TEST_F(Reader, MultiMemberGzip) {
  const std::string path = write_gzip("multi.csv.gz", {"a,b\n1,2\n", "3,4\n", "5,6\n"});
  const Table t = read_table(path);
  EXPECT_EQ(t.data, (std::vector<std::vector<double>>{{1, 3, 5}, {2, 4, 6}}));
}

TEST_F(Reader, PlainFileIsNotGzip) {
  const FileBuffer buf = FileBuffer::open(write("plain.csv.gz", "1\n"));
  EXPECT_FALSE(buf.was_gzip());
  EXPECT_EQ(buf.view(), "1\n");
}

// ---------------------------------------------------------------------------
// Parallel parsing: several chunks give the same result as one.

std::string big_text(std::size_t rows) {
  std::string s = "t,a,b\n";
  for (std::size_t i = 0; i < rows; ++i) {
    s += std::to_string(i) + "," + std::to_string(static_cast<double>(i) * 0.5) + ",-" + std::to_string(i % 97) + "\n";
    if (i % 1000 == 999) s += "# comment inside the data\n\n";
  }
  return s;
}

TEST_F(Reader, ChunksAgreeWithSingleThread) {
  const std::string text = big_text(300000);  // several MB: more than one chunk
  TableOptions one;
  one.threads = 1;
  TableOptions many;
  many.threads = 4;
  const Table a = parse_table(text, "mem", one);
  const Table b = parse_table(text, "mem", many);
  ASSERT_EQ(a.rows(), 300000u);
  EXPECT_EQ(a.data, b.data);
  EXPECT_EQ(b.data[1][123456], 61728.0);
}

TEST_F(Reader, ErrorInALaterChunkHasItsLineNumber) {
  std::string text = big_text(300000);
  const std::string bad = "\n299998,";
  const std::size_t pos = text.find(bad) + bad.size();
  text.replace(pos, 1, "x");  // "149999" -> "x49999"
  const std::size_t line =
      1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(pos), '\n'));
  for (unsigned threads : {1u, 2u, 4u}) {
    TableOptions opt;
    opt.threads = threads;
    const InputError e = input_error([&] { parse_table(text, "mem", opt); });
    EXPECT_EQ(e.line(), line) << threads;
    EXPECT_EQ(e.column(), 8u);
  }
}

TEST_F(Reader, EarliestErrorWinsAcrossChunks) {
  std::string text = big_text(300000);
  text.replace(text.find("\n5,") + 3, 1, "?");
  text.replace(text.find("\n299990,") + 8, 1, "?");
  TableOptions opt;
  opt.threads = 4;
  const InputError e = input_error([&] { parse_table(text, "mem", opt); });
  EXPECT_EQ(e.line(), 7u);
}

// A mapped file is parsed a window at a time and its pages dropped behind
// the parse: the columns, and an error's place found by reading the text
// again, are those of the same text parsed from memory.
TEST_F(Reader, FileParsedInWindowsEqualsTheTextInMemory) {
  const std::string text = big_text(600000);  // ~13 MB: several windows per thread
  const std::string path = write("big.csv", text);
  for (unsigned threads : {1u, 2u}) {
    TableOptions opt;
    opt.threads = threads;
    const Table from_file = read_table(path, opt);
    const Table from_memory = parse_table(text, "mem", opt);
    ASSERT_EQ(from_file.rows(), 600000u);
    EXPECT_EQ(from_file.data, from_memory.data) << threads;
  }
  std::string bad = text;
  const std::size_t pos = bad.find("\n599000,") + 8;
  bad[pos] = 'x';
  const std::string bad_path = write("bad.csv", bad);
  const std::size_t line =
      1 + static_cast<std::size_t>(std::count(bad.begin(), bad.begin() + static_cast<std::ptrdiff_t>(pos), '\n'));
  const InputError e = input_error([&] { read_table(bad_path); });
  EXPECT_EQ(e.line(), line);
  EXPECT_EQ(e.column(), 8u);
}

TEST_F(Reader, ReleasedPagesReadTheSameBytesAgain) {
  const std::string text = big_text(200000);
  const FileBuffer buf = FileBuffer::open(write("pages.csv", text));
  const std::string_view v = buf.view();
  buf.populate(v);
  buf.release(v.substr(1000, 3 << 20));
  EXPECT_EQ(std::string(v), text);
  buf.release(v);
  EXPECT_EQ(std::string(v), text);
}

// ---------------------------------------------------------------------------
// locate()

TEST_F(Reader, LocateFindsLineAndColumn) {
  const std::string path = write("loc.csv", "# c\nt, x\n0, 1\n# mid\n\n1,   2\n");
  const Table t = read_table(path);
  const Location a = locate(t, 1, 1);
  EXPECT_EQ(a.line, 6u);
  EXPECT_EQ(a.column, 6u);
  const Location b = locate(t, 0, 0);
  EXPECT_EQ(b.line, 3u);
  EXPECT_EQ(b.column, 1u);
}

// ---------------------------------------------------------------------------
// Data errors: message and FILE:LINE:COL

TEST_F(Reader, NonNumericFieldPointsAtTheField) {
  const std::string path = write("bad.csv", "t,gx,gz\n0,1,2\n1,2,abc\n");
  const InputError e = input_error([&] { read_table(path); });
  EXPECT_EQ(std::string(e.what()), path +
                                       ":3:5: non-numeric field 'abc' in column 3 'gz' "
                                       "(fix the row, remove it or comment it out with '#')");
}

TEST_F(Reader, TrailingGarbageIsNonNumeric) {
  const std::string path = write("g.csv", "1,2,3\n1, 1.2x ,3\n");
  const InputError e = input_error([&] { read_table(path); });
  EXPECT_EQ(e.line(), 2u);
  EXPECT_EQ(e.column(), 4u);
  EXPECT_EQ(e.problem(), "non-numeric field '1.2x' in column 2");
}

TEST_F(Reader, ColumnsCountCharactersNotBytes) {
  const std::string path = write("u.csv", "\xC2\xB5x,y\n1,\xC2\xB5\n");
  const InputError e = input_error([&] { read_table(path); });
  EXPECT_EQ(e.line(), 2u);
  EXPECT_EQ(e.column(), 3u);
}

TEST_F(Reader, DecimalCommaGetsAHint) {
  const InputError e = input_error([&] { parse_table("a;b\n1,5;2\n", "mem"); });
  EXPECT_EQ(e.problem(), "non-numeric field '1,5' in column 1 'a'");
  EXPECT_EQ(e.hint(), "decimal commas are not accepted; write numbers with a '.'");
}

TEST_F(Reader, WrongFieldCount) {
  const std::string path = write("fc.csv", "a,b,c,d,e,f,g,h\n1,2,3,4,5,6,7,8\n1,2,3,4,5\n");
  const InputError e = input_error([&] { read_table(path); });
  EXPECT_EQ(std::string(e.what()), path + ":3:10: row has 5 fields, expected 8 (header has 8)");

  const InputError more = input_error([&] { parse_table("1 2\n3 4 5\n", "mem"); });
  EXPECT_EQ(std::string(more.what()), "mem:2:5: row has 3 fields, expected 2 (the first data row, line 1, has 2)");
}

TEST_F(Reader, NaNIsRejected) {
  const std::string path = write("nan.csv", "t,gx\n0,1\n1,nan\n");
  const InputError e = input_error([&] { read_table(path); });
  EXPECT_EQ(e.text(), path +
                          ":3:3: NaN is not accepted in column 2 'gx' (a missing sample: {gaps} "
                          "skip leaves it out of the OADEV terms (dev, davar); otherwise remove the "
                          "row or split the record there)");
  EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
}

TEST_F(Reader, InfinityIsRejected) {
  const InputError e = input_error([&] { parse_table("t,gx\n0,-inf\n", "mem"); });
  EXPECT_EQ(e.problem(), "infinite value '-inf' in column 2 'gx'");
  EXPECT_EQ(e.column(), 3u);
}

TEST_F(Reader, OutOfRangeIsRejected) {
  const InputError e = input_error([&] { parse_table("x\n1e999\n", "mem"); });
  EXPECT_EQ(e.problem(), "value '1e999' out of range in column 1 'x'");
}

TEST_F(Reader, EmptyFieldIsRejected) {
  const std::string path = write("empty_field.csv", "t,gx,gy\n0,1,2\n1,,2\n");
  const InputError e = input_error([&] { read_table(path); });
  EXPECT_EQ(e.text(), path +
                          ":3:3: empty field in column 2 'gx' (a missing sample: {gaps} skip "
                          "leaves it out of the OADEV terms (dev, davar); otherwise fill or remove "
                          "the row)");
  EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
}

TEST_F(Reader, EmptyFile) {
  const std::string path = write("empty.csv", "");
  const InputError e = input_error([&] { read_table(path); });
  EXPECT_EQ(e.line(), 0u);
  EXPECT_EQ(e.problem(), "no data rows: the file is empty");
}

TEST_F(Reader, OnlyCommentsOrHeader) {
  EXPECT_EQ(input_error([&] { parse_table("# nothing\n\n", "mem"); }).problem(),
            "no data rows: only comments and blank lines");
  EXPECT_EQ(input_error([&] { parse_table("t,x\n# none\n", "mem"); }).problem(),
            "no data rows: nothing after the header on line 1");
  TableOptions opt;
  opt.skip_rows = 5;
  EXPECT_EQ(input_error([&] { parse_table("a\nb\n", "mem", opt); }).problem(),
            "no data rows: the file has 2 lines and 5 are skipped");
}

TEST_F(Reader, UnknownColumnName) {
  const std::string path = write("cols.csv", "# c\nt,gx,gy,gz\n0,1,2,3\n");
  TableOptions opt;
  opt.columns = {"gx", "gq"};
  const InputError e = input_error([&] { read_table(path, opt); });
  EXPECT_EQ(std::string(e.what()), path + ":2:1: unknown column 'gq' (columns are: t, gx, gy, gz)");
}

TEST_F(Reader, ColumnIndexOutOfRange) {
  TableOptions opt;
  opt.columns = {"5"};
  const InputError e = input_error([&] { parse_table("a,b\n1,2\n", "mem", opt); });
  EXPECT_EQ(std::string(e.what()), "mem:1:1: column index 5 out of range (the file has 2 columns; use 1 to 2)");
}

TEST_F(Reader, NameWithoutHeader) {
  TableOptions opt;
  opt.columns = {"gx"};
  const InputError e = input_error([&] { parse_table("1,2\n", "mem", opt); });
  EXPECT_EQ(e.problem(), "column 'gx' given by name but the file has no header line");
  EXPECT_EQ(e.hint(), "use 1-based column indices, 1 to 2");
}

TEST_F(Reader, MissingFile) {
  const std::string path = (dir_ / "nope.csv").string();
  const InputError e = input_error([&] { read_table(path); });
  EXPECT_EQ(std::string(e.what()), path + ": cannot open file: No such file or directory");
}

TEST_F(Reader, DirectoryIsNotAFile) {
  const InputError e = input_error([&] { read_table(dir_.string()); });
  EXPECT_EQ(e.problem(), "cannot open file: Is a directory");
}

TEST_F(Reader, TruncatedGzip) {
  const std::string full = write_gzip("full.gz", {big_text(2000)});
  const std::string bytes = bytes_of(full);
  const std::string path = write("cut.gz", bytes.substr(0, bytes.size() - 20));
  const InputError e = input_error([&] { read_table(path); });
  EXPECT_EQ(e.line(), 0u);
  EXPECT_EQ(e.problem().rfind("truncated gzip stream", 0), 0u) << e.what();
  EXPECT_EQ(e.hint(), "the file is incomplete; copy or download it again");
}

TEST_F(Reader, CorruptGzip) {
  std::string bytes = bytes_of(write_gzip("ok.gz", {big_text(2000)}));
  for (std::size_t i = 100; i < 140; ++i) bytes[i] = static_cast<char>(bytes[i] ^ 0x5a);
  const std::string path = write("bad.gz", bytes);
  const InputError e = input_error([&] { read_table(path); });
  EXPECT_EQ(e.problem().rfind("corrupt gzip data at byte offset ", 0), 0u) << e.what();
}

// ---------------------------------------------------------------------------
// Series

TEST_F(Reader, SeriesInfersRateFromAutoDetectedTimeColumn) {
  const std::string path = write("s.csv", timed_csv(regular_times(50, 0.1)));
  const Series s = read_series(path, {});
  EXPECT_EQ(s.time_name, "t");
  EXPECT_TRUE(s.rate_from_time);
  EXPECT_NEAR(s.rate_hz, 10.0, 1e-9);
  EXPECT_NEAR(s.tau0, 0.1, 1e-12);
  EXPECT_EQ(s.names, (std::vector<std::string>{"gx"}));  // time column is not a channel
  ASSERT_EQ(s.samples(), 50u);
  EXPECT_EQ(s.time.size(), 50u);
  ASSERT_EQ(s.segments.size(), 1u);
  EXPECT_EQ(s.segments[0].size(), 50u);
  EXPECT_EQ(s.irregular_intervals, 0u);
  EXPECT_FALSE(s.gzip);
  EXPECT_EQ(s.bytes, fs::file_size(path));
}

TEST(TimeColumnNames, Recognised) {
  for (const char* n : {"t", "T", "time", "Time", "t_s", "TIME_S", "timestamp", "sec", "Seconds"}) {
    EXPECT_TRUE(looks_like_time_column(n)) << n;
  }
  for (const char* n : {"gx", "temp", "", "times", "t_ms"}) EXPECT_FALSE(looks_like_time_column(n)) << n;
}

TEST_F(Reader, SeriesWithGivenRateAndNoTimeColumn) {
  SeriesOptions opt;
  opt.rate_hz = 200;
  opt.lsb = {4};
  const Series s = read_series(write("r.txt", "8 2\n4 6\n0 -2\n"), opt);
  EXPECT_EQ(s.rate_hz, 200.0);
  EXPECT_EQ(s.tau0, 0.005);
  EXPECT_FALSE(s.rate_from_time);
  EXPECT_TRUE(s.time.empty());
  EXPECT_EQ(s.names, (std::vector<std::string>{"col1", "col2"}));
  EXPECT_EQ(s.channels, (std::vector<std::vector<double>>{{2, 1, 0}, {0.5, 1.5, -0.5}}));
}

TEST_F(Reader, GivenRateIgnoresAnAutoDetectedTimeColumn) {
  std::vector<double> t = regular_times(10, 0.1);
  t[5] += 0.05;  // jitter that must not matter when the rate is given
  SeriesOptions opt;
  opt.rate_hz = 10;
  const Series s = read_series(write("j.csv", timed_csv(t)), opt);
  EXPECT_TRUE(s.time_name.empty());
  EXPECT_EQ(s.names, (std::vector<std::string>{"gx"}));
}

TEST_F(Reader, ExplicitTimeColumnByIndexIsCheckedAgainstGivenRate) {
  SeriesOptions opt;
  opt.time_col = "2";
  opt.rate_hz = 2;
  opt.table.columns = {"1"};
  const Series s = read_series(write("e.csv", "7 0\n8 0.5\n9 1.0\n"), opt);
  EXPECT_EQ(s.time_name, "col2");
  EXPECT_FALSE(s.rate_from_time);
  EXPECT_EQ(s.channels, (std::vector<std::vector<double>>{{7, 8, 9}}));

  opt.rate_hz = 4;
  const InputError e = input_error([&] { read_series(write("e2.csv", "7 0\n8 0.5\n9 1.0\n"), opt); });
  EXPECT_EQ(e.problem(), "gap of 0.5000 s (2 periods of 0.25 s) after t = 0 s");
  EXPECT_EQ(e.line(), 2u);
  EXPECT_EQ(e.column(), 3u);
}

TEST_F(Reader, LsbScalesChannels) {
  SeriesOptions opt;
  opt.lsb = {0.05};
  const Series s = read_series(write("l.csv", "t,g\n0,1\n0.5,-2\n1,4\n"), opt);
  EXPECT_EQ(s.channels[0], (std::vector<double>{1 / 0.05, -2 / 0.05, 4 / 0.05}));
  EXPECT_EQ(s.time, (std::vector<double>{0, 0.5, 1}));
}

// A raw 6-axis log: gyro and accelerometer columns with their own scales.
TEST_F(Reader, LsbPerColumnScalesEachChannel) {
  SeriesOptions opt;
  opt.rate_hz = 100;
  opt.lsb = {131, 16384};
  const Series s = read_series(write("p.csv", "gx,az\n262,16384\n-131,8192\n0,-32768\n"), opt);
  EXPECT_EQ(s.channels, (std::vector<std::vector<double>>{{2, -1, 0}, {1, 0.5, -2}}));
  // Named columns take the LSBs in the order named.
  opt.table.columns = {"az", "gx"};
  opt.lsb = {16384, 131};
  const Series n = read_series(write("p2.csv", "gx,az\n262,16384\n-131,8192\n0,-32768\n"), opt);
  EXPECT_EQ(n.channels, (std::vector<std::vector<double>>{{1, 0.5, -2}, {2, -1, 0}}));
}

TEST_F(Reader, LsbCountMustMatchTheColumns) {
  SeriesOptions opt;
  opt.rate_hz = 100;
  opt.lsb = {131, 131, 16384};
  const std::string path = write("c.csv", "gx,az\n262,16384\n-131,8192\n0,-32768\n");
  for (const bool named : {false, true}) {
    opt.table.columns = named ? std::vector<std::string>{"gx", "az"} : std::vector<std::string>{};
    try {
      read_series(path, opt);
      ADD_FAILURE() << "no error";
    } catch (const UsageError& e) {
      EXPECT_EQ(e.field(), cubecal::Field::counts_per_unit);
      EXPECT_EQ(std::string(e.what()),
                path + ": 3 LSB values for 2 columns (gx,az): give one value for every column, or one per column");
    }
  }
}

TEST_F(Reader, BadOptionsAreUsageErrors) {
  const std::string path = write("o.csv", timed_csv(regular_times(5, 1)));
  for (double lsb : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    SeriesOptions opt;
    opt.lsb = {lsb};
    EXPECT_THROW(read_series(path, opt), UsageError) << lsb;
  }
  SeriesOptions neg;
  neg.rate_hz = -5;
  EXPECT_THROW(read_series(path, neg), UsageError);
}

TEST(ReaderHints, PreambleNotSkippedSuggestsTheRightSkipRows) {
  // The MPU-6050 logger's preamble: "Fs,100" is taken for the first data row.
  const auto hint_of = [](const std::string& text, std::size_t skip = 0) {
    TableOptions o;
    o.skip_rows = skip;
    try {
      parse_table(text, "log.csv", o);
    } catch (const InputError& e) {
      return e.hint();
    }
    return std::string("no error");
  };
  const std::string mpu = "Fs,100\nLogging Type,1\nInitialization time,-1\nWaiting time,-1\nax,ay,az\n1,2,3\n4,5,6\n";
  EXPECT_EQ(hint_of(mpu), "the table seems to start on line 5 after a preamble: add {skip_rows} 4");
  // Too few lines skipped: N still counts from the top of the file.
  EXPECT_EQ(hint_of(mpu, 2), "the table seems to start on line 5 after a preamble: add {skip_rows} 4");
  // A preamble line taken for the header: a field-count fault.
  EXPECT_EQ(hint_of("logger,v2,x\nt,gx\n0,1\n0.1,2\n"),
            "the table seems to start on line 2 after a preamble: add {skip_rows} 1");
  // A bad value further down is no preamble.
  EXPECT_EQ(hint_of("t,gx\n0,1\n0.1,x\n0.2,3\n"), "fix the row, remove it or comment it out with '#'");
}

TEST_F(Reader, NoRateAndNoTimeColumnIsAUsageError) {
  const std::string path = write("nr.csv", "a,b\n1,2\n3,4\n5,6\n");
  try {
    read_series(path, {});
    FAIL() << "no UsageError";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.text(), path +
                            ": no sampling rate: no column is named as a time column (t, time, t_s, "
                            "timestamp...): give {rate} HZ or {time_col} NAME");
  }
}

TEST_F(Reader, NonMonotonicTimeStamp) {
  const std::string path = write("nm.csv", "t,gx\n12.2,0\n12.4,1\n12.3,2\n12.5,3\n");
  const InputError e = input_error([&] { read_series(path, {}); });
  EXPECT_EQ(std::string(e.what()), path +
                                       ":4:1: time stamp 12.3 s is not after the previous one 12.4 s "
                                       "(sort the file or fix the logger clock)");
}

TEST_F(Reader, DuplicatedTimeStamp) {
  const std::string path = write("dt.csv", "gx, time\n0, 1.0\n1, 2.0\n2, 2.0\n");
  const InputError e = input_error([&] { read_series(path, {}); });
  EXPECT_EQ(std::string(e.what()), path +
                                       ":4:4: time stamp 2 s is not after the previous one 2 s "
                                       "(duplicated time stamp: remove the repeated row or fix the logger clock)");
}

TEST_F(Reader, GapIsAnErrorByDefault) {
  std::vector<double> t = regular_times(20, 0.1);
  for (std::size_t i = 10; i < t.size(); ++i) t[i] += 2.9;  // 29 missing samples
  const std::string path = write("gap.csv", timed_csv(t));
  const InputError e = input_error([&] { read_series(path, {}); });
  EXPECT_EQ(e.text(), path +
                          ":12:1: gap of 3.000 s (30 periods of 0.1 s) after t = 0.9 s "
                          "(use {gaps} split to analyze the contiguous pieces)");
}

TEST_F(Reader, GapSplitsIntoSegments) {
  std::vector<double> t = regular_times(20, 0.1);
  for (std::size_t i = 10; i < t.size(); ++i) t[i] += 2.9;
  SeriesOptions opt;
  opt.gaps = GapPolicy::split;
  const Series s = read_series(write("gap.csv", timed_csv(t)), opt);
  ASSERT_EQ(s.segments.size(), 2u);
  EXPECT_EQ(s.segments[0].begin, 0u);
  EXPECT_EQ(s.segments[0].end, 10u);
  EXPECT_EQ(s.segments[1].begin, 10u);
  EXPECT_EQ(s.segments[1].end, 20u);
  EXPECT_EQ(s.irregular_intervals, 1u);
  EXPECT_NEAR(s.rate_hz, 10.0, 1e-9);
  EXPECT_EQ(s.samples(), 20u);
}

TEST_F(Reader, JitterBeyondTolerance) {
  std::vector<double> t = regular_times(20, 0.1);
  t[7] += 0.0043;
  const std::string path = write("jit.csv", timed_csv(t));
  const InputError e = input_error([&] { read_series(path, {}); });
  EXPECT_EQ(e.line(), 9u);
  EXPECT_EQ(e.column(), 1u);
  EXPECT_EQ(e.problem(), "jitter: interval 0.1043 s differs from the period 0.1 s by 4.3 %");
  EXPECT_EQ(e.hint(),
            "use {gaps} split to cut the record at irregular intervals, "
            "or give {rate} HZ to ignore the time stamps");

  SeriesOptions loose;
  loose.tolerance = 0.05;
  EXPECT_EQ(read_series(path, loose).segments.size(), 1u);
}

TEST_F(Reader, JitterWithinToleranceIsAccepted) {
  std::vector<double> t = regular_times(20, 0.1);
  t[7] += 0.0009;
  EXPECT_EQ(read_series(write("ok.csv", timed_csv(t)), {}).segments.size(), 1u);
}

TEST_F(Reader, SeriesOfEmptyFile) {
  const std::string path = write("e.csv", "");
  SeriesOptions opt;
  opt.rate_hz = 1;
  const InputError e = input_error([&] { read_series(path, opt); });
  EXPECT_EQ(e.line(), 0u);
  EXPECT_EQ(e.problem().rfind("no data rows", 0), 0u);
}

TEST_F(Reader, TooShortSeries) {
  SeriesOptions opt;
  opt.min_samples = 10;
  const std::string path = write("short.csv", timed_csv(regular_times(5, 1)));
  const InputError e = input_error([&] { read_series(path, opt); });
  EXPECT_EQ(std::string(e.what()),
            path + ": series too short: 5 samples, at least 10 needed (a longer record is needed)");
}

TEST_F(Reader, TooShortAfterSplitting) {
  std::vector<double> t = regular_times(12, 1);
  for (std::size_t i = 6; i < t.size(); ++i) t[i] += 10;
  SeriesOptions opt;
  opt.gaps = GapPolicy::split;
  opt.min_samples = 8;
  const InputError e = input_error([&] { read_series(write("split_short.csv", timed_csv(t)), opt); });
  EXPECT_EQ(e.problem(), "series too short: 6 samples, at least 8 needed");
}

TEST_F(Reader, OnlyTimeColumn) {
  const InputError e = input_error([&] { read_series(write("t.csv", "t\n0\n1\n2\n"), {}); });
  EXPECT_EQ(e.problem(), "no data columns besides the time column");
}

TEST_F(Reader, GzipSeries) {
  const std::string text = timed_csv(regular_times(30, 0.01));
  const Series s = read_series(write_gzip("s.csv.gz", {text}), {});
  EXPECT_TRUE(s.gzip);
  EXPECT_EQ(s.bytes, text.size());
  EXPECT_NEAR(s.rate_hz, 100.0, 1e-6);
}

TEST_F(Reader, TimeErrorInGzipFileIsLocated) {
  const std::string path = write_gzip("nm.csv.gz", {"t,x\n0,0\n1,0\n0.5,0\n"});
  const InputError e = input_error([&] { read_series(path, {}); });
  EXPECT_EQ(e.line(), 4u);
  EXPECT_EQ(e.column(), 1u);
}

// ---------------------------------------------------------------------------
// Reference data

TEST(RealFiles, Stable32PhaseDat) {
  const Table t = read_table(kData + "/stable32/phasedat/PHASE.DAT");
  ASSERT_EQ(t.rows(), 1001u);
  EXPECT_EQ(t.data.size(), 1u);
  EXPECT_EQ(t.data[0][0], 0.0);
  EXPECT_EQ(t.data[0][1], 8.511601033439709e-02);
  EXPECT_EQ(t.data[0][1000], 9.908740494779522e-14);
}

TEST(RealFiles, PinkFrequency) {
  const Table t = read_table(kData + "/stable32/pink_frequency/pink_frequency.txt");
  ASSERT_EQ(t.rows(), 10000u);
  EXPECT_EQ(t.data[0][0], 1.62551e-07);
}

TEST(RealFiles, Adis16405GzipSeries) {
  const Series s = read_series(kData + "/imu/adis16405/run1.csv.gz", {});
  EXPECT_TRUE(s.gzip);
  EXPECT_EQ(s.samples(), 1000000u);
  EXPECT_EQ(s.time_name, "t_s");
  EXPECT_TRUE(s.rate_from_time);
  EXPECT_NEAR(s.rate_hz, 100.0, 1e-6);
  EXPECT_EQ(s.segments.size(), 1u);
  EXPECT_EQ(s.names,
            (std::vector<std::string>{"gyro_x_dps", "gyro_y_dps", "gyro_z_dps", "acc_x_g", "acc_y_g", "acc_z_g"}));
  EXPECT_EQ(s.channels[0][1], 0.35);
  EXPECT_EQ(s.channels[5][999999], -1.01898);
}

TEST(RealFiles, Mpu6050WithPreamble) {
  TableOptions opt;
  opt.skip_rows = 4;
  const Table t = read_table(kData + "/imu/mpu6050/example_data_calibration.csv", opt);
  EXPECT_EQ(t.header, (std::vector<std::string>{"ax", "ay", "az", "gx", "gy", "gz"}));
  EXPECT_EQ(t.first_data_line, 6u);
  ASSERT_EQ(t.rows(), 10245u);
  EXPECT_EQ(t.data[0][0], -12.0);
  EXPECT_EQ(t.data[5][10244], -81.0);
}

TEST(RealFiles, Mpu6050WithoutSkipRowsPointsAtThePreamble) {
  const InputError e = input_error([] { read_table(kData + "/imu/mpu6050/example_data_calibration.csv"); });
  EXPECT_EQ(e.line(), 1u);  // "Fs,100": a word and a number, so data, not a header
  EXPECT_EQ(e.column(), 1u);
  EXPECT_NE(e.hint().find("{skip_rows}"), std::string::npos);
}

TEST(RealFiles, XsensWhitespace) {
  TableOptions opt;
  opt.columns = {"1", "4"};
  const Table t = read_table(kData + "/imu/xsens-multiposition/xsens_gyro.txt", opt);
  EXPECT_EQ(t.delimiter, Delimiter::whitespace);
  EXPECT_EQ(t.total_columns, 4u);
  EXPECT_EQ(t.data[0][0], 2.984e-2);
  EXPECT_EQ(t.data[1][0], 3.2499e4);
}

}  // namespace
