#include "core/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include "core/error.h"

namespace wheelpose {
namespace {

namespace fs = std::filesystem;

TEST(AtomicFile, WritesReplacesAndLeavesNoTemporary) {
  fs::path dir = fs::temp_directory_path() / ("wheelpose_atomic_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  ensure_directory(dir / "sub");
  fs::path file = dir / "sub" / "a.txt";
  write_file_atomic(file, std::string_view("first"));
  write_file_atomic(file, std::string_view("second"));
  EXPECT_EQ(read_file(file), "second");
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir / "sub")) ++entries;
  EXPECT_EQ(entries, 1);
  fs::remove_all(dir);
}

TEST(AtomicFile, StreamedFileAppearsOnlyOnCommit) {
  fs::path dir = fs::temp_directory_path() / ("wheelpose_stream_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  ensure_directory(dir);
  {
    AtomicFileWriter writer(dir / "a.txt");
    writer.write("one ");
    writer.write("two");
    EXPECT_FALSE(fs::exists(dir / "a.txt"));
    writer.commit();
  }
  EXPECT_EQ(read_file(dir / "a.txt"), "one two");
  {
    AtomicFileWriter abandoned(dir / "b.txt");
    abandoned.write("half");
  }
  EXPECT_FALSE(fs::exists(dir / "b.txt"));
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1);  // no temporary left behind
  // What a killed writer leaves is swept away; finished files stay.
  std::ofstream(dir / "c.txt.tmp-123") << "stale";
  remove_stale_temporaries(dir);
  EXPECT_FALSE(fs::exists(dir / "c.txt.tmp-123"));
  EXPECT_TRUE(fs::exists(dir / "a.txt"));
  fs::remove_all(dir);
}

// The error of `write`, or "" if it succeeded; `exit_code` gets its exit code.
std::string write_error(const fs::path& path, std::string_view contents, int* exit_code) {
  try {
    write_file_atomic(path, contents);
    *exit_code = 0;
    return "";
  } catch (const Error& e) {
    *exit_code = e.exit_code();
    return e.what();
  }
}

TEST(AtomicFile, FailsClearlyInMissingDirectory) {
  int code = 0;
  // The message names the path the user gave, not the temporary file; exit 2 (bad --out).
  EXPECT_EQ(write_error("/nonexistent-dir/x.txt", "x", &code),
            "/nonexistent-dir/x.txt: cannot create: No such file or directory");
  EXPECT_EQ(code, 2);
  EXPECT_THROW(check_output_file("/nonexistent-dir/x.txt"), Error);
  EXPECT_THROW(read_file("/nonexistent-dir/x.txt"), Error);
}

fs::path fresh_dir(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / (name + std::to_string(::getpid()));
  fs::remove_all(dir);
  ensure_directory(dir);
  return dir;
}

// Copies of /dev/null and /dev/full (made with mknod, so a regression replaces a copy, not the
// machine's device); skipped where this process may not make device files.
TEST(AtomicFile, DevicesAreWrittenInPlaceNeverReplaced) {
  const fs::path dir = fresh_dir("wheelpose_devices_");
  const fs::path null = dir / "null", full = dir / "full";
  if (::mknod(null.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0 ||
      ::mknod(full.c_str(), S_IFCHR | 0666, makedev(1, 7)) != 0) {
    fs::remove_all(dir);
    GTEST_SKIP() << "cannot make device files here (mknod needs CAP_MKNOD)";
  }
  int code = 0;
  EXPECT_EQ(write_error(null, "discarded", &code), "");
  EXPECT_TRUE(fs::is_character_file(null));
  EXPECT_NO_THROW(check_output_file(null));
  // A full device: the write fails (disk full, exit 1) and the device stays a device.
  EXPECT_EQ(write_error(full, "x", &code),
            full.string() + ": write failed: No space left on device");
  EXPECT_EQ(code, 1);
  EXPECT_TRUE(fs::is_character_file(full));
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 2);  // no temporary left behind
  fs::remove_all(dir);
}

TEST(AtomicFile, AFifoIsWrittenInPlace) {
  const fs::path dir = fresh_dir("wheelpose_fifo_");
  const fs::path fifo = dir / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = read_file(fifo); });
  write_file_atomic(fifo, std::string_view("through the pipe"));
  reader.join();
  EXPECT_EQ(received, "through the pipe");
  EXPECT_TRUE(fs::is_fifo(fifo));
  fs::remove_all(dir);
}

TEST(AtomicFile, ADirectoryOrDanglingLinkIsRefusedAndLeftAlone) {
  const fs::path dir = fresh_dir("wheelpose_refuse_");
  ensure_directory(dir / "out.json");
  int code = 0;
  EXPECT_EQ(
      write_error(dir / "out.json", "x", &code),
      (dir / "out.json").string() + ": is a directory, not a file to write; give a file name");
  EXPECT_EQ(code, 2);
  EXPECT_TRUE(fs::is_directory(dir / "out.json"));
  EXPECT_THROW(check_output_file(dir / "out.json"), Error);
  fs::create_symlink(dir / "nowhere", dir / "dangling");
  EXPECT_NE(write_error(dir / "dangling", "x", &code).find("a symbolic link to nothing"),
            std::string::npos);
  EXPECT_TRUE(fs::is_symlink(dir / "dangling"));
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 2);  // no temporary left behind
  fs::remove_all(dir);
}

TEST(AtomicFile, ALinkToAFileKeepsTheLink) {
  const fs::path dir = fresh_dir("wheelpose_link_");
  write_file_atomic(dir / "real.json", std::string_view("old"));
  fs::create_symlink("real.json", dir / "link.json");
  write_file_atomic(dir / "link.json", std::string_view("new"));
  EXPECT_TRUE(fs::is_symlink(dir / "link.json"));
  EXPECT_EQ(read_file(dir / "real.json"), "new");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wheelpose
