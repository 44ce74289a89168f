#pragma once
// What every local web page of the toolkit needs from cpp-httplib (review, demo): strict
// security headers, binding to an address (port 0 picks a free one) and serving until SIGINT
// or SIGTERM.

#include <httplib.h>
#include <signal.h>

#include <cstddef>
#include <string>

namespace wheelpose::http {

// Blocks SIGINT and SIGTERM in this thread and every thread it starts later; call first.
sigset_t block_stop_signals();

// What a page may do beyond loading its own files.
struct PagePolicy {
  bool blob_images = false;  // images from blob: URLs (a photo the user drops)
  bool wasm = false;         // compiling WebAssembly (TF.js's wasm backend)
};

// Content-Security-Policy (self only, plus what `policy` allows), nosniff, no referrer, no
// framing.
void set_security_headers(httplib::Server& http, PagePolicy policy = {});

// Connection limits and request checks both servers share, so that neither a slow client nor a
// malformed request holds or confuses them: 64 workers (one per open connection), a client
// silent for 2 s while a request is read is dropped, idle keep-alive connections close after
// 2 s; bodies over `max_request_bytes`, a Content-Length that is not a plain decimal number,
// and a path holding a NUL or other control byte get 400 before any handler runs.
void set_connection_limits(httplib::Server& http, std::size_t max_request_bytes);

// Binds `bind`:`port` (0 = any free port) and returns the page's URL. Throws Error (exit 1)
// when the address cannot be bound.
std::string bind_server(httplib::Server& http, const std::string& bind, int port);

// Serves until one of `signals` arrives.
void listen_until_signal(httplib::Server& http, const sigset_t& signals);

}  // namespace wheelpose::http
