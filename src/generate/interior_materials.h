#pragma once
// Surfaces of a lived-in room, for the Texture randomizer's `interior` style: painted walls in
// the light, quiet colours walls are mostly painted, floors of wood, tiles or carpet, furniture
// in wood or paint. The paper's style (random two-colour patterns in any hue) is
// random_material in randomizer.h.

#include <string>

#include "core/random.h"
#include "scene/scene.h"

namespace wheelpose::generate {

scene::Material interior_wall(RandomStream& rng, const std::string& name);
scene::Material interior_floor(RandomStream& rng, const std::string& name);
scene::Material interior_furniture(RandomStream& rng, const std::string& name);
// Open ground `size_m` across (its UVs span it once): asphalt, paving slabs or grass, with
// patterns at their real size.
scene::Material outdoor_ground(RandomStream& rng, const std::string& name, float size_m);

}  // namespace wheelpose::generate
