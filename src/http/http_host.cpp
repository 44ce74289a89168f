#include "http/http_host.h"

#include <pthread.h>

#include <thread>

#include "core/error.h"

namespace wheelpose::http {

sigset_t block_stop_signals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  return signals;
}

void set_security_headers(httplib::Server& http, PagePolicy policy) {
  const std::string images =
      policy.blob_images ? "img-src 'self' data: blob:; " : "img-src 'self' data:; ";
  const std::string wasm = policy.wasm ? "script-src 'self' 'wasm-unsafe-eval'; " : "";
  http.set_default_headers({
      {"Content-Security-Policy",
       "default-src 'self'; " + images + wasm +
           "object-src 'none'; frame-ancestors 'none'; base-uri 'none'; form-action 'none'"},
      {"X-Content-Type-Options", "nosniff"},
      {"Referrer-Policy", "no-referrer"},
      {"X-Frame-Options", "DENY"},
  });
}

namespace {

constexpr int kWorkers = 64;
constexpr time_t kReadTimeoutSeconds = 2;
constexpr time_t kWriteTimeoutSeconds = 10;
constexpr time_t kKeepAliveSeconds = 2;

// What the pre-routing check refuses, or "" for a request that may go on.
std::string malformed(const httplib::Request& req) {
  for (const unsigned char c : req.path) {
    if (c < 0x20 || c == 0x7F) return "a control byte in the path";
  }
  const auto lengths = req.headers.equal_range("Content-Length");
  for (auto it = lengths.first; it != lengths.second; ++it) {
    const std::string& v = it->second;
    // Digits only, and few enough that the value fits in 64 bits without wrapping.
    if (v.empty() || v.size() > 18 || v.find_first_not_of("0123456789") != std::string::npos) {
      return "a malformed Content-Length";
    }
  }
  return "";
}

}  // namespace

void set_connection_limits(httplib::Server& http, std::size_t max_request_bytes) {
  http.new_task_queue = [] { return new httplib::ThreadPool(kWorkers); };
  http.set_read_timeout(kReadTimeoutSeconds, 0);
  http.set_write_timeout(kWriteTimeoutSeconds, 0);
  http.set_keep_alive_timeout(kKeepAliveSeconds);
  http.set_payload_max_length(max_request_bytes);
  http.set_pre_routing_handler([](const httplib::Request& req, httplib::Response& res) {
    const std::string why = malformed(req);
    if (why.empty()) return httplib::Server::HandlerResponse::Unhandled;
    res.status = 400;
    res.set_header("Connection", "close");
    res.set_content("bad request: " + why + "\n", "text/plain; charset=utf-8");
    return httplib::Server::HandlerResponse::Handled;
  });
}

std::string bind_server(httplib::Server& http, const std::string& bind, int port) {
  if (port == 0) {
    port = http.bind_to_any_port(bind);
    if (port < 0) throw Error("cannot bind " + bind, ErrorKind::kFailure);
  } else if (!http.bind_to_port(bind, port)) {
    throw Error("cannot listen on " + bind + ":" + std::to_string(port) +
                    " (in use, or not an address of this machine)",
                ErrorKind::kFailure);
  }
  const std::string host = bind == "0.0.0.0" ? "127.0.0.1" : bind;
  return "http://" + host + ":" + std::to_string(port);
}

void listen_until_signal(httplib::Server& http, const sigset_t& signals) {
  std::thread stopper([&http, signals] {
    int sig = 0;
    sigwait(&signals, &sig);
    http.stop();
  });
  http.listen_after_bind();
  // listen returned on its own (not by a signal): wake the waiting thread.
  if (stopper.joinable()) {
    pthread_kill(stopper.native_handle(), SIGTERM);
    stopper.join();
  }
}

}  // namespace wheelpose::http
