#pragma once
// Camera framing: a photographer steps aside until the people show. A frame's first camera draw
// is judged by casting a ray to every keypoint of every person in view; while someone shows too
// little of themselves the Camera randomizer draws again (its own stream, keyed by the draw),
// and the first draw that shows everyone well enough, or else the best one, is kept.
//
// Candidate draws are judged against the first draw's built scene (people and furniture do not
// depend on the camera; surfaces within kNearClearance of a candidate camera are ignored, since
// the frame builder leaves out objects around the camera). The chosen camera then goes into the
// built frame, or the frame is built again when that camera would leave out other objects, so
// the frame rendered and labelled is exactly the one its draft builds.

#include <cstdint>

#include "generate/frame_builder.h"
#include "generate/scenario.h"
#include "render/renderer.h"

namespace wheelpose::generate {

// What one camera shows of a frame's people.
struct FramingScore {
  // The smallest share, over the people with at least `min_keypoints` keypoints in the image,
  // of those keypoints that no surface hides (1 when nobody is judged).
  double worst_visible_share = 1.0;
  int people_judged = 0;
  int people_short = 0;  // judged people who show less than the share asked for
};

inline constexpr float kNearClearance = 0.5f;  // metres; above the builder's 0.3 m

FramingScore score_framing(const BuiltFrame& frame, const render::Renderer& renderer,
                           const scene::Camera& camera, int min_keypoints,
                           double min_visible_share = 1.0);

// The camera draw to keep for frame `index` (0 = the first draw), given the first draw's
// draft and built frame, under scenario.framing: the first that shows everyone well enough,
// else the one that leaves the fewest people short (then the best-shown worst person).
int choose_camera_draw(const Scenario& scenario, std::uint64_t seed, std::int64_t index,
                       const RandomizerContext& context, const FrameDraft& first_draft,
                       const BuiltFrame& first_frame, const render::Renderer& renderer);

}  // namespace wheelpose::generate
