#pragma once
// `wheelpose review serve`: the study's HTTP server. Static page from web/review/, JSON API under /api.
// Participant endpoints take the participant's token (Authorization: Bearer <token>) and only
// ever touch that participant's rows; /api/admin/* take the admin token. Every body is validated
// before it reaches the store; bodies over 64 KiB are refused.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace wheelpose::review {

struct ServeOptions {
  std::vector<std::filesystem::path> clip_folders;
  std::filesystem::path db;
  std::string bind = "127.0.0.1";
  int port = 8080;                // 0 picks a free port (printed)
  std::filesystem::path web_dir;  // empty: the source tree's web/review
};

inline constexpr std::size_t kMaxRequestBytes = 64 * 1024;

// Runs until SIGINT/SIGTERM. Prints the URL (and the admin token when it created the database).
void serve(const ServeOptions& options);

// The link a participant opens (token in the fragment, so it never reaches logs or referrers).
std::string participant_link(const std::string& base_url, const std::string& token);

}  // namespace wheelpose::review
