// Shared helpers of the randomizer files: config reading with defaults, random surfaces,
// Poisson-disk sampling, and the generated Markdown reference.

#include <cmath>
#include <sstream>

#include "core/error.h"
#include "generate/randomizer.h"

namespace wheelpose::generate {

ScalarSampler sampler_or(const ConfigNode* config, const std::string& key,
                         const ScalarSampler& fallback, double min, double max) {
  if (config == nullptr || !config->has(key)) return fallback;
  return ScalarSampler::from_config(config->child(key), min, max);
}

double number_or(const ConfigNode* config, const std::string& key, double fallback, double min,
                 double max) {
  return config == nullptr ? fallback : config->get_double(key, fallback, min, max);
}

long long integer_or(const ConfigNode* config, const std::string& key, long long fallback,
                     long long min, long long max) {
  return config == nullptr ? fallback : config->get_int(key, fallback, min, max);
}

std::string choice_or(const ConfigNode* config, const std::string& key, const std::string& fallback,
                      const std::vector<std::string>& allowed) {
  return config == nullptr ? fallback : config->get_choice(key, fallback, allowed);
}

DistractorCount::DistractorCount(const ConfigNode* config, long long default_max)
    : min(integer_or(config, "min_count", 0, 0, 1000)),
      max(integer_or(config, "max_count", default_max, 0, 1000)),
      size(sampler_or(config, "size", ScalarSampler::uniform(0.5, 3), 0.01, 100)) {
  if (max < min) config->fail("max_count is below min_count");
}

nlohmann::ordered_json DistractorCount::parameters() const {
  return {{"min_count", min}, {"max_count", max}, {"size", size.describe()}};
}

Eigen::Vector3f people_volume_point(RandomStream& rng) {
  return Eigen::Vector3f(static_cast<float>(rng.uniform(-7.5, 7.5)),
                         static_cast<float>(rng.uniform(-7.5, 7.5)),
                         static_cast<float>(rng.uniform(-4, 1)));
}

scene::Material random_material(RandomStream& rng, const std::string& name) {
  static const scene::TextureKind kinds[] = {
      scene::TextureKind::kNoise,  scene::TextureKind::kStripes, scene::TextureKind::kChecker,
      scene::TextureKind::kFabric, scene::TextureKind::kWood,    scene::TextureKind::kMarble};
  scene::Material m;
  m.name = name;
  m.diffuse = Eigen::Vector3f::Ones();
  m.texture.kind = kinds[rng.uniform_int(0, 5)];
  auto colour = [&rng] {
    return Eigen::Vector3f(static_cast<float>(rng.uniform(0.05, 0.95)),
                           static_cast<float>(rng.uniform(0.05, 0.95)),
                           static_cast<float>(rng.uniform(0.05, 0.95)));
  };
  m.texture.color_a = colour();
  m.texture.color_b = colour();
  m.texture.scale = static_cast<float>(rng.uniform(1.0, 16.0));
  m.texture.turbulence = static_cast<float>(rng.uniform(0.3, 1.5));
  m.texture.seed = rng.next_u64();
  m.specular = static_cast<float>(rng.uniform(0.0, 0.3));
  m.shininess = static_cast<float>(rng.uniform(8.0, 64.0));
  return m;
}

std::vector<Eigen::Vector2f> poisson_disk(float width, float height, float separation,
                                          RandomStream& rng) {
  if (!(separation > 0) || !(width > 0) || !(height > 0)) return {};
  const float cell = separation / std::sqrt(2.0f);
  const int gw = static_cast<int>(std::ceil(width / cell));
  const int gh = static_cast<int>(std::ceil(height / cell));
  std::vector<int> grid(static_cast<std::size_t>(gw) * gh, -1);
  std::vector<Eigen::Vector2f> points;
  std::vector<int> active;
  auto cell_of = [&](const Eigen::Vector2f& p) {
    return std::pair<int, int>(std::min(gw - 1, static_cast<int>(p.x() / cell)),
                               std::min(gh - 1, static_cast<int>(p.y() / cell)));
  };
  auto far_enough = [&](const Eigen::Vector2f& p) {
    const auto [cx, cy] = cell_of(p);
    for (int y = std::max(0, cy - 2); y <= std::min(gh - 1, cy + 2); ++y) {
      for (int x = std::max(0, cx - 2); x <= std::min(gw - 1, cx + 2); ++x) {
        const int other = grid[static_cast<std::size_t>(y) * gw + x];
        if (other >= 0 && (points[other] - p).norm() < separation) return false;
      }
    }
    return true;
  };
  auto add = [&](const Eigen::Vector2f& p) {
    const auto [cx, cy] = cell_of(p);
    grid[static_cast<std::size_t>(cy) * gw + cx] = static_cast<int>(points.size());
    active.push_back(static_cast<int>(points.size()));
    points.push_back(p);
  };
  add(Eigen::Vector2f(static_cast<float>(rng.uniform(0, width)),
                      static_cast<float>(rng.uniform(0, height))));
  while (!active.empty()) {
    const std::size_t pick =
        static_cast<std::size_t>(rng.uniform_int(0, static_cast<std::int64_t>(active.size()) - 1));
    const Eigen::Vector2f origin = points[active[pick]];
    bool placed = false;
    for (int attempt = 0; attempt < 30; ++attempt) {
      const double angle = rng.uniform(0, 2 * M_PI);
      const double radius = rng.uniform(separation, 2 * separation);
      const Eigen::Vector2f p =
          origin + Eigen::Vector2f(static_cast<float>(radius * std::cos(angle)),
                                   static_cast<float>(radius * std::sin(angle)));
      if (p.x() < 0 || p.y() < 0 || p.x() >= width || p.y() >= height || !far_enough(p)) continue;
      add(p);
      placed = true;
      break;
    }
    if (!placed) {
      active[pick] = active.back();
      active.pop_back();
    }
  }
  return points;
}

const RandomizerEntry* find_randomizer(const std::string& name) {
  for (const RandomizerEntry& entry : randomizer_registry()) {
    if (name == entry.name) return &entry;
  }
  return nullptr;
}

std::string randomizer_reference_markdown() {
  std::ostringstream out;
  out << "Randomizers run in this order; each draws from its own seeded stream. Configure one "
         "under `randomizers: {Name: {...}}`; `enabled: false` switches it off.\n";
  for (const RandomizerEntry& entry : randomizer_registry()) {
    out << "\n**" << entry.name << "**" << (entry.enabled_by_default ? "" : " (off by default)")
        << " — " << entry.doc << "\n";
  }
  return out.str();
}

}  // namespace wheelpose::generate
