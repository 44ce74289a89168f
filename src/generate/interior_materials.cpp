#include "generate/interior_materials.h"

#include <array>

#include "core/srgb.h"

namespace wheelpose::generate {
namespace {

// sRGB swatches (0xRRGGBB) chosen here.
constexpr std::array<unsigned, 12> kWallPaints = {0xf2efe8, 0xebe6da, 0xe8e2d0, 0xdcd8cf,
                                                  0xcfd2d1, 0xd9dfe3, 0xdde5dc, 0xefe3c8,
                                                  0xe7d6cf, 0xb8c4c9, 0xc9bfae, 0x9fa8a3};
constexpr std::array<unsigned, 6> kWoods = {0xc19a6b, 0xa0764a, 0x8b5a2b,
                                            0x5c4033, 0xd2b48c, 0x9e9a91};
constexpr std::array<unsigned, 6> kTiles = {0xe9e7e2, 0xcfcac1, 0xa9a6a0,
                                            0xd8c8b0, 0x6f6c68, 0xbfb6a8};
constexpr std::array<unsigned, 5> kAsphalts = {0x3b3b3a, 0x4a4947, 0x57534d, 0x605e5a, 0x6e6c68};
constexpr std::array<unsigned, 6> kPavings = {0xa8a49c, 0xb9b2a5, 0x8f8a82,
                                              0xc2b8a3, 0x9d8f7e, 0x7d7a76};
constexpr std::array<unsigned, 5> kGrasses = {0x4f6b2e, 0x5d7a34, 0x6b7d3c, 0x47602a, 0x7a7f45};
constexpr std::array<unsigned, 8> kCarpets = {0x8a8174, 0x5f6470, 0x7b6a58, 0xa59c8f,
                                              0x4b5a4f, 0x6e5a5a, 0x3c4452, 0xb0a48f};

template <std::size_t N>
Eigen::Vector3f pick(RandomStream& rng, const std::array<unsigned, N>& swatches) {
  const Eigen::Vector3f c =
      linear_from_srgb_hex(swatches[rng.uniform_int(0, static_cast<std::int64_t>(N) - 1)]);
  return (c * static_cast<float>(rng.uniform(0.9, 1.1))).cwiseMin(0.92f);
}

scene::Material surface(const std::string& name, scene::TextureKind kind, const Eigen::Vector3f& a,
                        const Eigen::Vector3f& b, float scale, RandomStream& rng) {
  scene::Material m;
  m.name = name;
  m.diffuse = Eigen::Vector3f::Ones();
  m.texture.kind = kind;
  m.texture.color_a = a;
  m.texture.color_b = b;
  m.texture.scale = scale;
  m.texture.turbulence = static_cast<float>(rng.uniform(0.3, 1.0));
  m.texture.seed = rng.next_u64();
  m.specular = static_cast<float>(rng.uniform(0.0, 0.1));
  m.shininess = static_cast<float>(rng.uniform(8.0, 32.0));
  return m;
}

scene::Material wood(RandomStream& rng, const std::string& name) {
  const Eigen::Vector3f grain = pick(rng, kWoods);
  return surface(name, scene::TextureKind::kWood, grain,
                 grain * static_cast<float>(rng.uniform(0.6, 0.8)),
                 static_cast<float>(rng.uniform(2, 8)), rng);
}

}  // namespace

// Paint with a faint mottle (rollers and light leave walls a little uneven).
scene::Material interior_wall(RandomStream& rng, const std::string& name) {
  const Eigen::Vector3f paint = pick(rng, kWallPaints);
  return surface(name, scene::TextureKind::kNoise, paint,
                 paint * static_cast<float>(rng.uniform(0.93, 0.98)),
                 static_cast<float>(rng.uniform(1, 4)), rng);
}

// Wood half the time, tiles a quarter (two close shades), carpet a quarter.
scene::Material interior_floor(RandomStream& rng, const std::string& name) {
  const double u = rng.uniform01();
  if (u < 0.5) return wood(rng, name);
  if (u < 0.75) {
    const Eigen::Vector3f tile = pick(rng, kTiles);
    return surface(name, scene::TextureKind::kChecker, tile,
                   tile * static_cast<float>(rng.uniform(0.85, 0.97)),
                   static_cast<float>(rng.uniform(2, 6)), rng);
  }
  const Eigen::Vector3f pile = pick(rng, kCarpets);
  return surface(name, scene::TextureKind::kFabric, pile,
                 pile * static_cast<float>(rng.uniform(0.75, 0.9)),
                 static_cast<float>(rng.uniform(20, 60)), rng);
}

// Wood or paint, as furniture mostly is.
scene::Material interior_furniture(RandomStream& rng, const std::string& name) {
  if (rng.bernoulli(0.6)) return wood(rng, name);
  const Eigen::Vector3f paint = pick(rng, kWallPaints) * static_cast<float>(rng.uniform(0.5, 1.0));
  return surface(name, scene::TextureKind::kNoise, paint, paint * 0.95f, 2.0f, rng);
}

// Asphalt (0.4), paving slabs 0.4–0.8 m (0.3) or grass (0.3); a pattern's repeats per metre
// times the ground's size, since the ground's UVs span it once.
scene::Material outdoor_ground(RandomStream& rng, const std::string& name, float size_m) {
  const double u = rng.uniform01();
  if (u < 0.4) {
    const Eigen::Vector3f tar = pick(rng, kAsphalts);
    return surface(name, scene::TextureKind::kNoise, tar,
                   tar * static_cast<float>(rng.uniform(0.7, 0.9)),
                   size_m * static_cast<float>(rng.uniform(2, 6)), rng);
  }
  if (u < 0.7) {
    const Eigen::Vector3f slab = pick(rng, kPavings);
    return surface(name, scene::TextureKind::kChecker, slab,
                   slab * static_cast<float>(rng.uniform(0.85, 0.97)),
                   size_m / static_cast<float>(rng.uniform(0.4, 0.8)), rng);
  }
  const Eigen::Vector3f blade = pick(rng, kGrasses);
  return surface(name, scene::TextureKind::kNoise, blade,
                 blade * static_cast<float>(rng.uniform(0.6, 0.8)),
                 size_m * static_cast<float>(rng.uniform(3, 8)), rng);
}

}  // namespace wheelpose::generate
