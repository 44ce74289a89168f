#include "progress.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>

namespace wheelpose::app {

Progress::Progress(std::string what, std::string unit)
    : what_(std::move(what)),
      unit_(std::move(unit)),
      tty_(::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()) {}

void Progress::operator()(std::int64_t done, std::int64_t total) {
  if (first_) {
    first_ = false;
    first_done_ = done;
  }
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed > 0 ? static_cast<double>(done - first_done_) / elapsed : 0;
  const double eta = rate > 0 ? static_cast<double>(total - done) / rate : 0;
  if (tty_) {
    const int width = 30;
    const int filled = total > 0 ? static_cast<int>(width * done / total) : width;
    std::fprintf(stderr, "\r[%s%s] %lld/%lld  %.2f %s/s  ETA %.0f s ",
                 std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(),
                 static_cast<long long>(done), static_cast<long long>(total), rate, unit_.c_str(),
                 eta);
    if (done == total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
    return;
  }
  const std::int64_t decile = total > 0 ? 10 * done / total : 10;
  if (decile > last_decile_ || elapsed - last_line_ >= 30 || done == total) {
    last_decile_ = decile;
    last_line_ = elapsed;
    spdlog::info("{}: {}/{} {}, {:.2f} {}/s, ETA {:.0f} s", what_, done, total, unit_, rate, unit_,
                 eta);
  }
}

}  // namespace wheelpose::app
