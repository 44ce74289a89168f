// Texture: surface patterns of the background objects and the wall (or the room's surfaces).

#include "generate/interior_materials.h"
#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class TextureRandomizer final : public Randomizer {
 public:
  explicit TextureRandomizer(const ConfigNode* c) : interior_(interior_style(c)) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    if (interior_) {
      for (std::size_t i = 0; i < f.objects.size(); ++i) {
        f.objects[i].material = interior_furniture(rng, "object_" + std::to_string(i));
      }
      f.wall = interior_wall(rng, "wall");
      f.room.floor = interior_floor(rng, "floor");
      f.room.walls = interior_wall(rng, "walls");
      // Drawn after the room's own, so rooms keep their draws.
      if (f.room.outdoor) f.room.floor = outdoor_ground(rng, "ground", kOutdoorGroundSize);
      return;
    }
    for (std::size_t i = 0; i < f.objects.size(); ++i) {
      f.objects[i].material = random_material(rng, "object_" + std::to_string(i));
    }
    f.wall = random_material(rng, "wall");
    f.room.floor = random_material(rng, "floor");
    f.room.walls = random_material(rng, "walls");
  }

  nlohmann::ordered_json parameters() const override {
    if (interior_) return {{"style", "interior"}};
    return {{"patterns", "noise, stripes, checker, fabric, wood, marble"}};
  }

 private:
  static bool interior_style(const ConfigNode* c) {
    return choice_or(c, "style", "paper", {"paper", "interior"}) == "interior";
  }

  bool interior_;
};

}  // namespace

extern const RandomizerEntry kTextureRandomizer = {
    "Texture",
    "Gives every background object, the wall and the room surfaces a procedural texture: one of "
    "noise, stripes, checker, fabric, wood, marble (uniform), two colours U(0.05, 0.95) per "
    "channel, repeat U(1, 16) per UV unit, specular U(0, 0.3). The authors used the 529 texture "
    "JPEGs of the Perception samples, which are not redistributable; procedural patterns give "
    "the same kind of clutter without files. `style: interior` instead gives a lived-in room: "
    "walls in light, quiet paints with a faint mottle, floors of wood (0.5), tiles (0.25) or "
    "carpet (0.25), furniture and objects in wood (0.6) or paint; switch HueOffset off with it. "
    "New in WheelPose.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<TextureRandomizer>(c);
    }};

}  // namespace wheelpose::generate
