#include "review/http_host.h"

#include <pthread.h>

#include <thread>

#include "core/error.h"

namespace wheelpose::review {

sigset_t block_stop_signals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  return signals;
}

void set_security_headers(httplib::Server& http, bool allow_blob_images) {
  const std::string images =
      allow_blob_images ? "img-src 'self' data: blob:; " : "img-src 'self' data:; ";
  http.set_default_headers({
      {"Content-Security-Policy",
       "default-src 'self'; " + images +
           "object-src 'none'; frame-ancestors 'none'; base-uri 'none'; form-action 'none'"},
      {"X-Content-Type-Options", "nosniff"},
      {"Referrer-Policy", "no-referrer"},
      {"X-Frame-Options", "DENY"},
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

}  // namespace wheelpose::review
