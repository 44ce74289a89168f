#pragma once
// Progress of a long command: a bar with rate and ETA on a terminal; a log line every 10 % (or
// 30 s) otherwise, e.g. "generate: 10/100 frames, 2.17 frames/s, ETA 41 s".

#include <chrono>
#include <cstdint>
#include <string>

namespace wheelpose::app {

class Progress {
 public:
  // `what` starts the log line ("generate"), `unit` names the items ("frames").
  Progress(std::string what, std::string unit);

  void operator()(std::int64_t done, std::int64_t total);

 private:
  std::string what_, unit_;
  bool tty_;
  std::chrono::steady_clock::time_point start_;
  bool first_ = true;
  std::int64_t first_done_ = 0, last_decile_ = -1;
  double last_line_ = 0;
};

}  // namespace wheelpose::app
