// TransformPlacement: position, orientation and size of the generated people.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class TransformPlacement final : public Randomizer {
 public:
  explicit TransformPlacement(const ConfigNode* c)
      : x_(sampler_or(c, "x", ScalarSampler::uniform(-7.5, 7.5))),
        y_(sampler_or(c, "y", ScalarSampler::uniform(-7.5, 7.5))),
        z_(sampler_or(c, "z", ScalarSampler::uniform(-4, 1))),
        rx_(sampler_or(c, "rotation_x", ScalarSampler::uniform(0, 20))),
        ry_(sampler_or(c, "rotation_y", ScalarSampler::uniform(0, 360))),
        rz_(sampler_or(c, "rotation_z", ScalarSampler::uniform(0, 20))),
        size_(sampler_or(c, "size", ScalarSampler::uniform(0.5, 3), 0.01, 100)),
        room_separation_(number_or(c, "room_separation", 1.2, 0.3, 100)),
        room_heading_spread_(number_or(c, "room_heading_spread", 360, 0, 360)) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    if (f.environment == EnvironmentKind::kRoom) {
      place_in_room(f, rng);
      return;
    }
    for (PersonDraft& p : f.people) {
      p.position =
          Eigen::Vector3f(static_cast<float>(x_.sample(rng)), static_cast<float>(y_.sample(rng)),
                          static_cast<float>(z_.sample(rng)));
      const Eigen::Vector3d deg(rx_.sample(rng), ry_.sample(rng), rz_.sample(rng));
      p.rotation = euler_xyz_extrinsic(deg * (M_PI / 180.0)).cast<float>();
      p.scale = static_cast<float>(size_.sample(rng));
      p.placed = true;
    }
  }

  nlohmann::ordered_json parameters() const override {
    nlohmann::ordered_json j = {
        {"x", x_.describe()},           {"y", y_.describe()},
        {"z", z_.describe()},           {"rotation_x", rx_.describe()},
        {"rotation_y", ry_.describe()}, {"rotation_z", rz_.describe()},
        {"size", size_.describe()},     {"room_separation", room_separation_}};
    // Recorded only when narrowed, so that earlier runs' records stay as they were.
    if (room_heading_spread_ < 360) j["room_heading_spread"] = room_heading_spread_;
    return j;
  }

 private:
  // Wheels on the floor, upright, at least `room_separation` apart in the middle of the room
  // and clear of the furniture (its footprint radius plus 0.5 m for the chair; catalogue models,
  // whose size the draft does not hold, count as 0.8 m); people who do not fit are left out.
  void place_in_room(FrameDraft& f, RandomStream& rng) const {
    const float w = f.room.size.x() * 0.6f, d = f.room.size.y() * 0.6f;
    std::vector<Eigen::Vector2f> points;
    for (const Eigen::Vector2f& p : poisson_disk(w, d, static_cast<float>(room_separation_), rng)) {
      const Eigen::Vector2f at(p.x() - w / 2, p.y() - d / 2);
      bool clear = true;
      for (const ObjectDraft& o : f.objects) {
        const float radius =
            o.furniture >= 0 ? 0.8f : 0.5f * std::max(o.scale.x(), o.scale.z()) * 1.4142f;
        if ((Eigen::Vector2f(o.position.x(), o.position.z()) - at).norm() < radius + 0.5f)
          clear = false;
      }
      if (clear) points.push_back(at);
    }
    if (f.people.size() > points.size()) f.people.resize(points.size());
    // A narrowed spread turns the group one way, each person within spread / 2 of it (people
    // watching the same thing, or the camera). The full circle draws nothing extra, so that
    // earlier datasets regenerate byte for byte.
    const bool together = room_heading_spread_ < 360;
    const double group_heading = together ? rng.uniform(0, 2 * M_PI) : 0.0;
    const double half_spread = room_heading_spread_ * M_PI / 360;
    for (std::size_t i = 0; i < f.people.size(); ++i) {
      PersonDraft& p = f.people[i];
      p.position = Eigen::Vector3f(points[i].x(), 0.0f, points[i].y());
      const double heading = together ? group_heading + rng.uniform(-half_spread, half_spread)
                                      : rng.uniform(0, 2 * M_PI);
      p.rotation = Eigen::Quaternionf(
          Eigen::AngleAxisf(static_cast<float>(heading), Eigen::Vector3f::UnitY()));
      p.scale = 1.0f;
      p.placed = true;
    }
  }

  ScalarSampler x_, y_, z_, rx_, ry_, rz_, size_;
  double room_separation_;
  double room_heading_spread_;  // degrees; 360 = every heading drawn on its own
};

}  // namespace

extern const RandomizerEntry kTransformPlacementRandomizer = {
    "TransformPlacement",
    "Wall layout (paper): each person's pelvis at (`x`, `y`, `z`) = (U(−7.5, 7.5), U(−7.5, 7.5), "
    "U(−4, 1)) m, rotated by Euler angles `rotation_x` U(0, 20), `rotation_y` U(0, 360), "
    "`rotation_z` U(0, 20) degrees, scaled uniformly by `size` U(0.5, 3) (the authors' people "
    "float and may intersect). Room layout: wheels on the floor, upright, random heading "
    "(`room_heading_spread` = 360 degrees, 0–360: below 360 the group faces one random way, "
    "each person within half the spread of it), "
    "Poisson-disk points `room_separation` = 1.2 m apart in the middle 60 % of the room "
    "and clear of the furniture (footprint radius + 0.5 m), "
    "true size; people beyond the points that fit are left out.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<TransformPlacement>(c);
    }};

}  // namespace wheelpose::generate
