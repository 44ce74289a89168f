// Rotation: 3D orientation of the background objects.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class RotationRandomizer final : public Randomizer {
 public:
  explicit RotationRandomizer(const ConfigNode* c)
      : x_(sampler_or(c, "x", ScalarSampler::uniform(0, 360))),
        y_(sampler_or(c, "y", ScalarSampler::uniform(0, 360))),
        z_(sampler_or(c, "z", ScalarSampler::uniform(0, 360))) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    const bool room = f.environment == EnvironmentKind::kRoom;
    for (ObjectDraft& o : f.objects) {
      const double x = x_.sample(rng), y = y_.sample(rng), z = z_.sample(rng);
      // Furniture stands upright: only its heading is random.
      const Eigen::Vector3d deg = room ? Eigen::Vector3d(0, y, 0) : Eigen::Vector3d(x, y, z);
      o.rotation = euler_xyz_extrinsic(deg * (M_PI / 180.0)).cast<float>();
    }
  }

  nlohmann::ordered_json parameters() const override {
    return {{"x", x_.describe()}, {"y", y_.describe()}, {"z", z_.describe()}};
  }

 private:
  ScalarSampler x_, y_, z_;
};

}  // namespace

extern const RandomizerEntry kRotationRandomizer = {
    "Rotation",
    "Rotates each background object by Euler angles (degrees, extrinsic x, y, z) `x`, `y`, `z` "
    "= U(0, 360) each (paper). In rooms only the heading (`y`) is used.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<RotationRandomizer>(c);
    }};

}  // namespace wheelpose::generate
