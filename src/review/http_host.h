#pragma once
// What every local web page of the toolkit needs from cpp-httplib (review, demo): strict
// security headers, binding to an address (port 0 picks a free one) and serving until SIGINT
// or SIGTERM.

#include <httplib.h>
#include <signal.h>

#include <string>

namespace wheelpose::review {

// Blocks SIGINT and SIGTERM in this thread and every thread it starts later; call first.
sigset_t block_stop_signals();

// Content-Security-Policy (self only; images also from data: and blob: when allow_blob_images),
// nosniff, no referrer, no framing.
void set_security_headers(httplib::Server& http, bool allow_blob_images = false);

// Binds `bind`:`port` (0 = any free port) and returns the page's URL. Throws Error (exit 1)
// when the address cannot be bound.
std::string bind_server(httplib::Server& http, const std::string& bind, int port);

// Serves until one of `signals` arrives.
void listen_until_signal(httplib::Server& http, const sigset_t& signals);

}  // namespace wheelpose::review
