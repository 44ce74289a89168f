// Environment: the paper's layout (people floating in front of a textured wall) or a room.

#include <algorithm>
#include <filesystem>

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class EnvironmentRandomizer final : public Randomizer {
 public:
  explicit EnvironmentRandomizer(const ConfigNode* c)
      : room_probability_(number_or(c, "room_probability", 0.0, 0.0, 1.0)),
        room_width_(sampler_or(c, "room_width", ScalarSampler::uniform(6, 12), 3, 50)),
        room_depth_(sampler_or(c, "room_depth", ScalarSampler::uniform(6, 12), 3, 50)),
        room_height_(sampler_or(c, "room_height", ScalarSampler::uniform(2.5, 3.2), 2, 10)),
        sky_(sampler_or(c, "sky_radiance", ScalarSampler::uniform(0.1, 0.4), 0, 10)),
        hdri_probability_(number_or(c, "hdri_probability", 0.0, 0.0, 1.0)),
        hdri_intensity_(sampler_or(c, "hdri_intensity", ScalarSampler::uniform(0.3, 1.0), 0, 100)),
        outdoor_probability_(number_or(c, "outdoor_probability", 0.0, 0.0, 1.0)) {
    const std::string folder =
        c != nullptr ? c->get_string("hdri_folder", kDefaultHdriFolder) : kDefaultHdriFolder;
    std::error_code ec;
    if (std::filesystem::is_directory(folder, ec)) {
      for (const auto& e : std::filesystem::directory_iterator(folder, ec)) {
        const std::string ext = e.path().extension().string();
        if (ext == ".exr" || ext == ".hdr") hdris_.push_back(e.path().string());
      }
    }
    std::sort(hdris_.begin(), hdris_.end());  // directory order differs between machines
    for (const std::string& path : hdris_) {
      const std::string stem = std::filesystem::path(path).stem().string();
      if (stem != "interior" && stem != "studio") outdoor_hdris_.push_back(path);
    }
    // An explicit folder must hold maps; the default one may be absent (no blender-data).
    if (c != nullptr && c->has("hdri_folder") && hdris_.empty())
      c->child("hdri_folder")
          .fail("no .exr or .hdr files in " + folder +
                " (install Debian blender-data, or name a folder of HDRIs)");
  }

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    f.environment =
        rng.bernoulli(room_probability_) ? EnvironmentKind::kRoom : EnvironmentKind::kWall;
    f.room.size = Eigen::Vector2f(static_cast<float>(room_width_.sample(rng)),
                                  static_cast<float>(room_depth_.sample(rng)));
    f.room.height = static_cast<float>(room_height_.sample(rng));
    f.room.floor = random_material(rng, "floor");
    f.room.walls = random_material(rng, "walls");
    f.wall = random_material(rng, "wall");
    scene::Environment sky;
    const float radiance = static_cast<float>(sky_.sample(rng));
    sky.color = Eigen::Vector3f(0.85f, 0.92f, 1.0f) * radiance;
    // Drawn even without maps so the other draws do not depend on the installed packages.
    const bool use_hdri = rng.bernoulli(hdri_probability_);
    const std::int64_t pick = rng.uniform_int(0, std::max<std::int64_t>(0, std::ssize(hdris_) - 1));
    const float rotation = static_cast<float>(rng.uniform(0, 360));
    const float intensity = static_cast<float>(hdri_intensity_.sample(rng));
    if (use_hdri && !hdris_.empty()) {
      sky.path = hdris_[static_cast<std::size_t>(pick)];
      sky.rotation_deg = rotation;
      sky.intensity = intensity;
    }
    // Drawn last and only when asked for, so scenarios without outdoor frames keep every
    // earlier draw (and their bytes).
    f.room.outdoor = f.environment == EnvironmentKind::kRoom && outdoor_probability_ > 0 &&
                     rng.bernoulli(outdoor_probability_);
    if (f.room.outdoor && !outdoor_hdris_.empty()) {
      // Outdoors the sky is always a photographed one (blender-data's interior and studio maps
      // are not skies).
      const std::int64_t at = rng.uniform_int(0, std::ssize(outdoor_hdris_) - 1);
      sky.path = outdoor_hdris_[static_cast<std::size_t>(at)];
      sky.rotation_deg = rotation;
      sky.intensity = intensity;
    }
    // Recorded per image when a map lights the frame (`realism` splits by it); frames under
    // the uniform sky keep their entries as before.
    if (!sky.path.empty())
      f.image_attributes["hdri"] = std::filesystem::path(sky.path).stem().string();
    f.sky = sky;
  }

  nlohmann::ordered_json parameters() const override {
    return {{"room_probability", room_probability_},
            {"room_width", room_width_.describe()},
            {"room_depth", room_depth_.describe()},
            {"room_height", room_height_.describe()},
            {"sky_radiance", sky_.describe()},
            {"hdri_probability", hdri_probability_},
            {"hdri_intensity", hdri_intensity_.describe()},
            {"outdoor_probability", outdoor_probability_},
            {"hdris", hdris_}};
  }

 private:
  double room_probability_;
  static constexpr const char* kDefaultHdriFolder =
      "/usr/share/blender/datafiles/studiolights/world";
  ScalarSampler room_width_, room_depth_, room_height_, sky_;
  double hdri_probability_;
  ScalarSampler hdri_intensity_;
  double outdoor_probability_;
  std::vector<std::string> hdris_, outdoor_hdris_;
};

}  // namespace

extern const RandomizerEntry kEnvironmentRandomizer = {
    "Environment",
    "Chooses the layout: `wall` (the paper's: people and occluders float in front of a textured "
    "wall at z = −10, no floor; 80 m wide where the authors' was 30 m, so that it fills a 50° "
    "view from 25 m) with probability 1 − `room_probability` (default 0), "
    "else `room` (floor and four walls of `room_width` × `room_depth` U(6, 12) m, "
    "`room_height` U(2.5, 3.2) m, wheelchairs standing on the floor, camera at standing or "
    "seated eye height). Also sets the sky light that stands in for the authors' physically "
    "based sky: with `hdri_probability` (default 0: with one light sample per pixel HDRI-lit "
    "frames are still grainier than the uniform sky, so it is opt-in; raise "
    "`image.light_samples` with it) an HDRI from "
    "`hdri_folder` (default: the eight CC0 "
    "maps of Debian `blender-data`, by Greg Zaal / HDRI Haven, installed by setup; without them "
    "the uniform sky is used), turned U(0, 360)° and scaled by `hdri_intensity` U(0.3, 1.0), "
    "importance-sampled by the renderer; otherwise a uniform sky of `sky_radiance` U(0.1, 0.4) "
    "relative to the sun's 1. The maps used are recorded in scenario.json. With "
    "`outdoor_probability` (default 0) a room-layout frame is outdoors instead: the same people, "
    "furniture, lights and camera on open ground (400 m across) with no walls or ceiling, under "
    "one of the outdoor maps (all but `interior` and `studio`) whenever maps are installed; "
    "images record `environment: outdoor`. An image lit by a map records its name (`hdri`). New in "
    "WheelPose.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<EnvironmentRandomizer>(c);
    }};

}  // namespace wheelpose::generate
