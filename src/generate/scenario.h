#pragma once
// A generation scenario: image settings, the label template and the configured randomizers, read
// from one YAML file (configs/wheelpose-paper.yaml holds the defaults):
//
//   image: {width, height, spp, light_samples, denoise_radius, adaptive_contrast, jpeg_quality,
//           bounce}
//   labels: {keypoint_template, min_visible_pixels, segmentation, ground_truth_maps, box}
//   framing: {attempts, min_visible_share, min_keypoints}   (generate/framing.h)
//   randomizers: {<Name>: {enabled: bool, <parameter>: <value or distribution>, ...}}
//
// Unknown sections, randomizers and keys are errors naming file:line:key.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/config.h"
#include "core/keypoint_template.h"
#include "generate/frame_builder.h"
#include "generate/randomizer.h"
#include "render/renderer.h"

namespace wheelpose::generate {

struct Scenario {
  int width = 1280, height = 720;
  int spp = 4;             // samples per pixel (anti-aliasing)
  int light_samples = 1;   // of those, how many sample the lights (render::RenderOptions)
  int denoise_radius = 3;  // lighting smoothing window in pixels (0 = off)
  // Edge threshold of adaptive anti-aliasing (render::RenderOptions; < 0 = uniform sampling).
  double adaptive_contrast = 0.05;
  int jpeg_quality = 95;
  bool bounce = false;  // one diffuse bounce of the sun and point lights (render::RenderOptions)
  std::string keypoint_template_name = "coco17";
  int min_visible_pixels = 50;
  bool segmentation = true;
  bool ground_truth_maps = false;  // depth/normal/instance/semantic PNGs per frame
  // A seated person's `bbox` holds their wheelchair too (LabelOptions::box_holds_wheelchair).
  bool box_holds_wheelchair = false;
  // Camera framing (generate/framing.h): up to `attempts` camera draws (1 = the first, no
  // framing) until every person with at least `min_keypoints` keypoints in the image shows at
  // least `min_visible_share` of them unhidden.
  struct Framing {
    int attempts = 1;
    double min_visible_share = 0.7;
    int min_keypoints = 5;
  } framing;

  struct Active {
    const RandomizerEntry* entry;
    std::shared_ptr<const Randomizer> randomizer;
  };
  std::vector<Active> randomizers;  // enabled, in registry order
  KeypointTemplate keypoint_template;
  std::vector<KeypointAnchor> anchors;

  // The renderer's options for this scenario's image settings (checked when read).
  render::RenderOptions render_options() const;

  // Every setting at its default (the paper preset).
  static Scenario defaults();
  static Scenario from_config(const ConfigNode& root);
  static Scenario from_file(const std::string& path);
  // The resolved settings and every randomizer's parameters (scenario.json provenance).
  nlohmann::ordered_json to_json() const;
};

// Randomizes frame `index`: every active randomizer in order, each with its own stream. Camera
// draws after the first (`camera_draw` > 0, framing) give the Camera randomizer a stream of
// its own per draw; every other randomizer draws the same.
FrameDraft draft_frame(const Scenario& scenario, std::uint64_t seed, std::int64_t index,
                       const RandomizerContext& context, int camera_draw = 0);

}  // namespace wheelpose::generate
