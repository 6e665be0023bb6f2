// util::AtomicFile: a file is replaced whole or not at all, a failed write is one error naming the
// file, and no temporary is left behind.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "error_of.h"
#include "file_size_limit.h"
#include "lrd/util/atomic_file.h"
#include "lrd/util/binary_io.h"
#include "temp_dir.h"

namespace {

namespace fs = std::filesystem;
using lrd::test::error_of;
using lrd::test::error_with_file_size_limit;
using lrd::test::names_in;
using lrd::test::TempDir;
using lrd::util::AtomicFile;

TEST(AtomicFile, TheFileIsReplacedOnlyByCommit) {
  TempDir dir("atomic");
  const fs::path file = dir.write("out.txt", "old\n");
  {
    AtomicFile out(file);
    out.stream() << "new " << 42 << '\n';
    out.write(std::string(200000, 'x'));  // past the stream's buffer
    EXPECT_EQ(TempDir::read(file), "old\n");
    EXPECT_EQ(names_in(dir.path()).size(), 2u);  // the file and its temporary beside it
    EXPECT_EQ(out.temporary().parent_path(), file.parent_path());
    out.commit();
  }
  EXPECT_EQ(TempDir::read(file), "new 42\n" + std::string(200000, 'x'));
  EXPECT_EQ(names_in(dir.path()), std::set<std::string>{"out.txt"});
}

TEST(AtomicFile, AFileNotCommittedLeavesTheOldOneAndNoTemporary) {
  TempDir dir("atomic");
  const fs::path file = dir.write("out.txt", "old\n");
  {
    AtomicFile out(file);
    out.stream() << "half a file";
  }
  EXPECT_EQ(TempDir::read(file), "old\n");
  EXPECT_EQ(names_in(dir.path()), std::set<std::string>{"out.txt"});
  { AtomicFile out(dir.path() / "new.txt"); }
  EXPECT_EQ(names_in(dir.path()), std::set<std::string>{"out.txt"});
}

TEST(AtomicFile, AFullDiskIsOneErrorNamingTheFileAndTheOldFileStays) {
  TempDir dir("atomic");
  const fs::path file = dir.write("map.bin", "the previous run's good file\n");
  const std::string message =
      error_with_file_size_limit(1000, [&] { lrd::util::write_file_bytes(file, std::string(100000, 'x')); });
  EXPECT_EQ(message, file.string() + ": cannot write (File too large)");
  EXPECT_EQ(TempDir::read(file), "the previous run's good file\n");
  EXPECT_EQ(names_in(dir.path()), std::set<std::string>{"map.bin"});
  // The same through the stream, failing inside the buffer's flush at commit().
  const std::string streamed = error_with_file_size_limit(10, [&] {
    lrd::util::write_file_atomic(file, [](std::ostream& out) { out << "more than ten bytes\n"; });
  });
  EXPECT_EQ(streamed, file.string() + ": cannot write (File too large)");
  EXPECT_EQ(TempDir::read(file), "the previous run's good file\n");
  EXPECT_EQ(names_in(dir.path()), std::set<std::string>{"map.bin"});
}

TEST(AtomicFile, ADeviceIsWrittenIntoAndItsErrorsReported) {
  if (!fs::exists("/dev/full") || !fs::exists("/dev/null")) GTEST_SKIP() << "no /dev/full here";
  lrd::util::write_file_bytes("/dev/null", "gone\n");
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_EQ(error_of([] { lrd::util::write_file_bytes("/dev/full", "no room\n"); }),
            "/dev/full: cannot write (No space left on device)");
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

TEST(AtomicFile, AMissingFolderOrAFolderInTheWayIsOneErrorNamingTheFile) {
  TempDir dir("atomic");
  const fs::path missing = dir.path() / "no_such_dir" / "x.txt";
  EXPECT_EQ(error_of([&] { lrd::util::write_file_bytes(missing, "x"); }),
            missing.string() + ": cannot open for writing (No such file or directory)");
  fs::create_directory(dir.path() / "folder");
  EXPECT_EQ(error_of([&] { lrd::util::write_file_bytes(dir.path() / "folder", "x"); }),
            (dir.path() / "folder").string() + ": cannot open for writing (Is a directory)");
  EXPECT_EQ(names_in(dir.path()), std::set<std::string>{"folder"});
}

TEST(AtomicFile, ThroughASymlinkTheFileItPointsToIsReplaced) {
  TempDir dir("atomic");
  const fs::path target = dir.write("real/out.txt", "old\n");
  const fs::path link = dir.path() / "link.txt";
  fs::create_symlink(target, link);
  lrd::util::write_file_bytes(link, "new\n");
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(TempDir::read(target), "new\n");
  EXPECT_EQ(names_in(dir.path() / "real"), std::set<std::string>{"out.txt"});
}

TEST(AtomicFile, TheReplacementKeepsThePermissionsOfTheFileItReplaces) {
  TempDir dir("atomic");
  const fs::path file = dir.write("secret.txt", "old\n");
  fs::permissions(file, fs::perms::owner_read | fs::perms::owner_write);
  lrd::util::write_file_bytes(file, "new\n");
  EXPECT_EQ(fs::status(file).permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_EQ(TempDir::read(file), "new\n");
}

// Threads of one process writing the same file each use a temporary of their own: the file ends as
// one of them wrote it, never mixed, and no temporary is left.
TEST(AtomicFile, WritersOfTheSameFileInSeveralThreadsNeverMix) {
  TempDir dir("atomic");
  const fs::path file = dir.path() / "shared.txt";
  std::vector<std::string> contents;
  for (char c = 'a'; c < 'a' + 4; ++c) contents.emplace_back(100000, c);
  std::vector<std::thread> threads;
  for (const std::string& text : contents)
    threads.emplace_back([&file, &text] {
      for (int i = 0; i < 20; ++i) lrd::util::write_file_bytes(file, text, lrd::util::Sync::no);
    });
  for (std::thread& t : threads) t.join();
  const std::string result = TempDir::read(file);
  EXPECT_NE(std::find(contents.begin(), contents.end(), result), contents.end());
  EXPECT_EQ(names_in(dir.path()), std::set<std::string>{"shared.txt"});
}

}  // namespace
