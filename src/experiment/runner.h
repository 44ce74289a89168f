#pragma once
// Runs a plan's steps in order as child `wheelpose` processes, each logging to its folder's
// log.txt. A finished step leaves done.json (its commands and wall time) and is never run
// again; an interrupted training or generation continues with --resume, any other unfinished
// step starts over in an empty folder.

#include <filesystem>
#include <string>
#include <vector>

#include "experiment/plan.h"

namespace wheelpose::experiment {

struct StepRecord {
  std::string id, kind, label;
  double seconds = 0;  // wall time when it ran (recorded once, kept across resumes)
};

// `program` is the wheelpose binary. Throws Error (exit 1) naming the failed step, the last line
// of its log and the log's path.
std::vector<StepRecord> run_plan(const Plan& plan, const std::filesystem::path& program);

}  // namespace wheelpose::experiment
