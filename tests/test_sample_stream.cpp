// The chunked sample source against read_series on the same record (column
// by column, bit for bit), its errors at the same FILE:LINE as read_series
// where a piece boundary lies before them, and the simulator's blocks
// against its whole-array record.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/sample_stream.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/simulate.hpp"
#include "cubecal/sim/presets.hpp"
#include "white_plus_walk.hpp"

namespace cubecal {
namespace {

using test::TempDirTest;

// Every piece of `s` concatenated.
io::SampleChunk drain(io::SampleStream& s, std::size_t* pieces = nullptr) {
  io::SampleChunk all, piece;
  std::size_t n = 0;
  while (s.next(piece)) {
    ++n;
    all.channels.resize(piece.channels.size());
    all.extra.resize(piece.extra.size());
    for (std::size_t c = 0; c < piece.channels.size(); ++c)
      all.channels[c].insert(all.channels[c].end(), piece.channels[c].begin(), piece.channels[c].end());
    for (std::size_t c = 0; c < piece.extra.size(); ++c)
      all.extra[c].insert(all.extra[c].end(), piece.extra[c].begin(), piece.extra[c].end());
  }
  if (pieces) *pieces = n;
  return all;
}

class SampleStreamTest : public TempDirTest {
 protected:
  // A text record: a comment, a header, time, three channels and a
  // temperature; a comment line in the middle.
  std::string text_record(std::size_t rows) {
    const auto a = test::white_plus_walk(rows, 0.01, 0.3, 0.01, 7, 12.0);
    const auto b = test::white_plus_walk(rows, 0.01, 1.5, 0.02, 8, -3.0);
    std::string t = "# logger v2\nt,gx,gy,temp\n";
    for (std::size_t i = 0; i < rows; ++i) {
      if (i == rows / 2) t += "# resync\n";
      t += std::to_string(i) + "e-2," + std::to_string(a[i]) + "," + std::to_string(b[i]) + "," +
           std::to_string(25.0 + 1e-4 * static_cast<double>(i)) + "\n";
    }
    return t;
  }
};

TEST_F(SampleStreamTest, TextEqualsReadSeries) {
  const std::string file = write("r.csv", text_record(20000));
  io::SeriesOptions opt;
  opt.lsb = {2.0, 0.5};
  const io::Series whole = io::read_series(file, opt);
  const auto stream = io::SampleStream::open(file, opt, 4096);  // about 100 pieces
  EXPECT_EQ(stream->names(), whole.names);
  EXPECT_EQ(stream->rate_hz(), whole.rate_hz);
  EXPECT_TRUE(stream->rate_from_time());
  EXPECT_EQ(stream->time_name(), "t");
  EXPECT_EQ(stream->left_out(), whole.left_out);
  std::size_t pieces = 0;
  const io::SampleChunk all = drain(*stream, &pieces);
  EXPECT_GT(pieces, 50u);
  ASSERT_EQ(all.channels.size(), whole.channels.size());
  for (std::size_t c = 0; c < all.channels.size(); ++c) EXPECT_EQ(all.channels[c], whole.channels[c]) << c;
}

TEST_F(SampleStreamTest, BinaryEqualsReadSeries) {
  std::string bytes(16, 'h');  // a header
  const auto a = test::white_plus_walk(30001, 0.01, 0.3, 0.01, 9, 1.0);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double v = a[i];
    const auto s16 = static_cast<std::int16_t>(static_cast<int>(i % 2000) - 1000);
    bytes.append(reinterpret_cast<const char*>(&v), 8);
    bytes.append(reinterpret_cast<const char*>(&s16), 2);
  }
  const std::string file = write("r.bin", bytes);
  io::SeriesOptions opt;
  opt.binary = io::parse_raw_layout("float64le,int16le", 16);
  opt.rate_hz = 100.0;
  opt.lsb = {1.0, 131.0};
  const io::Series whole = io::read_series(file, opt);
  const auto stream = io::SampleStream::open(file, opt, 1000);
  EXPECT_EQ(stream->names(), whole.names);
  std::size_t pieces = 0;
  const io::SampleChunk all = drain(*stream, &pieces);
  EXPECT_GT(pieces, 100u);
  ASSERT_EQ(all.channels.size(), 2u);
  for (std::size_t c = 0; c < 2; ++c) EXPECT_EQ(all.channels[c], whole.channels[c]) << c;
}

// One float64 channel (frames copied at once) over several pieces of the
// default size: binary pieces are cache-sized whatever chunk_bytes says.
TEST_F(SampleStreamTest, BinarySingleFloat64ChannelInCacheSizedPieces) {
  const auto a = test::white_plus_walk(100000, 0.01, 0.3, 0.01, 11, 2.0);
  const std::string file =
      write("one.bin", std::string(reinterpret_cast<const char*>(a.data()), a.size() * sizeof(double)));
  io::SeriesOptions opt;
  opt.binary = io::parse_raw_layout("float64le", 0);
  opt.rate_hz = 100.0;
  const io::Series whole = io::read_series(file, opt);
  const auto stream = io::SampleStream::open(file, opt);  // the default chunk_bytes (8 MiB)
  std::size_t pieces = 0;
  const io::SampleChunk all = drain(*stream, &pieces);
  EXPECT_GE(pieces, 3u);  // 800 kB in pieces of at most 256 KiB
  ASSERT_EQ(all.channels.size(), 1u);
  EXPECT_EQ(all.channels[0], whole.channels[0]);
  EXPECT_EQ(all.channels[0], a);
}

// The message read_series gives for a record, and the stream's.
std::pair<std::string, std::string> both_errors(const std::string& file, const io::SeriesOptions& opt) {
  std::string whole, streamed;
  try {
    (void)io::read_series(file, opt);
  } catch (const InputError& e) {
    whole = e.what();
  }
  try {
    const auto s = io::SampleStream::open(file, opt, 4096);
    (void)drain(*s);
  } catch (const InputError& e) {
    streamed = e.what();
  }
  return {whole, streamed};
}

TEST_F(SampleStreamTest, BadFieldInALatePieceIsAtItsLine) {
  std::string t = text_record(5000);
  const std::size_t at = t.find("\n4321e-2,");
  ASSERT_NE(at, std::string::npos);
  t.insert(t.find(',', at + 1) + 1, "x");  // "x0.123"
  const auto [whole, streamed] = both_errors(write("bad.csv", t), {});
  ASSERT_FALSE(whole.empty());
  EXPECT_EQ(streamed, whole);
  // Row 4321: after the comment and the header, and the comment at row 2500.
  EXPECT_NE(whole.find(":4325:9:"), std::string::npos) << whole << " / " << streamed;
}

TEST_F(SampleStreamTest, GapInALatePieceIsAtItsLine) {
  std::string t = text_record(5000);
  // Rows 4000 .. 4008 missing.
  const std::size_t from = t.find("\n4000e-2,"), to = t.find("\n4009e-2,");
  t.erase(from, to - from);
  const std::string file = write("gap.csv", t);
  const auto [whole, streamed] = both_errors(file, {});
  ASSERT_NE(whole.find("gap of"), std::string::npos) << whole << " / " << streamed;
  ASSERT_NE(streamed.find("gap of"), std::string::npos) << streamed;
  // The same place (FILE:LINE), the stream without a column.
  const std::string place = whole.substr(0, whole.find(':', whole.find(':') + 1) + 1);
  EXPECT_EQ(streamed.rfind(place, 0), 0u) << streamed << " vs " << whole;
  io::SeriesOptions split;
  split.gaps = io::GapPolicy::split;
  EXPECT_THROW(io::SampleStream::open(file, split), UsageError);
}

TEST_F(SampleStreamTest, TrailingPartialFrameNamesItsOffset) {
  std::string bytes(8 * 1001 + 3, '\0');
  const std::string file = write("p.bin", bytes);
  io::SeriesOptions opt;
  opt.binary = io::parse_raw_layout("float64le", 0);
  opt.rate_hz = 10.0;
  try {
    const auto s = io::SampleStream::open(file, opt, 800);
    (void)drain(*s);
    FAIL() << "accepted a partial frame";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("byte offset 8008"), std::string::npos) << e.what();
  }
}

TEST(SimulateBlocks, EqualTheWholeRecord) {
  pipeline::SimulateRequest req;
  req.triads.push_back(preset("sport-gyro"));
  req.rate_hz = 50.0;
  req.duration_s = 3000.0;  // 150000 samples: several blocks
  req.seed = 42;
  req.temperature.kind = TemperatureProfile::Kind::sinusoid;
  req.temperature.amplitude = 3.0;
  const pipeline::SimulatedRecord rec = pipeline::simulate(req);
  const std::size_t channels = rec.names.size();
  std::vector<std::vector<double>> got(channels);
  std::size_t next = 0;
  pipeline::simulate_blocks(req, [&](std::size_t k0, std::span<const double> frames) {
    EXPECT_EQ(k0, next);
    next += frames.size() / channels;
    for (std::size_t i = 0; i < frames.size(); ++i) got[i % channels].push_back(frames[i]);
  });
  for (std::size_t c = 0; c < channels; ++c) EXPECT_EQ(got[c], rec.channels[c]) << rec.names[c];
}

}  // namespace
}  // namespace cubecal
