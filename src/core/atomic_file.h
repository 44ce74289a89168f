#pragma once
// Files appear whole or not at all: written to a temporary name beside the target, flushed to
// disk, then renamed over it. A killed process leaves at most a stray *.tmp-<pid> file.
//
// What the target already is decides how it is written:
// - nothing, or a regular file: the temporary file is renamed over it (through a symlink, over
//   the file it points to, so the link stays);
// - a character device or a FIFO (/dev/null, /dev/stdout on a pipe or terminal, a named pipe):
//   written in place, never replaced, since users name these on purpose;
// - a directory or anything else (block device, socket): refused, Error exit 2.
// Errors name the path the caller gave, never the temporary file: exit 2 when the path cannot
// be written at all (no such folder, no permission, read-only), exit 1 when writing fails
// midway (disk full).

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
  std::filesystem::path path_, target_, temp_;  // as given, where it lands, the temporary
  bool in_place_ = false;                       // a device or FIFO: written directly
  int fd_ = -1;
};

// Throws the Error the writer would for `path` (a directory, a socket, a missing or read-only
// folder), so a command can refuse its --out before hours of work rather than after.
void check_output_file(const std::filesystem::path& path);

// Removes the temporary files a killed writer left in `dir` (not recursive).
void remove_stale_temporaries(const std::filesystem::path& dir);
void write_file_atomic(const std::filesystem::path& path, std::span<const std::uint8_t> contents);

// Reads a whole file; throws Error naming the path if it cannot.
std::string read_file(const std::filesystem::path& path);

// Creates a directory (and parents); throws Error naming it on failure.
void ensure_directory(const std::filesystem::path& path);

}  // namespace wheelpose
