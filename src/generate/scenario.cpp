// Scenario loading: the YAML sections, randomizer configuration, and frame drafting.

#include "generate/scenario.h"

#include <limits>
#include <string_view>

#include "core/error.h"

namespace wheelpose::generate {
namespace {

void resolve_template(Scenario& s) {
  s.keypoint_template = load_keypoint_template(s.keypoint_template_name);
  s.anchors = resolve_anchors(s.keypoint_template);
}

}  // namespace

Scenario Scenario::defaults() {
  Scenario s;
  for (const RandomizerEntry& entry : randomizer_registry()) {
    if (entry.enabled_by_default) s.randomizers.push_back({&entry, entry.make(nullptr)});
  }
  resolve_template(s);
  return s;
}

render::RenderOptions Scenario::render_options() const {
  render::RenderOptions options;
  options.spp = spp;
  options.light_samples = light_samples;
  options.denoise_radius = denoise_radius;
  options.adaptive_contrast = static_cast<float>(adaptive_contrast);
  options.bounce = bounce;
  return options;
}

Scenario Scenario::from_config(const ConfigNode& root) {
  Scenario s;
  if (!root.is_null() && !root.is_map()) root.fail("expected a map of sections");
  if (auto image = root.optional_child("image")) {
    s.width = static_cast<int>(image->get_int("width", s.width, 16, 16384));
    s.height = static_cast<int>(image->get_int("height", s.height, 16, 16384));
    // Their ranges are the renderer's (RenderOptions::check, below).
    constexpr long long kIntMin = std::numeric_limits<int>::min();
    constexpr long long kIntMax = std::numeric_limits<int>::max();
    s.spp = static_cast<int>(image->get_int("spp", s.spp, kIntMin, kIntMax));
    s.light_samples =
        static_cast<int>(image->get_int("light_samples", s.light_samples, kIntMin, kIntMax));
    s.denoise_radius =
        static_cast<int>(image->get_int("denoise_radius", s.denoise_radius, kIntMin, kIntMax));
    s.adaptive_contrast =
        image->get_double("adaptive_contrast", s.adaptive_contrast,
                          -std::numeric_limits<double>::max(), std::numeric_limits<double>::max());
    s.jpeg_quality = static_cast<int>(image->get_int("jpeg_quality", s.jpeg_quality, 1, 100));
    s.bounce = image->get_bool("bounce", s.bounce);
    image->finish();
    try {
      s.render_options().check();
    } catch (const Error& e) {
      image->fail(e.what());
    }
  }
  if (auto labels = root.optional_child("labels")) {
    s.keypoint_template_name = labels->get_string("keypoint_template", s.keypoint_template_name);
    s.min_visible_pixels =
        static_cast<int>(labels->get_int("min_visible_pixels", s.min_visible_pixels, 1, 1LL << 30));
    s.segmentation = labels->get_bool("segmentation", s.segmentation);
    s.ground_truth_maps = labels->get_bool("ground_truth_maps", s.ground_truth_maps);
    const std::string box = labels->get_string("box", "person");
    if (box != "person" && box != "person_and_wheelchair")
      labels->fail("box: '" + box + "' is not person or person_and_wheelchair");
    s.box_holds_wheelchair = box == "person_and_wheelchair";
    try {
      resolve_template(s);
    } catch (const Error& e) {
      labels->fail(std::string("keypoint_template: ") + e.what());
    }
    labels->finish();
  } else {
    resolve_template(s);
  }
  if (auto framing = root.optional_child("framing")) {
    s.framing.attempts = static_cast<int>(framing->get_int("attempts", s.framing.attempts, 1, 64));
    s.framing.min_visible_share =
        framing->get_double("min_visible_share", s.framing.min_visible_share, 0.0, 1.0);
    s.framing.min_keypoints =
        static_cast<int>(framing->get_int("min_keypoints", s.framing.min_keypoints, 1, 1000));
    framing->finish();
  }
  std::optional<ConfigNode> section = root.optional_child("randomizers");
  if (section && !section->is_null() && !section->is_map()) {
    section->fail("expected a map from randomizer name to its settings");
  }
  if (section && section->is_map()) {
    for (const std::string& name : section->keys()) {
      if (find_randomizer(name) == nullptr) {
        section->child(name).fail(
            "unknown randomizer (see `wheelpose generate --list-randomizers`)");
      }
    }
  }
  for (const RandomizerEntry& entry : randomizer_registry()) {
    std::optional<ConfigNode> node;
    if (section && section->is_map()) node = section->optional_child(entry.name);
    if (node && !node->is_null() && !node->is_map()) node->fail("expected a map of settings");
    const ConfigNode* config = node && node->is_map() ? &*node : nullptr;
    const bool enabled =
        config ? config->get_bool("enabled", entry.enabled_by_default) : entry.enabled_by_default;
    if (!enabled) {
      if (config) {
        // A disabled randomizer's settings are still checked, so typos do not hide.
        entry.make(config);
        config->finish();
      }
      continue;
    }
    s.randomizers.push_back({&entry, entry.make(config)});
    if (config) config->finish();
  }
  root.finish();
  return s;
}

Scenario Scenario::from_file(const std::string& path) {
  return from_config(ConfigNode::load_file(path));
}

nlohmann::ordered_json Scenario::to_json() const {
  nlohmann::ordered_json j;
  j["image"] = {{"width", width},
                {"height", height},
                {"spp", spp},
                {"light_samples", light_samples},
                {"denoise_radius", denoise_radius},
                {"adaptive_contrast", adaptive_contrast},
                {"jpeg_quality", jpeg_quality}};
  // Written only when on, so the scenarios of earlier runs read back unchanged.
  if (bounce) j["image"]["bounce"] = true;
  j["labels"] = {{"keypoint_template", keypoint_template_name},
                 {"min_visible_pixels", min_visible_pixels},
                 {"segmentation", segmentation},
                 {"ground_truth_maps", ground_truth_maps}};
  // Written only when not the default, so the scenarios of earlier runs read back unchanged.
  if (box_holds_wheelchair) j["labels"]["box"] = "person_and_wheelchair";
  if (framing.attempts > 1) {
    j["framing"] = {{"attempts", framing.attempts},
                    {"min_visible_share", framing.min_visible_share},
                    {"min_keypoints", framing.min_keypoints}};
  }
  nlohmann::ordered_json r = nlohmann::ordered_json::object();
  for (const Active& a : randomizers) r[a.entry->name] = a.randomizer->parameters();
  j["randomizers"] = std::move(r);
  return j;
}

FrameDraft draft_frame(const Scenario& scenario, std::uint64_t seed, std::int64_t index,
                       const RandomizerContext& context, int camera_draw) {
  FrameDraft draft;
  draft.index = index;
  draft.seed = seed;
  for (const Scenario::Active& a : scenario.randomizers) {
    RandomStream rng(seed, {"frame", static_cast<std::uint64_t>(index), a.entry->name});
    if (camera_draw > 0 && std::string_view(a.entry->name) == "Camera") {
      rng = rng.child({"draw", camera_draw});
    }
    a.randomizer->apply(draft, rng, context);
  }
  return draft;
}

}  // namespace wheelpose::generate
