#pragma once
// Training data for `wheelpose train`: COCO person-keypoint files read into images with their
// people, and one augmented network input per (seed, step, slot), built the same way on any
// thread. Torch-free.

#include <array>
#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/coco_data.h"

namespace wheelpose::learn {

// One `--train` argument: "A.json" or "A.json:weight" (weight > 0: how often its images are
// drawn relative to the other files', per image).
struct TrainSource {
  std::filesystem::path coco;
  double weight = 1;
};
TrainSource parse_train_source(const std::string& text);

struct TrainPerson {
  coco::Box box;                       // pixels
  std::array<double, 51> keypoints{};  // x, y, v (COCO-17); v = 0: not labelled
  // A crowd region (COCO iscrowd 1): no targets, and its cells carry no heatmap loss, so people
  // a set leaves unlabelled there are not taught as background.
  bool ignore = false;
};

struct TrainImage {
  std::filesystem::path file;
  std::vector<TrainPerson> people;  // people with a box, and crowd regions (ignore)
  double weight = 1;                // its source's weight
};

struct TrainSet {
  std::vector<TrainImage> images;
  int labelled_people = 0;  // people with at least one labelled keypoint
};

// Where a COCO file's images are: `<dir of the json>/images/` when that folder exists (a
// generated dataset), else the json's own folder.
std::filesystem::path image_root(const std::filesystem::path& coco);

// Reads every source. Images are looked up in `<dir of the json>/images/` when that folder
// exists (a generated dataset), else beside the json. Throws Error naming the file for an
// unreadable or invalid COCO file, a missing image, or a set with no labelled keypoint.
TrainSet load_train_set(const std::vector<TrainSource>& sources);

struct AugmentOptions {
  int input_size = 256;  // square network input
  // People appear at the scale `predict` sees them: the image scaled so its longer side is
  // `target_longer_side`, times a random factor in [scale_min, scale_max] (log-uniform).
  int target_longer_side = 640;
  double scale_min = 0.7, scale_max = 1.4;
  // When person_size_max > 0: instead, the chosen person's longer box side in the input is
  // log-uniform in [person_size_min, person_size_max] pixels, whatever the frame's scale — real
  // photos show people from small to filling the frame, our frames mostly small.
  double person_size_min = 0, person_size_max = 0;
  double shift_fraction = 0.25;  // the person's centre lands within ± this × input of the middle
  double rotate_degrees = 15;    // uniform in ±this
  double flip_probability = 0.5;
  double color_jitter = 0.3;  // brightness, contrast, saturation each × [1 - j, 1 + j]
  double blur_probability = 0.2;
  double jpeg_probability = 0.3;  // re-encode at quality 40..95
};

struct TrainSample {
  cv::Mat rgb;                      // input_size² CV_8UC3 RGB
  std::vector<TrainPerson> people;  // in input pixels; keypoints outside the input get v = 0
};

// The crop around a randomly chosen person of `image` (already decoded to RGB), flipped (left
// and right keypoints swapped by `flip_pairs`), rotated, scaled, colour-jittered, blurred and
// JPEG-degraded, all drawn from `random_seed`'s stream for `key` (deterministic).
TrainSample augment(const cv::Mat& rgb, const std::vector<TrainPerson>& people,
                    const std::vector<std::pair<int, int>>& flip_pairs,
                    const AugmentOptions& options, std::uint64_t random_seed, std::uint64_t key);

// Which image slot `slot` of optimizer step `step` uses: a weighted draw, deterministic in
// (seed, step, slot). `cumulative_weights` is the running sum of the images' weights.
std::size_t pick_image(const std::vector<double>& cumulative_weights, std::uint64_t seed,
                       std::int64_t step, int slot);

}  // namespace wheelpose::learn
