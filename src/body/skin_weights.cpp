#include "body/skin_weights.h"

#include <algorithm>
#include <map>

#include "body/person.h"

namespace wheelpose::body {

void blend_influences(const Rig& rig, const std::vector<std::pair<int, float>>& sources,
                      std::array<int, Rig::kMaxInfluences>& bone,
                      std::array<float, Rig::kMaxInfluences>& weight) {
  std::map<int, double> by_bone;  // ordered, so equal weights come out the same way every time
  auto gather = [&](bool every_source) {
    for (const auto& [vertex, share] : sources) {
      // A proxy's barycentric weight can dip below 0 off its triangle.
      if (!every_source && !(share > 0)) continue;
      for (int k = 0; k < Rig::kMaxInfluences; ++k) {
        const float w = rig.influence_weight[vertex][k];
        if (w > 0) by_bone[rig.influence_bone[vertex][k]] += (every_source ? 1.0 : share) * w;
      }
    }
  };
  gather(false);
  if (by_bone.empty()) gather(true);  // no positive share: the sources count alike
  std::vector<std::pair<int, double>> ranked(by_bone.begin(), by_bone.end());
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  if (ranked.size() > Rig::kMaxInfluences) ranked.resize(Rig::kMaxInfluences);
  double total = 0;
  for (const auto& r : ranked) total += r.second;
  // Tiny weights move nothing visible but can push a float sum past 1 before the last slot.
  std::erase_if(ranked, [&](const auto& r) { return r.second < 1e-4 * total; });
  total = 0;
  for (const auto& r : ranked) total += r.second;
  bone.fill(-1);
  weight.fill(0.0f);
  float assigned = 0;
  for (std::size_t k = 0; k < ranked.size(); ++k) {
    bone[k] = ranked[k].first;
    weight[k] = static_cast<float>(ranked[k].second / total);
    if (k > 0) assigned += weight[k];
  }
  // The strongest weight takes the float rounding, so the four sum to 1 as closely as floats can.
  if (!ranked.empty()) weight[0] = 1.0f - assigned;
}

SkinWeights body_skin_weights(const Rig& rig, const Person& person) {
  SkinWeights out;
  const std::size_t n = person.base_vertex.size();
  out.bone.resize(n);
  out.weight.resize(n);
  std::size_t cap = 0;
  for (std::size_t v = 0; v < n; ++v) {
    std::vector<std::pair<int, float>> sources;
    if (person.base_vertex[v] >= 0) {
      sources.emplace_back(person.base_vertex[v], 1.0f);
    } else {
      const std::vector<unsigned>& rim = person.cap_rims[cap++];
      for (unsigned r : rim) sources.emplace_back(person.base_vertex[r], 1.0f);
    }
    blend_influences(rig, sources, out.bone[v], out.weight[v]);
  }
  return out;
}

SkinWeights proxy_skin_weights(const Rig& rig, const Proxy& proxy) {
  SkinWeights out;
  out.bone.resize(proxy.refs.size());
  out.weight.resize(proxy.refs.size());
  for (std::size_t v = 0; v < proxy.refs.size(); ++v) {
    std::vector<std::pair<int, float>> sources;
    for (int k = 0; k < 3; ++k) sources.emplace_back(proxy.refs[v][k], proxy.weights[v][k]);
    blend_influences(rig, sources, out.bone[v], out.weight[v]);
  }
  return out;
}

SkinWeights rigid_skin_weights(int bone, std::size_t vertex_count) {
  SkinWeights out;
  out.bone.assign(vertex_count, {bone, -1, -1, -1});
  out.weight.assign(vertex_count, {1.0f, 0.0f, 0.0f, 0.0f});
  return out;
}

}  // namespace wheelpose::body
