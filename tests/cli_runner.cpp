#include "cli_runner.h"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace wheelpose::testing {

CliResult run_wheelpose(const std::string& args, const std::string& env) {
  const std::string command = (env.empty() ? "" : "env " + env + " ") +
                              std::string(WHEELPOSE_BINARY) + " " + args + " 2>&1";
  CliResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer{};
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

KilledRuns run_killed_until_done(const std::function<std::string()>& args, double first_delay,
                                 double step) {
  KilledRuns runs;
  for (double delay = first_delay;; delay += step) {
    char timeout[64];
    std::snprintf(timeout, sizeof timeout, "timeout -s KILL %.2f ", delay);
    const std::string command =
        timeout + std::string(WHEELPOSE_BINARY) + " " + args() + " > /dev/null 2>&1";
    const int status = std::system(command.c_str());
    if (!WIFEXITED(status)) {
      runs.failure = "the shell did not exit normally";
      return runs;
    }
    if (WEXITSTATUS(status) == 0) return runs;
    if (WEXITSTATUS(status) != 137) {
      runs.failure =
          "a run failed (exit " + std::to_string(WEXITSTATUS(status)) + ") instead of being killed";
      return runs;
    }
    if (++runs.kills >= 60) {
      runs.failure = "60 kills and no run completed";
      return runs;
    }
  }
}

std::filesystem::path fresh_temp_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() /
             ("wheelpose_" + name + "_" + std::to_string(static_cast<long>(::getpid())));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

std::filesystem::path coco_sample_dir() {
  return std::filesystem::path(WHEELPOSE_SHARED_DIR) / "data" / "coco-sample";
}

std::filesystem::path write_coco_sample_gt(const std::filesystem::path& dir, bool copy_image) {
  const std::string image_file = "000000000785.jpg";
  nlohmann::json gt =
      nlohmann::json::parse(read_text(coco_sample_dir() / "person_keypoints_sample.json"));
  nlohmann::json images = nlohmann::json::array(), annotations = nlohmann::json::array();
  for (const nlohmann::json& image : gt["images"]) {
    if (image["file_name"] == image_file) images.push_back(image);
  }
  for (const nlohmann::json& a : gt["annotations"]) {
    if (a["image_id"] == images.at(0)["id"]) annotations.push_back(a);
  }
  gt["images"] = images;
  gt["annotations"] = annotations;
  if (copy_image) std::filesystem::copy_file(coco_sample_dir() / image_file, dir / image_file);
  std::ofstream(dir / "gt.json") << gt.dump();
  return dir / "gt.json";
}

double printed_ap(const std::string& eval_output) {
  const std::string line = "IoU=0.50:0.95 | area=   all | maxDets= 20 ] = ";
  const auto at = eval_output.find(line);
  return at == std::string::npos ? -1.0 : std::stod(eval_output.substr(at + line.size(), 5));
}

}  // namespace wheelpose::testing
