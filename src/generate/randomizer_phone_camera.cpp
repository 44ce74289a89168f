// PhoneCamera: what a phone or webcam does to a photo — automatic exposure, a filmic tone curve,
// sensor noise that grows in the dark, resampling, JPEG at everyday qualities and motion blur
// over the shutter time.

#include <cmath>

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class PhoneCamera final : public Randomizer {
 public:
  explicit PhoneCamera(const ConfigNode* c)
      : key_(sampler_or(c, "exposure_key", ScalarSampler::uniform(0.1, 0.2), 0.01, 1)),
        filmic_(number_or(c, "filmic_probability", 1, 0, 1)),
        shot_(sampler_or(c, "shot_noise", ScalarSampler::uniform(0.0002, 0.002), 0, 0.1)),
        read_(sampler_or(c, "read_noise", ScalarSampler::uniform(0.0001, 0.001), 0, 0.1)),
        quality_(sampler_or(c, "jpeg_quality", ScalarSampler::uniform(50, 95), 1, 100)),
        rescale_probability_(number_or(c, "rescale_probability", 0.25, 0, 1)),
        rescale_(sampler_or(c, "rescale", ScalarSampler::uniform(0.35, 0.9), 0.1, 1)),
        shutter_(sampler_or(c, "shutter", ScalarSampler::uniform(0.002, 0.033), 0, 0.25)) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    // Every value is drawn whatever the others are, so changing one setting leaves the rest.
    scene::PostProcess& p = f.post;
    p.auto_exposure_key = static_cast<float>(key_.sample(rng));
    p.filmic = rng.bernoulli(filmic_);
    p.shot_noise = static_cast<float>(shot_.sample(rng));
    p.read_noise = static_cast<float>(read_.sample(rng));
    f.jpeg_quality = static_cast<int>(std::lround(quality_.sample(rng)));
    const bool rescaled = rng.bernoulli(rescale_probability_);
    const double factor = rescale_.sample(rng);
    f.rescale = rescaled ? static_cast<float>(factor) : 1.0f;
    f.shutter = static_cast<float>(shutter_.sample(rng));
    const auto rounded = [](double v, double unit) { return std::round(v / unit) * unit; };
    f.image_attributes["phone_camera"] = {{"exposure_key", rounded(p.auto_exposure_key, 1e-4)},
                                          {"filmic", p.filmic},
                                          {"shot_noise", rounded(p.shot_noise, 1e-6)},
                                          {"read_noise", rounded(p.read_noise, 1e-6)},
                                          {"jpeg_quality", f.jpeg_quality},
                                          {"rescale", rounded(f.rescale, 1e-4)},
                                          {"shutter", rounded(f.shutter, 1e-4)}};
  }

  nlohmann::ordered_json parameters() const override {
    return {{"exposure_key", key_.describe()},     {"filmic_probability", filmic_},
            {"shot_noise", shot_.describe()},      {"read_noise", read_.describe()},
            {"jpeg_quality", quality_.describe()}, {"rescale_probability", rescale_probability_},
            {"rescale", rescale_.describe()},      {"shutter", shutter_.describe()}};
  }

 private:
  ScalarSampler key_;
  double filmic_;
  ScalarSampler shot_, read_, quality_;
  double rescale_probability_;
  ScalarSampler rescale_, shutter_;
};

}  // namespace

extern const RandomizerEntry kPhoneCameraRandomizer = {
    "PhoneCamera",
    "A phone's or webcam's picture pipeline. Automatic exposure: the image is scaled so its "
    "log-average luminance becomes `exposure_key` U(0.1, 0.2) (mid grey is 0.18), then "
    "PostProcessVolume's exposure applies as compensation; a filmic tone curve (the ACES fit) "
    "with `filmic_probability` 1 instead of clipping; Poisson–Gaussian sensor noise of variance "
    "`shot_noise` · s + `read_noise`² in the sensor's signal s before the exposure gain "
    "(`shot_noise` U(0.0002, 0.002), `read_noise` U(0.0001, 0.001)), so dark scenes lifted by "
    "the exposure are noisier; with `rescale_probability` 0.25 the image is shrunk by `rescale` "
    "U(0.35, 0.9) and enlarged back (detail lost as in a small or digitally zoomed photo); JPEG "
    "at `jpeg_quality` U(50, 95) with 4:2:0 chroma in place of `image.jpeg_quality`; the "
    "shutter stays open `shutter` U(0.002, 0.033) seconds (at most 0.25), and people moving in "
    "their clips leave streaks that long (motion blur from the clip's own velocities, centred "
    "on the labelled instant). Labels are unchanged: keypoints stay at the shutter's middle "
    "time. The drawn values are recorded per image (`phone_camera`). New in WheelPose.",
    false, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<PhoneCamera>(c);
    }};

}  // namespace wheelpose::generate
