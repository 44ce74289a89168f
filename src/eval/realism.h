#pragma once
// How a model trained on real photos sees a dataset's people (`wheelpose realism`): for every
// labelled person large enough to judge, is the model's best match there (OKS ≥ 0.5, or box IoU
// ≥ 0.5 for a set labelled by box only), and how close is it. Split by every attribute the dataset
// records per person and per image (the generator's randomizer draws: environment, wheelchair type,
// clothing assets, body, camera, …) and by what shows of the person (visible keypoints, whether the
// face shows) so a user sees which scene choices look fake to a real-photo model. Run on a real
// keypoint set it gives the reference a photo-real render should reach.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/coco_data.h"
#include "core/keypoint_template.h"

namespace wheelpose::eval {

struct RealismOptions {
  double min_height_px = 120;  // the person's box height
  int min_keypoints = 10;      // labelled keypoints (v > 0)
  // Keypoints labelled visible (v = 2); 0 judges everyone. A renderer labels every hidden joint,
  // an annotator mostly what shows, so this compares a render with photos at equal visibility.
  int min_visible_keypoints = 0;
  double found_oks = 0.5;   // a best match at least this close counts as found
  int numeric_buckets = 4;  // numeric attributes split at their quantiles
  // Judge by box instead: found when the model's best box overlaps the labelled one at IoU ≥
  // found_iou, whatever its score. Keypoint counts are not asked for, so a set labelled by box
  // only (photos of wheelchair users, the box holding the chair) is a reference too.
  bool boxes = false;
  double found_iou = 0.5;
  // Leave out people whose box touches the image border: cut by the frame, as a photographer
  // rarely leaves someone and a renderer's camera often does.
  bool whole_in_frame = false;
};

// Width and height of each image, by id (from the COCO file's `images`; 0 where not given).
struct ImageSize {
  double width = 0, height = 0;
};
using ImageSizes = std::unordered_map<std::int64_t, ImageSize>;
ImageSizes image_sizes(const nlohmann::json& root);

// Whether `person` is judged: not a crowd region, its box at least min_height_px tall, (judging
// keypoints) at least min_keypoints labelled and min_visible_keypoints of them visible, and (with
// whole_in_frame) its box clear of the image border. Throws Error naming the image when
// whole_in_frame needs a size the file does not give.
bool realism_judges(const coco::GtAnnotation& person, const RealismOptions& options,
                    const ImageSizes& sizes);

// The people of one attribute value (or of the whole set: key and bucket "all").
struct RealismGroup {
  std::string key, bucket;
  int people = 0, found = 0;
  double oks_sum = 0;  // best-match OKS (box IoU when judging boxes), 0 where nothing was found
  double found_share() const { return people ? static_cast<double>(found) / people : 0; }
  double mean_oks() const { return people ? oks_sum / people : 0; }
};

struct RealismReport {
  RealismGroup overall;
  std::vector<RealismGroup> groups;  // by key, then bucket (numeric buckets in value order)
  // People left out, and why.
  int too_small = 0, too_few_keypoints = 0, too_few_visible = 0, crowd = 0, cut_by_frame = 0;
  bool boxes = false;  // judged by box: the means are box IoU, not OKS
};

// `root` is the GT file as parsed JSON (for the attributes), `gt` the same parsed as COCO, and
// `results` the model's detections (with keypoints unless judging boxes). Throws Error if they
// lack what is judged.
RealismReport measure_realism(const nlohmann::json& root, const coco::CocoGroundTruth& gt,
                              const coco::CocoResults& results,
                              const KeypointTemplate& keypoint_template,
                              const RealismOptions& options);

// The report as Markdown tables and as JSON (every group with its counts).
std::string realism_markdown(const RealismReport& report, const std::string& title);
nlohmann::json realism_json(const RealismReport& report, const RealismOptions& options);

}  // namespace wheelpose::eval
