// io::AtomicFile: a file is written whole or not at all, through PATH.partial;
// no symlink is followed into another file, nothing but a regular file is
// replaced (a FIFO or a device is written into, a link refused) and nothing
// but the writer's own temporary is ever removed.
#include "cubecal/io/atomic_file.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <thread>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include "cubecal/error.hpp"
#include "fifo.hpp"

namespace {

using cubecal::test::drain_fifo;
namespace fs = std::filesystem;
using cubecal::io::AtomicFile;

class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cubecal-atomic-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static std::string read(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  static void write(const std::string& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

  fs::path dir_;
};

TEST_F(AtomicFileTest, CommitPutsTheWholeFileInPlaceAndLeavesNoTemporary) {
  const std::string p = path("out.txt");
  write(p, "old");
  {
    AtomicFile f(p);
    ASSERT_TRUE(f.is_open());
    EXPECT_EQ(f.temp_path(), p + ".partial");
    EXPECT_TRUE(f.write("new "));
    EXPECT_TRUE(f.write("content"));
    EXPECT_EQ(read(p), "old");  // nothing under the real name before the commit
    EXPECT_TRUE(f.commit());
  }
  EXPECT_EQ(read(p), "new content");
  EXPECT_FALSE(fs::exists(p + ".partial"));
}

TEST_F(AtomicFileTest, WithoutCommitTheOldFileStaysAndTheTemporaryGoes) {
  const std::string p = path("out.txt");
  write(p, "old");
  {
    AtomicFile f(p);
    ASSERT_TRUE(f.is_open());
    EXPECT_TRUE(f.write("half"));
  }
  EXPECT_EQ(read(p), "old");
  EXPECT_FALSE(fs::exists(p + ".partial"));
}

TEST_F(AtomicFileTest, AStaleTemporaryOfAKilledRunIsReplaced) {
  const std::string p = path("out.txt");
  write(p + ".partial", "stale bytes of an interrupted run");
  AtomicFile f(p);
  ASSERT_TRUE(f.is_open());
  EXPECT_TRUE(f.write("x"));
  EXPECT_TRUE(f.commit());
  EXPECT_EQ(read(p), "x");
}

TEST_F(AtomicFileTest, ASymlinkInPlaceOfTheTemporaryIsNeitherFollowedNorRemoved) {
  const std::string p = path("out.txt");
  const std::string victim = path("victim.txt");
  write(victim, "keep me");
  fs::create_symlink(victim, p + ".partial");
  {
    AtomicFile f(p);
    EXPECT_FALSE(f.is_open());
    EXPECT_EQ(f.failed_step(), AtomicFile::Step::create);
    EXPECT_FALSE(f.write("x"));
  }
  EXPECT_TRUE(fs::is_symlink(p + ".partial"));
  EXPECT_EQ(read(victim), "keep me");
  EXPECT_FALSE(fs::exists(p));
}

// Issue 33, item 5: only a regular file is ever replaced. A symbolic link at
// the target (to a file, or dangling) is refused: neither replaced nor
// followed.
TEST_F(AtomicFileTest, ASymlinkAtTheTargetIsRefusedNeitherReplacedNorFollowed) {
  const std::string p = path("out.txt");
  const std::string victim = path("victim.txt");
  write(victim, "keep me");
  fs::create_symlink(victim, p);
  fs::create_symlink(path("nowhere"), path("dangling"));
  for (const std::string& target : {p, path("dangling")}) {
    AtomicFile f(target);
    EXPECT_FALSE(f.is_open()) << target;
    EXPECT_EQ(f.error(), EEXIST) << target;
    EXPECT_TRUE(fs::is_symlink(target)) << target;
    std::string why;
    EXPECT_EQ(cubecal::io::classify_output(target, &why), cubecal::io::OutputTarget::refused);
    EXPECT_NE(why.find(target + " is a symbolic link to "), std::string::npos) << why;
    EXPECT_THROW(cubecal::io::write_file(target, "new"), cubecal::UsageError);
  }
  EXPECT_EQ(read(victim), "keep me");
  EXPECT_FALSE(fs::exists(path("nowhere")));
  EXPECT_THROW(cubecal::io::replace_file_atomically(p, "new"), std::system_error);
  EXPECT_TRUE(fs::is_symlink(p));
}

// A FIFO, and a character device through a link (/dev/null), are written
// into: what a user naming them means; neither is replaced by a file.
TEST_F(AtomicFileTest, AFifoOrADeviceIsWrittenIntoNotReplaced) {
  const std::string fifo = path("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string got;
  std::thread reader([&] { got = drain_fifo(fifo); });
  {
    AtomicFile f(fifo);
    ASSERT_TRUE(f.is_open());
    EXPECT_TRUE(f.into_stream());
    EXPECT_TRUE(f.write("through the pipe"));
    EXPECT_TRUE(f.commit());
  }
  reader.join();
  EXPECT_EQ(got, "through the pipe");
  struct stat st {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  const std::string null = path("null");
  fs::create_symlink("/dev/null", null);
  cubecal::io::write_file(null, "gone");
  EXPECT_TRUE(fs::is_symlink(null));
  EXPECT_FALSE(fs::exists(null + ".partial"));
  // Not for a recording's manifest: a FIFO there is refused, left as it is.
  EXPECT_THROW(cubecal::io::replace_file_atomically(fifo, "{}"), std::system_error);
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
}

TEST_F(AtomicFileTest, WhatTookTheTemporarysPlaceIsNotRemoved) {
  const std::string p = path("out.txt");
  {
    AtomicFile f(p);
    ASSERT_TRUE(f.is_open());
    fs::remove(p + ".partial");
    fs::create_directory(p + ".partial");  // not the writer's file any more
  }
  EXPECT_TRUE(fs::is_directory(p + ".partial"));
}

TEST_F(AtomicFileTest, FailuresSayTheFileAndTheStep) {
  const std::string p = path("missing/out.txt");
  try {
    cubecal::io::replace_file_atomically(p, "x");
    FAIL() << "no error";
  } catch (const std::system_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(p + ".partial: cannot be created", 0), 0u) << e.what();
  }
  try {
    cubecal::io::write_file(p, "x", cubecal::Field::out);
    FAIL() << "no error";
  } catch (const cubecal::UsageError& e) {
    EXPECT_EQ(e.field(), cubecal::Field::out);
    EXPECT_EQ(std::string(e.what()), "cannot write " + p + " (check the directory exists and is writable)");
  }
  cubecal::io::write_file(path("out.txt"), "whole");
  EXPECT_EQ(read(path("out.txt")), "whole");
}

}  // namespace
