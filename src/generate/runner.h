#pragma once
// Running a scenario: frames [0, frames) split into contiguous shards, rendered and labelled in
// parallel, each frame written as an image plus a label fragment (labels/NNNNNN.json) the moment
// it is done, then the fragments assembled into annotations.json. A frame's bytes depend only
// on (scenario, seed, frame index, clips), so thread count, shard split and resuming after a
// kill never change the output; `wheelpose coco merge` of the shards' annotations.json equals
// a single run's.
//
// Output folder: images/NNNNNN.jpg|png, labels/NNNNNN.json, annotations.json (COCO, canonical
// form), scenario.json (resolved settings, seed, frame count, clip names), and with
// labels.ground_truth_maps maps/NNNNNN_{depth,normals,instance,semantic}.png.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "generate/motion_source.h"
#include "generate/scenario.h"

namespace wheelpose::generate {

struct RunOptions {
  std::filesystem::path out;
  std::int64_t frames = 100;
  std::uint64_t seed = 0;
  int shard_index = 0, shard_count = 1;
  int threads = 0;  // 0 = every core
  std::string format = "jpg";
  bool resume = false;
  MotionSource motions;
  std::optional<std::filesystem::path> assets;

  // Throws Error naming the first option that is out of range (run_generate calls it).
  void check() const;
};

struct RunSummary {
  std::int64_t first_frame = 0, end_frame = 0;  // this shard's frames [first, end)
  std::int64_t rendered = 0, resumed = 0;       // rendered now, found done
  std::int64_t images = 0, annotations = 0, dropped_people = 0;
  double seconds = 0;
  // Milliseconds per rendered frame in each stage, summed over the threads that ran them (so
  // with T threads busy they add up to about T × the wall time per frame): drawing the
  // randomizers, building the scene (people, wheelchairs, room), building the ray-tracing
  // structure, rendering, labelling, and encoding and writing the files.
  struct StageMs {
    double draft = 0, build = 0, bvh = 0, render = 0, label = 0, write = 0;
  } stage_ms;
};

// Progress callback: frames done (incl. resumed) of the shard's total.
using ProgressFn = std::function<void(std::int64_t done, std::int64_t total)>;

// This shard's frames: [i·n/N, (i+1)·n/N).
std::pair<std::int64_t, std::int64_t> shard_range(std::int64_t frames, int index, int count);

RunSummary run_generate(const Scenario& scenario, const RunOptions& options,
                        const ProgressFn& progress = {});

// Image file name of a frame: zero-padded to 6 digits (more when needed).
std::string frame_stem(std::int64_t frame);

}  // namespace wheelpose::generate
