#include "core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace wheelpose {

namespace {

namespace fs = std::filesystem;

constexpr const char* kTempMarker = ".tmp-";

// Errors where the path itself cannot be written (the user's to fix) versus the machine failing.
bool is_path_problem(int error) {
  return error == EACCES || error == EPERM || error == ENOENT || error == ENOTDIR ||
         error == EROFS || error == EISDIR || error == ENAMETOOLONG || error == ELOOP ||
         error == ENXIO;
}

[[noreturn]] void io_failure(const fs::path& path, const char* what, int error) {
  throw Error(path.string() + ": " + what + ": " + std::strerror(error),
              is_path_problem(error) ? ErrorKind::kBadInput : ErrorKind::kFailure);
}

void fsync_directory(const fs::path& dir) {
  int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;  // best effort: some filesystems refuse directory fds
  ::fsync(fd);
  ::close(fd);
}

const char* file_kind(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

struct OutputPlan {
  fs::path target;  // where the bytes land
  bool in_place = false;
};

// How `path` is written, from what it is now (see the header).
OutputPlan plan_output(const fs::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) {
      struct stat link {};
      // A dangling symlink: creating the temporary beside it and renaming would drop the link.
      if (::lstat(path.c_str(), &link) == 0) {
        throw Error(path.string() + ": a symbolic link to nothing; not replaced");
      }
      return {path, false};
    }
    io_failure(path, "cannot look at the output", errno);
  }
  if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) return {path, true};
  if (!S_ISREG(st.st_mode)) {
    throw Error(path.string() + ": is " + file_kind(st.st_mode) +
                ", not a file to write; give a file name");
  }
  std::error_code ec;
  if (!fs::is_symlink(path, ec)) return {path, false};
  // /dev/stdout redirected to a file resolves through /proc/self/fd: write through the
  // descriptor's file rather than swapping the file out from under the shell.
  const fs::path first_hop = fs::read_symlink(path, ec);
  const std::string hop = first_hop.string();
  if (hop.starts_with("/proc/") || hop.starts_with("/dev/")) return {path, true};
  const fs::path resolved = fs::canonical(path, ec);
  if (ec) io_failure(path, "cannot resolve the link", ec.value());
  return {resolved, false};
}

}  // namespace

AtomicFileWriter::AtomicFileWriter(const fs::path& path) : path_(path) {
  const OutputPlan plan = plan_output(path);
  target_ = plan.target;
  in_place_ = plan.in_place;
  if (in_place_) {
    fd_ = ::open(target_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    if (fd_ < 0) io_failure(path_, "cannot open for writing", errno);
    return;
  }
  temp_ = target_.string() + kTempMarker + std::to_string(static_cast<long>(::getpid()));
  fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) io_failure(path_, "cannot create", errno);
}

AtomicFileWriter::~AtomicFileWriter() {
  if (fd_ >= 0) {
    ::close(fd_);
    if (!in_place_) ::unlink(temp_.c_str());
  }
}

void AtomicFileWriter::write(std::string_view contents) {
  const char* data = contents.data();
  std::size_t left = contents.size();
  while (left > 0) {
    ssize_t written = ::write(fd_, data, left);
    if (written < 0) {
      if (errno == EINTR) continue;
      // The destructor removes the temporary file.
      throw Error(path_.string() + ": write failed: " + std::strerror(errno), ErrorKind::kFailure);
    }
    data += written;
    left -= static_cast<std::size_t>(written);
  }
}

void AtomicFileWriter::commit() {
  const int fd = fd_;
  fd_ = -1;
  if (in_place_) {
    if (::close(fd) != 0) io_failure(path_, "write failed", errno);
    return;
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const int error = errno;
    ::unlink(temp_.c_str());
    throw Error(path_.string() + ": flush failed: " + std::strerror(error), ErrorKind::kFailure);
  }
  if (::rename(temp_.c_str(), target_.c_str()) != 0) {
    const int error = errno;
    ::unlink(temp_.c_str());
    io_failure(path_, "cannot replace", error);
  }
  fsync_directory(target_.parent_path());
}

void check_output_file(const fs::path& path) {
  const OutputPlan plan = plan_output(path);
  if (plan.in_place) {
    if (::access(plan.target.c_str(), W_OK) != 0)
      io_failure(path, "cannot open for writing", errno);
    return;
  }
  const fs::path parent = plan.target.parent_path().empty() ? "." : plan.target.parent_path();
  struct stat st {};
  if (::stat(parent.c_str(), &st) != 0) io_failure(path, "cannot create", errno);
  if (!S_ISDIR(st.st_mode)) io_failure(path, "cannot create", ENOTDIR);
  if (::access(parent.c_str(), W_OK) != 0) io_failure(path, "cannot create", errno);
}

void remove_stale_temporaries(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    if (entry.path().filename().string().find(kTempMarker) != std::string::npos)
      std::filesystem::remove(entry.path(), ec);
  }
}

void write_file_atomic(const std::filesystem::path& path, std::string_view contents) {
  AtomicFileWriter writer(path);
  writer.write(contents);
  writer.commit();
}

void write_file_atomic(const std::filesystem::path& path, std::span<const std::uint8_t> contents) {
  write_file_atomic(
      path, std::string_view(reinterpret_cast<const char*>(contents.data()), contents.size()));
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot open file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw Error(path.string() + ": read failed", ErrorKind::kFailure);
  return buffer.str();
}

void ensure_directory(const std::filesystem::path& path) {
  std::error_code error;
  std::filesystem::create_directories(path, error);
  if (error) {
    // A file in the way or a path the user cannot write is theirs to fix (exit 2).
    const bool users = error.value() == EEXIST || is_path_problem(error.value());
    throw Error(path.string() + ": cannot create directory: " + error.message(),
                users ? ErrorKind::kBadInput : ErrorKind::kFailure);
  }
}

}  // namespace wheelpose
