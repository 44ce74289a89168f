// Texture: surface patterns of the background objects and the wall (or the room's surfaces).

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class TextureRandomizer final : public Randomizer {
 public:
  explicit TextureRandomizer(const ConfigNode*) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    for (std::size_t i = 0; i < f.objects.size(); ++i) {
      f.objects[i].material = random_material(rng, "object_" + std::to_string(i));
    }
    f.wall = random_material(rng, "wall");
    f.room.floor = random_material(rng, "floor");
    f.room.walls = random_material(rng, "walls");
  }

  nlohmann::ordered_json parameters() const override {
    return {{"patterns", "noise, stripes, checker, fabric, wood, marble"}};
  }
};

}  // namespace

extern const RandomizerEntry kTextureRandomizer = {
    "Texture",
    "Gives every background object, the wall and the room surfaces a procedural texture: one of "
    "noise, stripes, checker, fabric, wood, marble (uniform), two colours U(0.05, 0.95) per "
    "channel, repeat U(1, 16) per UV unit, specular U(0, 0.3). The authors used the 529 texture "
    "JPEGs of the Perception samples, which are not redistributable; procedural patterns give "
    "the same kind of clutter without files.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<TextureRandomizer>(c);
    }};

}  // namespace wheelpose::generate
