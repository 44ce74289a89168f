#pragma once
// Running the pipeline over many clips at once (in parallel, deterministically): each clip is
// converted and written independently; a broken clip is reported and skipped, never half-written.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "motion/exporters.h"
#include "motion/pipeline.h"

namespace wheelpose::motion {

struct BatchResult {
  std::vector<std::string> written;  // clip names converted, in input order
  std::vector<std::string> failures;  // one line per rejected clip: "<source>: <reason>"
};

// `load(i)` produces the i-th PositionClip (it may throw Error: that clip fails alone).
// Outputs go to `out_dir/<clip name><extension>` for every exporter.
BatchResult convert_batch(std::size_t count, const std::function<PositionClip(std::size_t)>& load,
                          const MotionOptions& options,
                          const std::vector<const ClipExporter*>& exporters,
                          const std::filesystem::path& out_dir);

}  // namespace wheelpose::motion
