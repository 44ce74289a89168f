#include "http_probe.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "cli_runner.h"

namespace wheelpose::testing {
namespace {

sockaddr_in loopback(int port) {
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  return addr;
}

}  // namespace

int free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr = loopback(0);
  ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  ::close(fd);
  return ntohs(addr.sin_port);
}

void ChildServer::start(const std::vector<std::string>& args, const std::filesystem::path& log) {
  std::vector<std::string> argv_strings = {WHEELPOSE_BINARY};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  pid_ = ::fork();
  if (pid_ == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    std::vector<char*> argv;
    for (auto& a : argv_strings) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  for (int i = 0; i < 400; ++i) {
    const std::string text = read_text(log);
    if (text.find("listening on") != std::string::npos) {
      output_ = text;
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  FAIL() << "server did not start: " << read_text(log);
}

void ChildServer::stop(int signal) {
  if (pid_ <= 0) return;
  ::kill(pid_, signal);
  int status = 0;
  ::waitpid(pid_, &status, 0);
  pid_ = -1;
}

int open_connection(int port, const std::string& bytes) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const sockaddr_in addr = loopback(port);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return -1;
  }
  if (!bytes.empty()) ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
  return fd;
}

std::string exchange(int port, const std::string& request, double timeout_seconds) {
  const int fd = open_connection(port, request);
  if (fd < 0) return "";
  std::string response;
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::milliseconds(static_cast<int>(timeout_seconds * 1000));
  char buffer[4096];
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) break;
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n <= 0) break;
    response.append(buffer, static_cast<std::size_t>(n));
    // One whole response: its headers and as many body bytes as they announce.
    const std::size_t end = response.find("\r\n\r\n");
    if (end == std::string::npos) continue;
    const std::size_t at = response.find("Content-Length: ");
    if (at == std::string::npos || at > end) break;
    const std::size_t length = std::stoul(response.substr(at + 16));
    if (response.size() >= end + 4 + length) break;
  }
  ::close(fd);
  return response;
}

int status_of(const std::string& response) {
  if (response.rfind("HTTP/1.", 0) != 0 || response.size() < 12) return -1;
  return std::atoi(response.substr(9, 3).c_str());
}

void expect_slow_and_malformed_clients_refused(int port, const std::string& page,
                                               int slow_clients) {
  std::vector<int> slow;
  for (int i = 0; i < slow_clients; ++i)
    slow.push_back(open_connection(port, "GET / HTTP/1.1\r\n"));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // let the server take them all
  const auto start = std::chrono::steady_clock::now();
  const std::string normal = exchange(
      port, "GET " + page + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n", 5.0);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(status_of(normal), 200) << normal.substr(0, 200);
  EXPECT_LT(seconds, 1.0) << "a normal request waited behind " << slow_clients
                          << " slow connections";

  for (const std::string length : {"-1", "99999999999999999999", "12abc", "1 2"}) {
    const std::string response = exchange(
        port, "GET " + page + " HTTP/1.1\r\nHost: x\r\nContent-Length: " + length + "\r\n\r\n",
        3.0);
    EXPECT_EQ(status_of(response), 400) << "Content-Length '" << length << "': " << response;
  }
  for (const std::string path : {"/index.html%00.js", "/index.html%0a", "/%7f"}) {
    const std::string response =
        exchange(port, "GET " + path + " HTTP/1.1\r\nHost: x\r\n\r\n", 3.0);
    EXPECT_EQ(status_of(response), 400) << path << ": " << response.substr(0, 200);
  }
  for (const int fd : slow) {
    if (fd >= 0) ::close(fd);
  }
}

}  // namespace wheelpose::testing
