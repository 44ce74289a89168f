// Camera framing: ray-cast keypoint visibility of candidate cameras.

#include "generate/framing.h"

#include <cmath>

#include "scene/projector.h"

namespace wheelpose::generate {

FramingScore score_framing(const BuiltFrame& frame, const render::Renderer& renderer,
                           const scene::Camera& camera, int min_keypoints,
                           double min_visible_share) {
  const scene::Projector proj(camera);
  FramingScore score;
  for (const LabelPerson& person : frame.people) {
    int in_image = 0, shown = 0;
    for (std::size_t k = 0; k < person.keypoints.size(); ++k) {
      if (!person.present[k]) continue;
      const Eigen::Vector3f c = proj.to_camera(person.keypoints[k]);
      if (c.z() >= -kNearClearance) continue;
      const Eigen::Vector2f px = proj.project(c);
      if (!(px.x() >= 0 && px.y() >= 0 && px.x() < static_cast<float>(camera.width) &&
            px.y() < static_cast<float>(camera.height))) {
        continue;
      }
      ++in_image;
      // The labeler's rule (labeler.h) on a ray instead of a depth-buffer pixel: hidden when a
      // surface lies nearer in depth than the keypoint by more than its tolerance.
      const Eigen::Vector3f toward = person.keypoints[k] - camera.position;
      const float distance = toward.norm();
      const Eigen::Vector3f direction = toward / distance;
      const Eigen::Vector3f origin = camera.position + kNearClearance * direction;
      const render::RayQuery hit = renderer.cast(origin, direction, distance - kNearClearance);
      const bool hidden =
          hit.hit && -proj.to_camera(hit.position).z() < -c.z() - person.tolerance[k];
      if (!hidden) ++shown;
    }
    if (in_image < min_keypoints) continue;
    ++score.people_judged;
    const double share = static_cast<double>(shown) / in_image;
    if (share < score.worst_visible_share) score.worst_visible_share = share;
    if (share < min_visible_share) ++score.people_short;
  }
  return score;
}

int choose_camera_draw(const Scenario& scenario, std::uint64_t seed, std::int64_t index,
                       const RandomizerContext& context, const FrameDraft& first_draft,
                       const BuiltFrame& first_frame, const render::Renderer& renderer) {
  const Scenario::Framing& framing = scenario.framing;
  int best_draw = 0;
  FramingScore best;
  for (int draw = 0; draw < framing.attempts; ++draw) {
    const scene::Camera camera =
        draw == 0 ? first_draft.camera : draft_frame(scenario, seed, index, context, draw).camera;
    const FramingScore score = score_framing(first_frame, renderer, camera, framing.min_keypoints,
                                             framing.min_visible_share);
    if (score.people_short == 0) return draw;
    if (draw == 0 || score.people_short < best.people_short ||
        (score.people_short == best.people_short &&
         score.worst_visible_share > best.worst_visible_share)) {
      best = score;
      best_draw = draw;
    }
  }
  return best_draw;
}

}  // namespace wheelpose::generate
