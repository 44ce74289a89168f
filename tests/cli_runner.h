#pragma once
// Runs the built `wheelpose` binary for end-to-end tests and captures its output and exit code.

#include <filesystem>
#include <functional>
#include <string>

namespace wheelpose::testing {

struct CliResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr interleaved
};

// `args` is appended to the binary path as shell words (quote paths yourself if needed);
// `env`, shell words of VAR=value, is set for that run only.
CliResult run_wheelpose(const std::string& args, const std::string& env = "");

// Runs `wheelpose <args()>` again and again, each run killed with SIGKILL after a delay that
// grows from `first_delay` by `step` seconds, until one exits 0. `args` is asked before every
// run (it may add --resume once there is something to resume). `failure` is set when a run
// exits otherwise than 0 or by the kill, or after 60 kills.
struct KilledRuns {
  int kills = 0;
  std::string failure;
};
KilledRuns run_killed_until_done(const std::function<std::string()>& args, double first_delay,
                                 double step);

// A fresh empty directory under the system temp dir, unique per test.
std::filesystem::path fresh_temp_dir(const std::string& name);

// The whole file as bytes ("" if it cannot be read).
std::string read_text(const std::filesystem::path& path);

// ../shared/data/coco-sample: a COCO keypoint file and one of its images, 000000000785.jpg.
std::filesystem::path coco_sample_dir();

// The sample's ground truth cut to that one image, written as `dir`/gt.json (returned); with
// `copy_image` the image is copied into `dir` too, so `dir` is a dataset on its own.
std::filesystem::path write_coco_sample_gt(const std::filesystem::path& dir, bool copy_image);

// The AP of the first "IoU=0.50:0.95 | area=   all | maxDets= 20" line of `wheelpose eval`'s
// printed summary (keypoint AP); -1 when the output has none.
double printed_ap(const std::string& eval_output);

}  // namespace wheelpose::testing
