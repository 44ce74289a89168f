#include "learn/model_ensemble.h"

#include <algorithm>
#include <cstddef>
#include <string>

#include "core/error.h"
#include "eval/oks_iou.h"

namespace wheelpose::learn {
namespace {

struct Member {
  std::size_t model = 0;
  const PosePrediction* person = nullptr;
};

struct Group {
  std::vector<Member> members;  // members[0] leads
  bool has(std::size_t model) const {
    return std::any_of(members.begin(), members.end(),
                       [&](const Member& m) { return m.model == model; });
  }
};

PosePrediction fuse_group(const Group& group, const std::vector<double>& weights) {
  PosePrediction out;
  double box_weight = 0;
  for (const Member& m : group.members) {
    const PosePrediction& p = *m.person;
    out.score += weights[m.model] * p.score;
    box_weight += p.score;
    out.bbox.x += p.score * p.bbox.x;
    out.bbox.y += p.score * p.bbox.y;
    out.bbox.w += p.score * p.bbox.w;
    out.bbox.h += p.score * p.bbox.h;
  }
  const PosePrediction& lead = *group.members.front().person;
  if (box_weight > 0) {
    out.bbox.x /= box_weight;
    out.bbox.y /= box_weight;
    out.bbox.w /= box_weight;
    out.bbox.h /= box_weight;
  } else {
    out.bbox = lead.bbox;
  }
  for (std::size_t k = 0; k < 17; ++k) {
    double x = 0, y = 0, weight = 0, score = 0;
    for (const Member& m : group.members) {
      const PosePrediction& p = *m.person;
      const double w = p.score * p.keypoints[3 * k + 2];
      x += w * p.keypoints[3 * k];
      y += w * p.keypoints[3 * k + 1];
      weight += w;
      score += weights[m.model] * p.keypoints[3 * k + 2];
    }
    // No member sees the keypoint: the lead's guess stands.
    out.keypoints[3 * k] = weight > 0 ? x / weight : lead.keypoints[3 * k];
    out.keypoints[3 * k + 1] = weight > 0 ? y / weight : lead.keypoints[3 * k + 1];
    out.keypoints[3 * k + 2] = score;
  }
  return out;
}

}  // namespace

std::vector<PosePrediction> fuse_models(const std::vector<std::vector<PosePrediction>>& per_model,
                                        const EnsembleOptions& options) {
  std::vector<double> weights = options.weights;
  if (weights.empty()) {
    weights.assign(per_model.size(), per_model.empty() ? 0.0 : 1.0 / per_model.size());
  }
  if (weights.size() != per_model.size()) {
    throw Error("ensemble: " + std::to_string(weights.size()) + " weights for " +
                std::to_string(per_model.size()) + " models");
  }
  std::vector<Member> everyone;
  for (std::size_t m = 0; m < per_model.size(); ++m) {
    for (const PosePrediction& p : per_model[m]) everyone.push_back({m, &p});
  }
  // Stable: equal scores keep the earlier model's person first, then the model's own order.
  std::stable_sort(everyone.begin(), everyone.end(), [](const Member& a, const Member& b) {
    return a.person->score > b.person->score;
  });
  std::vector<Group> groups;
  for (const Member& member : everyone) {
    auto joins = [&](const Group& g) {
      return !g.has(member.model) &&
             eval::bbox_iou(member.person->bbox, g.members.front().person->bbox, false) >=
                 options.iou;
    };
    const auto found = std::find_if(groups.begin(), groups.end(), joins);
    if (found != groups.end()) {
      found->members.push_back(member);
    } else {
      groups.push_back({{member}});
    }
  }
  std::vector<PosePrediction> fused;
  fused.reserve(groups.size());
  for (const Group& g : groups) fused.push_back(fuse_group(g, weights));
  std::stable_sort(
      fused.begin(), fused.end(),
      [](const PosePrediction& a, const PosePrediction& b) { return a.score > b.score; });
  return fused;
}

PosePrediction mirror_prediction(const PosePrediction& person, double image_width,
                                 const std::vector<std::pair<int, int>>& flip_pairs) {
  PosePrediction out = person;
  out.bbox.x = image_width - person.bbox.x - person.bbox.w;
  for (std::size_t k = 0; k < 17; ++k) out.keypoints[3 * k] = image_width - person.keypoints[3 * k];
  for (const auto& [a, b] : flip_pairs) {
    for (int c = 0; c < 3; ++c) std::swap(out.keypoints[3 * a + c], out.keypoints[3 * b + c]);
  }
  return out;
}

}  // namespace wheelpose::learn
