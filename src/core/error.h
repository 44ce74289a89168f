#pragma once
// Errors that cross module boundaries. Bad input (files, configs, requests) throws
// wheelpose::Error; only main() and the HTTP layer catch it. Programming errors use CHECK.

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace wheelpose {

enum class ErrorKind {
  kBadInput,  // the user's file, flag or config is wrong: exit code 2
  kFailure,   // the input was fine but the job could not be done (I/O, resources): exit code 1
};

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message, ErrorKind kind = ErrorKind::kBadInput)
      : std::runtime_error(message), kind_(kind) {}
  ErrorKind kind() const { return kind_; }
  int exit_code() const { return kind_ == ErrorKind::kBadInput ? 2 : 1; }

 private:
  ErrorKind kind_;
};

[[noreturn]] inline void check_failed(const char* expr, const char* file, int line) {
  std::fprintf(stderr, "internal error: CHECK(%s) failed at %s:%d\n", expr, file, line);
  std::abort();
}

}  // namespace wheelpose

#define WHEELPOSE_CHECK(expr) \
  ((expr) ? (void)0 : ::wheelpose::check_failed(#expr, __FILE__, __LINE__))
