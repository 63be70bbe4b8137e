// cubecal record's parts: the text line framer, the binary frame decoder
// and its checksums, the manifest's JSON round trip and the recovery of a
// chunk a crash left open.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cubecal/acquire/chunk_writer.hpp"
#include "cubecal/acquire/frame_decoder.hpp"
#include "cubecal/acquire/frame_spec.hpp"
#include "cubecal/acquire/line_framer.hpp"
#include "cubecal/acquire/rejects_writer.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/recording_manifest.hpp"

using namespace cubecal;
using namespace cubecal::acquire;
using namespace std::string_literals;

namespace {

struct Collect : SampleHandler {
  std::vector<std::string> names;
  std::vector<std::string> samples;
  std::vector<std::vector<double>> values;
  std::vector<std::pair<std::string, std::string>> rejects;
  void on_layout(const std::vector<std::string>& n) override { names = n; }
  void on_sample(std::string_view f, std::span<const double> v) override {
    samples.emplace_back(f);
    values.emplace_back(v.begin(), v.end());
  }
  void on_reject(std::string_view reason, std::string_view data, bool) override {
    rejects.emplace_back(std::string(reason), std::string(data));
  }
};

std::string temp_dir() {
  char tmpl[] = "/tmp/cubecal_record_XXXXXX";
  const char* d = ::mkdtemp(tmpl);
  if (d == nullptr) throw std::runtime_error("mkdtemp");
  return d;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST(LineFramer, HeaderDelimiterAndRejectsFedByteByByte) {
  const std::string text = "t;gx;gy\r\n0.0;1.5;-2\r\n0.1;1.25;bad\r\n0.2;+3;4e-3\r\n0.3;1\r\n\r\nt;gx;gy\r\n0.4;5;6";
  LineFramer f;
  Collect c;
  for (const char ch : text) f.feed(std::string_view(&ch, 1), c);  // every split point
  f.finish(c);
  EXPECT_EQ(c.names, (std::vector<std::string>{"t", "gx", "gy"}));
  EXPECT_EQ(f.delimiter(), ';');
  ASSERT_EQ(c.samples.size(), 2u);
  EXPECT_EQ(c.samples[0], "0.0,1.5,-2");  // re-joined by commas
  EXPECT_EQ(c.samples[1], "0.2,+3,4e-3");
  EXPECT_DOUBLE_EQ(c.values[1][2], 4e-3);
  ASSERT_EQ(c.rejects.size(), 4u);
  EXPECT_EQ(c.rejects[0], (std::pair<std::string, std::string>{"field 3 is not a number", "0.1;1.25;bad"}));
  EXPECT_EQ(c.rejects[1].first, "2 fields where the layout has 3");
  EXPECT_EQ(c.rejects[2].first, "header line repeated");
  EXPECT_EQ(c.rejects[3], (std::pair<std::string, std::string>{"partial line at end of stream", "0.4;5;6"}));
  EXPECT_EQ(f.blank_lines(), 1u);
}

TEST(LineFramer, PartialFirstLineOfAStreamJoinedMidway) {
  LineFramer f;
  Collect c;
  f.feed("2,0.5\n1.0,2.0,3.0\n1.1,2.1,3.1\n", c);
  EXPECT_EQ(c.names, (std::vector<std::string>{"col1", "col2", "col3"}));
  ASSERT_EQ(c.rejects.size(), 1u);
  EXPECT_EQ(c.rejects[0].first, "partial line at start of stream");
  EXPECT_EQ(c.samples, (std::vector<std::string>{"1.0,2.0,3.0", "1.1,2.1,3.1"}));
}

TEST(LineFramer, CarriageReturnLinesAndGivenColumns) {
  LineFramerOptions o;
  o.columns = {"a", "b"};
  LineFramer f(o);
  Collect c;
  f.feed("1 2\r3\t4\r5 inf\r", c);
  EXPECT_EQ(c.names, o.columns);
  EXPECT_EQ(c.samples, (std::vector<std::string>{"1,2", "3,4"}));
  ASSERT_EQ(c.rejects.size(), 1u);
  EXPECT_EQ(c.rejects[0].first, "field 2 is not finite");
}

// Issue 33, item 2: serial noise at power-up (bytes that are not UTF-8, a
// NUL) before the header is a reject each, never the header.
TEST(LineFramer, NoiseThatIsNotTextBeforeTheHeaderIsARejectNotTheHeader) {
  LineFramer f;
  Collect c;
  f.feed("\xff\xfe\x00gar\xe9\n\xe9\xff\nt,gx\n0,1\n"s, c);
  f.feed("0.01,2\n", c);
  EXPECT_EQ(c.names, (std::vector<std::string>{"t", "gx"}));
  EXPECT_EQ(c.samples, (std::vector<std::string>{"0,1", "0.01,2"}));
  ASSERT_EQ(c.rejects.size(), 2u);
  EXPECT_EQ(c.rejects[0].second, "\xff\xfe\x00gar\xe9"s);
  EXPECT_EQ(c.rejects[1].second, "\xe9\xff");
  EXPECT_EQ(c.rejects[0].first.rfind("not text", 0), 0u) << c.rejects[0].first;
  // A tab-delimited header is text.
  LineFramer tabs;
  Collect t;
  tabs.feed("t\tgx\n0\t1\n", t);
  EXPECT_EQ(t.names, (std::vector<std::string>{"t", "gx"}));
  EXPECT_TRUE(t.rejects.empty());
  LineFramerOptions o;
  o.columns = {"t", "g\xe9"};
  EXPECT_THROW(LineFramer{o}, UsageError);
}

// Issue 33, item 8: the end of a datagram ends a line.
TEST(LineFramer, TheEndOfARecordEndsTheLine) {
  LineFramer f;
  Collect c;
  for (const std::string_view d : {"t,gx", "0,1", "0.01,2\n0.02,3", "0.03,4\r", "0.04,5\r\n"}) {
    f.feed(d, c);
    f.end_record(c);
  }
  f.finish(c);
  EXPECT_EQ(c.names, (std::vector<std::string>{"t", "gx"}));
  EXPECT_EQ(c.samples, (std::vector<std::string>{"0,1", "0.01,2", "0.02,3", "0.03,4", "0.04,5"}));
  EXPECT_TRUE(c.rejects.empty());
}

// rejects.csv stays valid UTF-8 text, one line per reject, and gives the
// bytes back: control bytes, malformed UTF-8 and the backslash as \xNN.
TEST(RejectsWriter, TextIsEscapedToOneLineOfUtf8) {
  EXPECT_EQ(escaped_text("a\xff\x00"s + "b\\x41\r\n\xc3\xa9\t"), "a\\xff\\x00b\\x5cx41\\x0d\\x0a\xc3\xa9\\x09");
  const std::string d = temp_dir();
  {
    RejectsWriter w(d);
    w.add(",,", "comment line", "# \xe9\n\"q\"", false);
    w.close();
  }
  EXPECT_EQ(slurp(d + "/rejects.csv"),
            "host_mono_s,host_utc_s,reason,data\n,,\"comment line\",\"# \\xe9\\x0a\"\"q\"\"\"\n");
  EXPECT_EQ(std::system(("rm -rf " + d).c_str()), 0);
}

// Issue 33, item 8: recovery reads, cuts and syncs the chunk itself, never
// a file a symbolic link in its place points to.
TEST(ChunkWriter, RecoveryNeverFollowsASymbolicLink) {
  const std::string d = temp_dir();
  const std::string victim = d + "/outside.txt";
  const std::string text = "host_mono_s,host_utc_s,t,gx\n1.0,100.0,0.0,1\npartial";
  { std::ofstream(victim, std::ios::binary) << text; }
  ASSERT_EQ(::symlink(victim.c_str(), (d + "/chunk-000001.csv").c_str()), 0);
  io::RecordingChunk as_manifest;
  as_manifest.file = "chunk-000001.csv";
  as_manifest.open = true;
  EXPECT_THROW(recover_chunk(d, as_manifest, 2), InputError);
  EXPECT_EQ(slurp(victim), text);
  EXPECT_EQ(std::system(("rm -rf " + d).c_str()), 0);
}

TEST(FrameSpec, ParsesAndRefuses) {
  const FrameSpec s = parse_frame_spec("sync=A55A;fields=t:u32,gx:i16,gy:f32;checksum=crc16;endian=be");
  EXPECT_EQ(s.sync, std::string("\xA5\x5A", 2));
  EXPECT_EQ(s.frame_size(), 2u + 4 + 2 + 4 + 2);
  EXPECT_TRUE(s.big_endian);
  EXPECT_EQ(s.fields[2].offset, 8u);
  EXPECT_THROW(parse_frame_spec("sync=A5;fields=t:u24"), UsageError);
  EXPECT_THROW(parse_frame_spec("fields=t:u32"), UsageError);
  EXPECT_THROW(parse_frame_spec("sync=A55;fields=t:u32"), UsageError);
  // A key given twice is refused: two syncs would make one of 5 bytes (the
  // fuzzer's find), two field lists one list whose names were never checked
  // against each other.
  for (const char* twice :
       {"sync=7E7E32;sync=7E7E;fields=x:u16", "sync=7E;fields=a:u8;fields=a:u8",
        "sync=7E;fields=a:u8;checksum=xor8;checksum=crc16", "sync=7E;endian=le;fields=a:u8;endian=be"}) {
    try {
      (void)parse_frame_spec(twice);
      ADD_FAILURE() << twice << " accepted";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("given twice"), std::string::npos) << twice << ": " << e.what();
    }
  }
}

TEST(FrameSpec, Checksums) {
  // CRC-16/CCITT-FALSE and CRC-32 check values of "123456789".
  EXPECT_EQ(checksum_of(Checksum::crc16, "123456789"), 0x29B1u);
  EXPECT_EQ(checksum_of(Checksum::crc32, "123456789"), 0xCBF43926u);
  EXPECT_EQ(checksum_of(Checksum::xor8, std::string("\x01\x02\x04", 3)), 0x07u);
  EXPECT_EQ(checksum_of(Checksum::sum8, std::string("\xF0\x20", 2)), 0x10u);
}

TEST(FrameDecoder, DecodesResyncsAndRejectsBadChecksums) {
  const FrameSpec s = parse_frame_spec("sync=A55A;fields=t:u16,gx:i16,v:f32;checksum=xor8");
  auto frame = [&](std::uint16_t t, std::int16_t gx, float v, bool corrupt) {
    std::string b = s.sync;
    std::string p;
    p.push_back(static_cast<char>(t & 0xFF));
    p.push_back(static_cast<char>(t >> 8));
    const auto ugx = static_cast<std::uint16_t>(gx);
    p.push_back(static_cast<char>(ugx & 0xFF));
    p.push_back(static_cast<char>(ugx >> 8));
    char fb[4];
    std::memcpy(fb, &v, 4);
    p.append(fb, 4);
    b += p;
    b.push_back(static_cast<char>(checksum_of(Checksum::xor8, p) ^ (corrupt ? 1 : 0)));
    return b;
  };
  const std::string stream = "\x01\x02\x03" + frame(1, -5, 0.5f, false) + frame(2, 7, 1.5f, true) + "zz" +
                             frame(3, -32768, -2.25f, false) + frame(4, 0, 0.0f, false).substr(0, 5);
  FrameDecoder d(s);
  Collect c;
  for (std::size_t i = 0; i < stream.size(); i += 3) d.feed(std::string_view(stream).substr(i, 3), c);
  d.drop_partial("partial frame at end of stream", c);
  EXPECT_EQ(c.names, (std::vector<std::string>{"t", "gx", "v"}));
  EXPECT_EQ(c.samples, (std::vector<std::string>{"1,-5,0.5", "3,-32768,-2.25"}));
  ASSERT_EQ(c.rejects.size(), 4u);
  EXPECT_EQ(c.rejects[0],
            (std::pair<std::string, std::string>{"bytes skipped looking for the sync bytes", "\x01\x02\x03"}));
  EXPECT_EQ(c.rejects[1].first, "bad checksum");
  EXPECT_EQ(c.rejects[1].second.size(), s.frame_size());
  EXPECT_EQ(c.rejects[2].second, "zz");
  EXPECT_EQ(c.rejects[3].first, "partial frame at end of stream");
  EXPECT_EQ(c.rejects[3].second.size(), 5u);
}

// Found by fuzz_line_framer: lines ending in CR whose first read ended on
// that CR had the first line joined to the second.
TEST(LineFramer, CarriageReturnLinesSplitOnTheFirstLineEnd) {
  const std::string text = "a,b\r1,2\r3,4\r5,6\r";
  for (std::size_t cut = 1; cut < text.size(); ++cut) {
    LineFramer f;
    Collect c;
    f.feed(std::string_view(text).substr(0, cut), c);
    f.feed(std::string_view(text).substr(cut), c);
    f.finish(c);
    EXPECT_EQ(c.names, (std::vector<std::string>{"a", "b"})) << "cut at " << cut;
    EXPECT_EQ(c.samples, (std::vector<std::string>{"1,2", "3,4", "5,6"})) << "cut at " << cut;
    EXPECT_TRUE(c.rejects.empty()) << "cut at " << cut;
  }
  LineFramer f;
  Collect c;
  for (const char ch : std::string("7,8\r9,10\r11,12\r")) f.feed(std::string_view(&ch, 1), c);
  f.finish(c);
  EXPECT_EQ(c.samples, (std::vector<std::string>{"7,8", "9,10", "11,12"}));
}

// Found by fuzz_frame_decoder: a NaN or infinite float became a chunk value.
TEST(FrameDecoder, NonFiniteFloatMakesTheFrameAReject) {
  const FrameSpec s = parse_frame_spec("sync=7E;fields=n:u8,v:f32");
  auto frame = [&](std::uint8_t n, std::uint32_t bits) {
    std::string b = s.sync;
    b.push_back(static_cast<char>(n));
    for (int k = 0; k < 4; ++k) b.push_back(static_cast<char>((bits >> (8 * k)) & 0xFF));
    return b;
  };
  FrameDecoder d(s);
  Collect c;
  d.feed(frame(1, 0x3FC00000u) + frame(2, 0x7FC00000u) + frame(3, 0xFF800000u) + frame(4, 0xC0100000u), c);
  EXPECT_EQ(c.samples, (std::vector<std::string>{"1,1.5", "4,-2.25"}));
  ASSERT_EQ(c.rejects.size(), 2u);
  EXPECT_EQ(c.rejects[0].first, "field 2 is not finite");
  EXPECT_EQ(c.rejects[0].second, frame(2, 0x7FC00000u));
  EXPECT_EQ(c.rejects[1].second, frame(3, 0xFF800000u));
}

// Found by fuzz_frame_decoder: the spec's text was quoted raw in the error.
TEST(FrameSpec, ErrorQuotesTheSpecPrintably) {
  try {
    (void)parse_frame_spec("sync=A5;fie\x01lds=t:u8");
    FAIL() << "no error";
  } catch (const UsageError& e) {
    EXPECT_EQ(std::string(e.what()).find('\x01'), std::string::npos) << e.what();
  }
}

// Found by fuzz_recording_manifest: a number beyond a double threw
// nlohmann's out_of_range instead of an InputError.
TEST(RecordingManifest, NumberBeyondADoubleIsAnInputError) {
  EXPECT_THROW(io::parse_manifest("{\"format\": \"cubecal-record/1\", \"rate_hz\": 1e999}", "m.json"), InputError);
}

TEST(RecordingManifest, JsonRoundTrip) {
  io::RecordingManifest m;
  m.columns = {"t", "gx"};
  m.time_column = "t";
  m.rate_hz = 100.0;
  m.framing.kind = io::RecordingFraming::Kind::binary;
  m.framing.frame = "sync=A5;fields=t:u32,gx:i16";
  m.source = "/dev/ttyUSB0 at 115200 baud";
  io::RecordingSegment s;
  s.index = 2;
  s.dir = "seg-002";
  s.start_utc = io::utc_iso8601(1795780000, 123456789);
  s.start_mono_s = 12.5;
  s.end = io::SegmentEnd::recovered;
  s.samples = 7;
  s.rejects = 1;
  s.partial_bytes = 9;
  io::RecordingChunk c;
  c.file = "chunk-000001.csv";
  c.samples = 7;
  c.bytes = 300;
  c.crc32 = 0x0a1b2c3du;
  c.first_host_utc_s = 1795780000.25;
  c.last_host_utc_s = 1795780001.5;
  s.chunks = {c};
  io::RecordingEvent g;
  g.kind = io::RecordingEvent::Kind::gap;
  g.sample = 5;
  g.device_time = 0.05;
  g.dt = 0.03;
  g.expected_dt = 0.01;
  io::RecordingEvent r;
  r.kind = io::RecordingEvent::Kind::reconnect;
  r.sample = 6;
  r.host_utc_s = 1795780001.0;
  s.events = {g, r};
  m.segments = {s};
  const std::string text = io::manifest_text(m);
  EXPECT_NE(text.find("\"crc32\": \"0a1b2c3d\""), std::string::npos);
  EXPECT_NE(text.find("\"start_utc\": \"2026-11-27T11:46:40.123456789Z\""), std::string::npos);
  const io::RecordingManifest back = io::parse_manifest(text, "manifest.json");
  EXPECT_EQ(io::manifest_text(back), text);
  EXPECT_EQ(back.segments[0].chunks[0].crc32, 0x0a1b2c3du);
  EXPECT_EQ(back.segments[0].events[1].kind, io::RecordingEvent::Kind::reconnect);
  EXPECT_FALSE(back.unit.has_value());
  EXPECT_THROW(io::parse_manifest("{\"format\": \"other\"}", "m.json"), InputError);
  EXPECT_THROW(io::parse_manifest("{", "m.json"), InputError);
}

TEST(RecordingManifest, AtomicReplace) {
  const std::string d = temp_dir();
  io::RecordingManifest m;
  m.columns = {"x"};
  m.source = "stdin";
  io::write_manifest(d, m);
  EXPECT_TRUE(io::is_recording_dir(d));
  EXPECT_FALSE(io::is_recording_dir(d + "/none"));
  EXPECT_EQ(io::read_manifest(d).columns, m.columns);
  struct stat st {};
  EXPECT_NE(::stat((d + "/manifest.json.partial").c_str(), &st), 0);  // renamed away
  EXPECT_EQ(std::system(("rm -rf " + d).c_str()), 0);
}

TEST(ChunkWriter, CrcAndRecoveryOfAPartialTail) {
  const std::string d = temp_dir();
  {
    ChunkWriter w(d, chunk_file_name(1), {"t", "gx"});
    w.add("1.000000000,100.000000000,", "0.0,1", 100.0);
    w.add("1.000000000,100.000000000,", "0.1,2", 100.0);
    w.sync();
    EXPECT_EQ(w.synced().samples, 2u);
    w.add("2.000000000,101.000000000,", "0.2,3", 101.0);
    const io::RecordingChunk c = w.close();
    const std::string data = slurp(d + "/chunk-000001.csv");
    EXPECT_EQ(c.bytes, data.size());
    EXPECT_EQ(*c.crc32, static_cast<std::uint32_t>(
                            crc32(0, reinterpret_cast<const Bytef*>(data.data()), static_cast<uInt>(data.size()))));
    EXPECT_EQ(c.samples, 3u);
  }
  // A crashed chunk: the manifest vouched for the header and one line; two
  // more complete lines, a corrupt one and a partial tail follow.
  const std::string body = "host_mono_s,host_utc_s,t,gx\n1.0,100.0,0.0,1\n1.0,100.0,0.1,2\n2.0,101.5,0.2,3\n";
  const std::string bad = "2.0,101.5,0.3\n2.0,101.5,0.4,5\n2.0,10";
  { std::ofstream(d + "/chunk-000002.csv", std::ios::binary) << body << bad; }
  io::RecordingChunk as_manifest;
  as_manifest.file = "chunk-000002.csv";
  as_manifest.bytes = 44;  // the header and the first line
  as_manifest.samples = 1;
  as_manifest.open = true;
  const RecoveredChunk r = recover_chunk(d, as_manifest, 2);
  EXPECT_EQ(r.chunk.samples, 3u);
  EXPECT_EQ(r.chunk.bytes, body.size());
  EXPECT_EQ(r.tail, bad);
  EXPECT_EQ(r.last_stamps, "2.0,101.5,");
  EXPECT_DOUBLE_EQ(r.chunk.last_host_utc_s, 101.5);
  EXPECT_FALSE(r.chunk.open);
  EXPECT_EQ(slurp(d + "/chunk-000002.csv"), body);
  EXPECT_EQ(*r.chunk.crc32, static_cast<std::uint32_t>(
                                crc32(0, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()))));
  EXPECT_EQ(std::system(("rm -rf " + d).c_str()), 0);
}
