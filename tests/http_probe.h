#pragma once
// The toolkit's web servers (review, demo) as child processes of a test, and raw HTTP on
// loopback: half-sent requests that hold a connection open, and requests httplib's client
// would never send (a negative Content-Length, a NUL in the path).

#include <signal.h>
#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace wheelpose::testing {

// A free TCP port on 127.0.0.1 (free when asked; the server binds it soon after).
int free_port();

// `wheelpose <args>` as a child process, its output in `log`; start() returns once it prints
// "listening on" (and fails the test if it never does). Stopped with SIGTERM when destroyed.
class ChildServer {
 public:
  ChildServer() = default;
  ~ChildServer() { stop(SIGTERM); }
  ChildServer(const ChildServer&) = delete;
  ChildServer& operator=(const ChildServer&) = delete;

  void start(const std::vector<std::string>& args, const std::filesystem::path& log);
  void stop(int signal);
  const std::string& output() const { return output_; }

 private:
  pid_t pid_ = -1;
  std::string output_;
};

// A connection to 127.0.0.1:`port` that sent `bytes` and waits (-1 if it could not connect).
int open_connection(int port, const std::string& bytes);

// Sends `request` on a new connection and returns what came back within `timeout_seconds`
// (until the server closes or one full response has arrived).
std::string exchange(int port, const std::string& request, double timeout_seconds);

// The status code of a complete response's first line, or -1 if none arrived.
int status_of(const std::string& response);

// The server on `port` under attack (gtest expectations): `slow_clients` connections that send
// half a request line and wait must not keep a normal GET of `page` from being answered within
// a second; a Content-Length that is negative, too large or not a number, and a path with a NUL
// or a line feed get 400.
void expect_slow_and_malformed_clients_refused(int port, const std::string& page, int slow_clients);

}  // namespace wheelpose::testing
