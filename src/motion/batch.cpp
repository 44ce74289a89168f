#include "motion/batch.h"

#include <tbb/parallel_for.h>

#include <map>
#include <optional>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose::motion {

BatchResult convert_batch(std::size_t count, const std::function<PositionClip(std::size_t)>& load,
                          const MotionOptions& options,
                          const std::vector<const ClipExporter*>& exporters,
                          const std::filesystem::path& out_dir) {
  ensure_directory(out_dir);
  std::vector<std::optional<SeatedClip>> clips(count);
  std::vector<std::string> errors(count);
  // Each clip depends only on its own input and the seed, so thread scheduling cannot change
  // any output byte.
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t i) {
    try {
      clips[i] = run_motion_pipeline(load(i), options);
    } catch (const Error& e) {
      errors[i] = e.what();
    }
  });

  BatchResult result;
  std::map<std::string, std::size_t> first_with_name;
  for (std::size_t i = 0; i < count; ++i) {
    if (!clips[i]) {
      result.failures.push_back(errors[i]);
      continue;
    }
    const std::string& name = clips[i]->motion.name;
    auto [it, inserted] = first_with_name.emplace(name, i);
    if (!inserted) {
      result.failures.push_back(clips[i]->provenance["source"].get<std::string>() +
                                ": clip name '" + name + "' is already used by input " +
                                std::to_string(it->second + 1));
      clips[i].reset();
    }
  }
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t i) {
    if (!clips[i]) return;
    std::vector<std::filesystem::path> written;
    for (const ClipExporter* exporter : exporters) {
      const auto path = out_dir / (clips[i]->motion.name + exporter->extension);
      try {
        exporter->write(*clips[i], path);
        written.push_back(path);
      } catch (const Error& e) {
        errors[i] = e.what();
        break;
      }
    }
    // A clip is written in every format or in none (e.g. a name that FBX cannot hold).
    if (!errors[i].empty()) {
      for (const auto& path : written) {
        std::error_code ignored;
        std::filesystem::remove(path, ignored);
      }
    }
  });
  for (std::size_t i = 0; i < count; ++i) {
    if (!clips[i]) continue;
    if (!errors[i].empty()) {
      result.failures.push_back(errors[i]);
    } else {
      result.written.push_back(clips[i]->motion.name);
    }
  }
  return result;
}

}  // namespace wheelpose::motion
