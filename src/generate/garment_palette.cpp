#include "generate/garment_palette.h"

#include <array>

#include "core/srgb.h"
#include "generate/furniture.h"

namespace wheelpose::generate {
namespace {

struct Swatch {
  const char* name;
  unsigned rgb;  // sRGB, 0xRRGGBB
  bool saturated;
};

// Everyday garment colours (sRGB swatches chosen here, not taken from a catalogue).
constexpr std::array<Swatch, 26> kSwatches = {{
    {"black", 0x1c1c1e, false},       {"charcoal", 0x36393d, false},   {"grey", 0x7a7d80, false},
    {"light grey", 0xb9bbbd, false},  {"white", 0xe8e6e1, false},      {"cream", 0xe6dcc5, false},
    {"beige", 0xc8b08c, false},       {"khaki", 0xa8956b, false},      {"camel", 0xb08554, false},
    {"brown", 0x5e4030, false},       {"navy", 0x1f2a44, false},       {"denim", 0x3b5477, false},
    {"light denim", 0x6d89a8, false}, {"olive", 0x5b5e3a, false},      {"forest", 0x2f4a35, false},
    {"burgundy", 0x5a1f2a, false},    {"slate blue", 0x4a5a78, false}, {"taupe", 0x8b7d6b, false},
    {"red", 0xb3262e, true},          {"mustard", 0xd1a23b, true},     {"teal", 0x1f7a7a, true},
    {"royal blue", 0x2e4fa3, true},   {"pink", 0xd98ca6, true},        {"orange", 0xd2691e, true},
    {"purple", 0x5e3f7d, true},       {"green", 0x3f8f4f, true},
}};

constexpr double kSaturatedShare = 0.2;

GarmentShade shade_of(const Swatch& s) {
  const Eigen::Vector3f c = linear_from_srgb_hex(s.rgb);
  return {s.name, c.x(), c.y(), c.z(), s.saturated};
}

// A palette shade, a fifth of the time a saturated one, its brightness and each channel
// jittered a little so no two garments are exactly alike.
Eigen::Vector3f palette_colour(RandomStream& rng) {
  const std::vector<GarmentShade>& palette = garment_palette();
  const bool saturated = rng.bernoulli(kSaturatedShare);
  std::vector<const GarmentShade*> pool;
  for (const GarmentShade& s : palette) {
    if (s.saturated == saturated) pool.push_back(&s);
  }
  const GarmentShade& s = *pool[rng.uniform_int(0, static_cast<std::int64_t>(pool.size()) - 1)];
  const float brightness = static_cast<float>(rng.uniform(0.85, 1.15));
  Eigen::Vector3f c(s.r, s.g, s.b);
  for (int i = 0; i < 3; ++i) c[i] *= brightness * static_cast<float>(rng.uniform(0.96, 1.04));
  return c.cwiseMin(0.95f);
}

scene::Material uniform_garment(RandomStream& rng, const std::string& name) {
  scene::Material m;
  m.name = name;
  m.diffuse = Eigen::Vector3f::Ones();
  const double u = rng.uniform01();
  m.texture.kind = u < 0.5   ? scene::TextureKind::kFabric
                   : u < 0.7 ? scene::TextureKind::kStripes
                   : u < 0.8 ? scene::TextureKind::kChecker
                             : scene::TextureKind::kNoise;
  const Eigen::Vector3f base(static_cast<float>(rng.uniform(0.03, 0.9)),
                             static_cast<float>(rng.uniform(0.03, 0.9)),
                             static_cast<float>(rng.uniform(0.03, 0.9)));
  m.texture.color_a = base;
  m.texture.color_b = rng.bernoulli(0.6) ? (base * 0.6f).eval()
                                         : Eigen::Vector3f(static_cast<float>(rng.uniform01()),
                                                           static_cast<float>(rng.uniform01()),
                                                           static_cast<float>(rng.uniform01()));
  m.texture.scale = static_cast<float>(rng.uniform(4, 40));
  m.texture.seed = rng.next_u64();
  return m;
}

}  // namespace

const std::vector<GarmentShade>& garment_palette() {
  static const std::vector<GarmentShade> palette = [] {
    std::vector<GarmentShade> out;
    for (const Swatch& s : kSwatches) out.push_back(shade_of(s));
    return out;
  }();
  return palette;
}

scene::Material garment_material(RandomStream& rng, const std::string& name, GarmentColours style) {
  if (style == GarmentColours::kUniform) return uniform_garment(rng, name);
  scene::Material m;
  m.name = name;
  m.diffuse = Eigen::Vector3f::Ones();
  const Eigen::Vector3f base = palette_colour(rng);
  const Eigen::Vector3f second = palette_colour(rng);  // drawn always: stable streams
  const double u = rng.uniform01();
  m.texture.color_a = base;
  if (u < 0.6) {  // a plain weave: the thread's own shade a little darker
    m.texture.kind = scene::TextureKind::kFabric;
    m.texture.color_b = base * static_cast<float>(rng.uniform(0.7, 0.9));
  } else if (u < 0.8) {  // heather: a mottled knit
    m.texture.kind = scene::TextureKind::kNoise;
    m.texture.color_b = base * static_cast<float>(rng.uniform(0.6, 0.85));
  } else if (u < 0.92) {
    m.texture.kind = scene::TextureKind::kStripes;
    m.texture.color_b = second;
  } else {
    m.texture.kind = scene::TextureKind::kChecker;
    m.texture.color_b = second;
  }
  m.texture.scale = static_cast<float>(rng.uniform(4, 40));
  m.texture.seed = rng.next_u64();
  // Half the plain weaves are a photographed fabric's weave and folds in the drawn colour,
  // from the draws already made, so every other garment keeps its look.
  if (u < kPhotoFabricShare) {
    const std::vector<std::string>& photos = fabric_photos();
    m.diffuse = base;
    m.texture.kind = scene::TextureKind::kImageDetail;
    m.texture.path = photos[m.texture.seed % photos.size()];
    m.texture.scale /= 8;  // 0.5–5 repeats over the garment's UV square
  }
  return m;
}

const std::vector<std::string>& fabric_photos() {
  static const std::vector<std::string> photos = [] {
    const std::string archive = FurnitureCatalog::default_archive().string() + "!/blendswap-cc-0/";
    std::vector<std::string> out;
    for (const char* entry : {"couch2/Fabric_011_COLOR.jpg", "couch/Plain001.jpg",
                              "chairWithCushion/Denim_001_COLOR.jpg", "chair/tecido.jpg"}) {
      out.push_back(archive + entry);
    }
    return out;
  }();
  return photos;
}

}  // namespace wheelpose::generate
