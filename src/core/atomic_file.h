#pragma once
// Files appear whole or not at all: written to a temporary name beside the target, flushed to
// disk, then renamed over it. A killed process leaves at most a stray *.tmp-<pid> file.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace wheelpose {

void write_file_atomic(const std::filesystem::path& path, std::string_view contents);

// The same for contents produced piece by piece: written to the temporary name as they come,
// renamed into place by commit(). Destroyed without commit(), it removes the temporary file.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(const std::filesystem::path& path);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
  void write(std::string_view contents);
  void commit();

 private:
  std::filesystem::path path_, temp_;
  int fd_ = -1;
};

// Removes the temporary files a killed writer left in `dir` (not recursive).
void remove_stale_temporaries(const std::filesystem::path& dir);
void write_file_atomic(const std::filesystem::path& path, std::span<const std::uint8_t> contents);

// Reads a whole file; throws Error naming the path if it cannot.
std::string read_file(const std::filesystem::path& path);

// Creates a directory (and parents); throws Error naming it on failure.
void ensure_directory(const std::filesystem::path& path);

}  // namespace wheelpose
