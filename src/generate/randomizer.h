#pragma once
// Domain randomization: each randomizer is one file (randomizer_<name>.cpp) that changes part of
// a FrameDraft, and one line in the registry (registry.cpp). Randomizers run in registry order,
// each with its own stream RandomStream(seed, {"frame", index, name}), so adding, removing or
// reconfiguring one never changes the numbers another draws.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "body/proxy.h"
#include "core/config.h"
#include "core/random.h"
#include "core/sampler.h"
#include "generate/frame_draft.h"

namespace wheelpose::generate {

// Read-only facts the randomizers may need about the run.
struct RandomizerContext {
  std::vector<std::string> clip_names;
  std::vector<double> clip_durations;  // seconds
  int width = 1280, height = 720;
  int furniture_count = 0;           // models in the furniture catalog (0 = none installed)
  std::vector<int> hanging_clothes;  // catalog indices of the hanging clothes (none: absent)
  body::ProxyCatalog proxies;        // the MakeHuman clothes, hair, eyebrows and eyes installed
};

class Randomizer {
 public:
  virtual ~Randomizer() = default;
  virtual void apply(FrameDraft& frame, RandomStream& rng, const RandomizerContext& ctx) const = 0;
  // The resolved parameters, for the run's provenance (scenario.json).
  virtual nlohmann::ordered_json parameters() const = 0;
};

struct RandomizerEntry {
  const char* name;
  // Markdown paragraph(s): what it randomizes, its parameters and their defaults, the paper's
  // value and where we differ. The randomizer reference in docs/commands/generate.md is generated
  // from these.
  const char* doc;
  bool enabled_by_default;
  // Builds the randomizer from its config section; nullptr = every parameter at its default.
  std::unique_ptr<Randomizer> (*make)(const ConfigNode* config);
};

// Every randomizer, in the order they run.
const std::vector<RandomizerEntry>& randomizer_registry();
const RandomizerEntry* find_randomizer(const std::string& name);

// The Markdown reference of every randomizer (docs/commands/generate.md, "Randomizer reference").
std::string randomizer_reference_markdown();

// ---- Helpers for randomizer files. ----

// `key` of `config` as a distribution (core/sampler.h forms), or `fallback` when absent.
ScalarSampler sampler_or(const ConfigNode* config, const std::string& key,
                         const ScalarSampler& fallback, double min = -INFINITY,
                         double max = INFINITY);
double number_or(const ConfigNode* config, const std::string& key, double fallback, double min,
                 double max);
long long integer_or(const ConfigNode* config, const std::string& key, long long fallback,
                     long long min, long long max);
// `key` of `config` as one of `allowed`, or `fallback` when absent (ConfigNode::get_choice).
std::string choice_or(const ConfigNode* config, const std::string& key, const std::string& fallback,
                      const std::vector<std::string>& allowed);

// How many distractors (empty wheelchairs, statues) a frame gets and, in the wall layout, how
// large: the keys `min_count`, `max_count` and `size` U(0.5, 3).
struct DistractorCount {
  DistractorCount(const ConfigNode* config, long long default_max);
  nlohmann::ordered_json parameters() const;
  long long min, max;
  ScalarSampler size;
};

// A point of the people's volume in the wall layout (TransformPlacement's): x and y
// U(−7.5, 7.5), z U(−4, 1).
Eigen::Vector3f people_volume_point(RandomStream& rng);

// A random procedural surface: pattern kind, two colours, scale, seed.
scene::Material random_material(RandomStream& rng, const std::string& name);

// Bridson's Poisson-disk sampling in [0, width) x [0, height): points at least `separation`
// apart, 30 candidates per active point.
std::vector<Eigen::Vector2f> poisson_disk(float width, float height, float separation,
                                          RandomStream& rng);

}  // namespace wheelpose::generate
