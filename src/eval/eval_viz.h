#pragma once
// Overlay images for eyeballing an evaluation: GT (white), baseline (red) and ours (green)
// skeletons and boxes. Labelled-visible GT keypoints (v = 2) are filled dots, labelled-occluded
// ones (v = 1) hollow rings; detections are drawn when their score is at least `min_score`.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/coco_data.h"
#include "core/keypoint_template.h"

namespace wheelpose::eval {

// Which GT images to draw: evenly spaced over the images sorted by id, or the ones where the
// results do best or worst (image_pose_scores).
enum class VizPick { kSpread, kBest, kWorst };

// "spread", "best", "worst": the command-line names.
const std::map<std::string, VizPick>& viz_pick_names();

struct VizOptions {
  int count = 0;  // images to draw
  VizPick pick = VizPick::kSpread;
  std::filesystem::path images_dir;
  std::filesystem::path out_dir;  // written as out_dir/<file stem>.jpg
  double min_score = 0.5;
};

// Returns the written files. A missing or unreadable image throws Error naming it.
std::vector<std::filesystem::path> write_overlays(const coco::CocoGroundTruth& gt,
                                                  const coco::CocoResults& ours,
                                                  const coco::CocoResults* baseline,
                                                  const KeypointTemplate& keypoint_template,
                                                  const VizOptions& options);

// The GT image positions write_overlays picks: i * n / count for i < min(count, n).
std::vector<int> evenly_spaced(int n, int count);

// Per GT image (by position): the mean over its non-crowd people with labelled keypoints of the
// best OKS any detection in the image reaches (0 when none), so an image where every person is
// found well scores near 1. NaN for an image without such people. Results need keypoints.
std::vector<double> image_pose_scores(const coco::CocoGroundTruth& gt,
                                      const coco::CocoResults& results,
                                      const KeypointTemplate& keypoint_template);

// Up to `count` positions of images with a score, best (highest) or worst first; ties by position.
std::vector<int> ranked_positions(const std::vector<double>& scores, int count, VizPick pick);

}  // namespace wheelpose::eval
