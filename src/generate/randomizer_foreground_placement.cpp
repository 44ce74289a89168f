// ForegroundObjectPlacement: the PeopleSansPeople placement of people (Poisson-disk in a plane
// at a random depth, then a mostly-upright rotation).

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class ForegroundObjectPlacement final : public Randomizer {
 public:
  explicit ForegroundObjectPlacement(const ConfigNode* c)
      : width_(number_or(c, "width", 15.0, 0.1, 1000.0)),
        height_(number_or(c, "height", 15.0, 0.1, 1000.0)),
        separation_(number_or(c, "separation", 3.0, 0.1, 100.0)),
        depth_(sampler_or(c, "depth", ScalarSampler::uniform(-9, 6))),
        rx_(sampler_or(c, "rotation_x", ScalarSampler::uniform(0, 20))),
        ry_(sampler_or(c, "rotation_y", ScalarSampler::uniform(0, 360))),
        rz_(sampler_or(c, "rotation_z", ScalarSampler::uniform(0, 20))) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    if (f.environment == EnvironmentKind::kRoom) return;  // TransformPlacement handles rooms
    const auto points = poisson_disk(static_cast<float>(width_), static_cast<float>(height_),
                                     static_cast<float>(separation_), rng);
    if (f.people.size() > points.size()) f.people.resize(points.size());
    for (std::size_t i = 0; i < f.people.size(); ++i) {
      PersonDraft& p = f.people[i];
      p.position = Eigen::Vector3f(points[i].x() - static_cast<float>(width_ / 2),
                                   points[i].y() - static_cast<float>(height_ / 2),
                                   static_cast<float>(depth_.sample(rng)));
      const Eigen::Vector3d deg(rx_.sample(rng), ry_.sample(rng), rz_.sample(rng));
      p.rotation = euler_xyz_extrinsic(deg * (M_PI / 180.0)).cast<float>();
      p.placed = true;
    }
  }

  nlohmann::ordered_json parameters() const override {
    return {{"width", width_},
            {"height", height_},
            {"separation", separation_},
            {"depth", depth_.describe()},
            {"rotation_x", rx_.describe()},
            {"rotation_y", ry_.describe()},
            {"rotation_z", rz_.describe()}};
  }

 private:
  double width_, height_, separation_;
  ScalarSampler depth_, rx_, ry_, rz_;
};

}  // namespace

extern const RandomizerEntry kForegroundObjectPlacementRandomizer = {
    "ForegroundObjectPlacement",
    "The PeopleSansPeople-scene alternative to TransformPlacement: people at Poisson-disk points "
    "of a `width` × `height` = 15 × 15 m area, `separation` = 3 m apart, depth `depth` U(−9, 6), "
    "rotated by `rotation_x` U(0, 20), `rotation_y` U(0, 360), `rotation_z` U(0, 20) degrees "
    "(the paper's ForegroundRotationRandomizer row); people beyond the points are left out. "
    "Off by default: the paper's final datasets used the SyntheticHumans scene.",
    false, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<ForegroundObjectPlacement>(c);
    }};

}  // namespace wheelpose::generate
