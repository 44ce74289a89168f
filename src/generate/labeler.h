#pragma once
// COCO person-keypoint labels of one rendered frame, exact from the renderer's ground truth.
//
// Projection: the renderer's pinhole, fx = fy = (height / 2) / tan(vfov / 2), cx = width / 2,
// cy = height / 2, in continuous pixel coordinates (pixel (i, j) covers [i, i + 1) × [j, j + 1)).
// Visibility: 0 = outside the image, behind the camera or on a missing limb (written 0, 0, 0);
// 1 = the depth buffer at the keypoint's pixel holds a surface nearer than the keypoint by more
// than its tolerance (template tolerance × person scale); 2 = otherwise.

#include <nlohmann/json.hpp>
#include <vector>

#include "generate/frame_builder.h"
#include "render/renderer.h"

namespace wheelpose::generate {

struct LabelOptions {
  int min_visible_pixels = 50;  // people with fewer visible mask pixels are not labelled
  bool segmentation = true;     // polygon outlines of the visible mask
  // A seated person's `bbox` is the box around their visible pixels and their wheelchair's
  // (the convention of detection sets that find wheelchair users, such as lexra/wheelchair's);
  // the person's own box is kept as `bbox_person`.
  bool box_holds_wheelchair = false;
};

struct FrameLabels {
  nlohmann::ordered_json image;                     // COCO image entry without "id"
  std::vector<nlohmann::ordered_json> annotations;  // without "id" and "image_id"
  int dropped_people = 0;                           // under min_visible_pixels
};

// Row-major 4×4 camera → world of a scene camera.
Eigen::Matrix4f camera_to_world(const scene::Camera& camera);

FrameLabels label_frame(const BuiltFrame& frame, const render::FrameBuffers& buffers,
                        const LabelOptions& options);

}  // namespace wheelpose::generate
