#pragma once
// Overlay images for eyeballing an evaluation: GT (white), baseline (red) and ours (green)
// skeletons and boxes. Labelled-visible GT keypoints (v = 2) are filled dots, labelled-occluded
// ones (v = 1) hollow rings; detections are drawn when their score is at least `min_score`.

#include <filesystem>
#include <vector>

#include "eval/coco_data.h"
#include "eval/keypoint_template.h"

namespace wheelpose::eval {

struct VizOptions {
  int count = 0;  // images to draw, evenly spaced over the GT images sorted by id
  std::filesystem::path images_dir;
  std::filesystem::path out_dir;  // written as out_dir/<file stem>.jpg
  double min_score = 0.5;
};

// Returns the written files. A missing or unreadable image throws Error naming it.
std::vector<std::filesystem::path> write_overlays(const CocoGroundTruth& gt,
                                                  const CocoResults& ours,
                                                  const CocoResults* baseline,
                                                  const KeypointTemplate& keypoint_template,
                                                  const VizOptions& options);

// The GT image positions write_overlays picks: i * n / count for i < min(count, n).
std::vector<int> evenly_spaced(int n, int count);

}  // namespace wheelpose::eval
