// The randomizer registry: one line per randomizer, in the order they run.

#include "generate/randomizer.h"

namespace wheelpose::generate {

extern const RandomizerEntry kEnvironmentRandomizer;
extern const RandomizerEntry kBackgroundObjectPlacementRandomizer;
extern const RandomizerEntry kBackgroundOccluderScaleRandomizer;
extern const RandomizerEntry kRotationRandomizer;
extern const RandomizerEntry kTextureRandomizer;
extern const RandomizerEntry kHueOffsetRandomizer;
extern const RandomizerEntry kSpriteRandomizer;
extern const RandomizerEntry kHumanGenerationRandomizer;
extern const RandomizerEntry kLimbDifferenceRandomizer;
extern const RandomizerEntry kWheelchairRandomizer;
extern const RandomizerEntry kMobilityAidRandomizer;
extern const RandomizerEntry kNonTagAnimationRandomizer;
extern const RandomizerEntry kTransformPlacementRandomizer;
extern const RandomizerEntry kForegroundObjectPlacementRandomizer;
extern const RandomizerEntry kForegroundScaleRandomizer;
extern const RandomizerEntry kEmptyWheelchairRandomizer;
extern const RandomizerEntry kStatueRandomizer;
extern const RandomizerEntry kHangingClothesRandomizer;
extern const RandomizerEntry kSunAngleRandomizer;
extern const RandomizerEntry kLightRandomizer;
extern const RandomizerEntry kLightPositionRotationRandomizer;
extern const RandomizerEntry kCameraRandomizer;
extern const RandomizerEntry kPostProcessVolumeRandomizer;
extern const RandomizerEntry kPhoneCameraRandomizer;

const std::vector<RandomizerEntry>& randomizer_registry() {
  // Environment first (others depend on the layout); Camera after the people (rooms aim at
  // them); PostProcessVolume after Camera (it sets the camera's focus distance), then the
  // phone camera's pipeline on top of it.
  static const std::vector<RandomizerEntry> registry = {
      kEnvironmentRandomizer,
      kBackgroundObjectPlacementRandomizer,
      kBackgroundOccluderScaleRandomizer,
      kRotationRandomizer,
      kTextureRandomizer,
      kHueOffsetRandomizer,
      kSpriteRandomizer,
      kHumanGenerationRandomizer,
      kLimbDifferenceRandomizer,
      kWheelchairRandomizer,
      kMobilityAidRandomizer,
      kNonTagAnimationRandomizer,
      kTransformPlacementRandomizer,
      kForegroundObjectPlacementRandomizer,
      kForegroundScaleRandomizer,
      kEmptyWheelchairRandomizer,
      kStatueRandomizer,
      kHangingClothesRandomizer,
      kSunAngleRandomizer,
      kLightRandomizer,
      kLightPositionRotationRandomizer,
      kCameraRandomizer,
      kPostProcessVolumeRandomizer,
      kPhoneCameraRandomizer,
  };
  return registry;
}

}  // namespace wheelpose::generate
