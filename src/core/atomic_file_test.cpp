#include "core/atomic_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

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
  { AtomicFileWriter abandoned(dir / "b.txt"); abandoned.write("half"); }
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

TEST(AtomicFile, FailsClearlyInMissingDirectory) {
  try {
    write_file_atomic("/nonexistent-dir/x.txt", std::string_view("x"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.txt"), std::string::npos);
    EXPECT_EQ(e.exit_code(), 1);
  }
  EXPECT_THROW(read_file("/nonexistent-dir/x.txt"), Error);
}

}  // namespace
}  // namespace wheelpose
