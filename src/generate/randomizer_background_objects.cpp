// BackgroundObjectPlacement: primitives scattered by Poisson-disk sampling (wall layout) or
// furniture-sized blocks standing on the floor (room layout).

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class BackgroundObjectPlacement final : public Randomizer {
 public:
  explicit BackgroundObjectPlacement(const ConfigNode* c)
      : width_(number_or(c, "width", 15.0, 0.1, 1000.0)),
        height_(number_or(c, "height", 15.0, 0.1, 1000.0)),
        separation_(number_or(c, "separation", 2.5, 0.1, 100.0)),
        depth_(sampler_or(c, "depth", ScalarSampler::uniform(-7.5, 7.5))),
        room_separation_(number_or(c, "room_separation", 1.5, 0.1, 100.0)),
        furniture_probability_(number_or(c, "furniture_probability", 0.85, 0.0, 1.0)) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext& ctx) const override {
    static const char* shapes[] = {"box", "sphere", "capsule", "cylinder"};
    if (f.environment == EnvironmentKind::kRoom) {
      // Furniture along the walls: the outer 15 % of the room on each side, so the middle
      // stays free for the people.
      const float w = f.room.size.x(), d = f.room.size.y();
      for (const Eigen::Vector2f& p :
           poisson_disk(w, d, static_cast<float>(room_separation_), rng)) {
        const Eigen::Vector2f q = p - Eigen::Vector2f(w / 2, d / 2);
        if (std::abs(q.x()) < 0.35f * w && std::abs(q.y()) < 0.35f * d) continue;
        ObjectDraft o;
        o.shape = rng.bernoulli(0.7) ? "box" : shapes[rng.uniform_int(1, 3)];
        // Both drawn always, so the stream does not depend on what is installed.
        const bool furniture = rng.bernoulli(furniture_probability_);
        const auto item = rng.uniform_int(0, std::max(0, ctx.furniture_count - 1));
        if (furniture && ctx.furniture_count > 0) o.furniture = static_cast<int>(item);
        o.position = Eigen::Vector3f(q.x(), 0.5f, q.y());  // the builder rests it on the floor
        f.objects.push_back(o);
      }
      return;
    }
    for (const Eigen::Vector2f& p :
         poisson_disk(static_cast<float>(width_), static_cast<float>(height_),
                      static_cast<float>(separation_), rng)) {
      ObjectDraft o;
      o.shape = shapes[rng.uniform_int(0, 3)];
      o.position = Eigen::Vector3f(p.x() - static_cast<float>(width_ / 2),
                                   p.y() - static_cast<float>(height_ / 2),
                                   static_cast<float>(depth_.sample(rng)));
      f.objects.push_back(o);
    }
  }

  nlohmann::ordered_json parameters() const override {
    return {{"width", width_},
            {"height", height_},
            {"separation", separation_},
            {"depth", depth_.describe()},
            {"room_separation", room_separation_},
            {"furniture_probability", furniture_probability_}};
  }

 private:
  double width_, height_, separation_;
  ScalarSampler depth_;
  double room_separation_;
  double furniture_probability_;
};

}  // namespace

extern const RandomizerEntry kBackgroundObjectPlacementRandomizer = {
    "BackgroundObjectPlacement",
    "Wall layout: background and occluder objects (unit box, sphere, capsule, cylinder) at "
    "Poisson-disk points (Bridson, 30 candidates) of a `width` × `height` = 15 × 15 m area centred "
    "on the origin, at least `separation` = 2.5 m apart, at depth z ~ `depth` = U(−7.5, 7.5) "
    "(the paper's table; the authors' scene used U(−10, 14), which puts 12 m objects against the "
    "camera). Room layout: furniture on the floor along the walls (the outer 15 % of the room "
    "on each side), `room_separation` = 1.5 m apart: with `furniture_probability` = 0.85 a CC0 "
    "model from Debian "
    "`sweethome3d-furniture` (BlendSwap-CC-0.sh3f: living room, bedroom, kitchen, office and "
    "bathroom items at their catalogued size), else a box or rounded block.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<BackgroundObjectPlacement>(c);
    }};

}  // namespace wheelpose::generate
