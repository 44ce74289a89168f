#include "core/atomic_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

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
