// Sprite: a real background image instead of the textured wall.

#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

namespace fs = std::filesystem;

class SpriteRandomizer final : public Randomizer {
 public:
  explicit SpriteRandomizer(const ConfigNode* c)
      : probability_(number_or(c, "probability", 1.0, 0.0, 1.0)) {
    if (c == nullptr || !c->has("images")) return;
    const ConfigNode node = c->child("images");
    directory_ = node.as_string();
    std::error_code ec;
    if (!fs::is_directory(directory_, ec)) node.fail("not a directory: " + directory_);
    for (const auto& entry : fs::directory_iterator(directory_)) {
      std::string ext = entry.path().extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
      if (ext == ".jpg" || ext == ".jpeg" || ext == ".png")
        images_.push_back(entry.path().string());
    }
    std::sort(images_.begin(), images_.end());  // directory order is not stable across machines
    if (images_.empty()) node.fail("no .jpg/.jpeg/.png files in " + directory_);
  }

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    if (images_.empty() || !rng.bernoulli(probability_)) return;
    f.background.image = images_[static_cast<std::size_t>(
        rng.uniform_int(0, static_cast<std::int64_t>(images_.size()) - 1))];
  }

  nlohmann::ordered_json parameters() const override {
    return {{"images", directory_}, {"image_count", images_.size()}, {"probability", probability_}};
  }

 private:
  double probability_;
  std::string directory_;
  std::vector<std::string> images_;
};

}  // namespace

extern const RandomizerEntry kSpriteRandomizer = {
    "Sprite",
    "With probability `probability` (1) replaces the wall by an image drawn uniformly from the "
    "`images` folder (.jpg/.png, sorted by name), scaled to cover the frame without stretching. "
    "Off by default because the paper's backgrounds (BG-20K, SynthHomes samples) are not "
    "redistributable: point `images` at your own set.",
    false, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<SpriteRandomizer>(c);
    }};

}  // namespace wheelpose::generate
