#pragma once
// The paper's dataset statistics (§"Statistical Analyses") for any COCO person-keypoint file:
// counts, boxes per image, relative box size, box-centre heatmap, keypoint visibility, keypoint
// locations within the box, and camera placement around each person when images carry it.
//
// Camera metadata (written by our generator; other datasets have none and the camera analysis is
// skipped with a note):
//   image.camera.extrinsics: 16 numbers, the row-major 4x4 camera-to-world matrix (metres,
//     world +Y up, camera looking down its -Z); its translation is the camera position.
//   annotation.keypoints_3d: x, y, z per keypoint in world metres (same order as keypoints).
// Per person, d = camera position - nose; the person's frame is up = +Y, left = horizontal
// direction from right_hip to left_hip, forward = left x up. elevation = asin(d_y / |d|)
// (positive: camera above the nose looking down), azimuth = atan2(d . right, d . forward)
// (positive: camera on the person's right), distance = |d|.

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "dataset/coco_file.h"

namespace wheelpose::dataset {

struct Histogram {
  double lo = 0, hi = 1;
  std::vector<std::int64_t> counts;
  std::int64_t total() const;
  void add(double value);  // values outside [lo, hi] go to the end bins
};

// Counts over [0,1]^2 (normalised x right, y down), nx columns by ny rows, row-major.
struct Grid {
  int nx = 0, ny = 0;
  std::vector<std::int64_t> counts;
  void add(double x, double y);  // clamped into the unit square
  std::int64_t total() const;
  std::pair<int, int> peak() const;  // (column, row) of the largest count, first if tied
};

struct KeypointMap {
  std::string name;
  Grid grid;
};

struct DatasetStats {
  std::string label;   // shown in figures
  std::string source;  // file path
  std::int64_t images = 0;
  std::int64_t instances = 0;           // annotations with iscrowd = 0
  std::int64_t labelled_instances = 0;  // instances with at least one keypoint v > 0
  std::int64_t images_with_people = 0;
  std::vector<std::int64_t> boxes_per_image;  // [k-1] = images with k instances (k >= 1)
  Histogram box_size;                         // sqrt(box w*h / image w*h), 20 bins on [0, 1]
  Grid box_centre;                            // 32 x 32 over the normalised image
  std::vector<std::string> keypoint_names;
  // Per keypoint, over labelled instances: counts of v = 0 (not visible), 1 (occluded), 2.
  std::vector<std::array<std::int64_t, 3>> visibility;
  std::vector<KeypointMap> keypoint_maps;  // 24 x 24 over the normalised box, v > 0 only
  bool has_camera = false;
  std::string camera_note;  // why the camera analysis is missing or partial
  Histogram elevation, azimuth, distance;
  std::vector<std::array<double, 3>> directions;  // unit (right, up, forward), every 100th person
};

// `root` must be usable (require_usable).
DatasetStats compute_stats(const json& root, const std::string& source, const std::string& label);

json stats_to_json(const DatasetStats& stats);

}  // namespace wheelpose::dataset
