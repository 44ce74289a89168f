#pragma once
// Skin weights of everything a rigged person wears: the body's own from the rig (MakeHuman's
// weights), a cap centre's and a proxy vertex's blended from the base-mesh vertices they are
// made of. Each vertex keeps its four strongest bones, renormalised to sum to 1 (glTF's rule).

#include <array>
#include <utility>
#include <vector>

#include "body/proxy.h"
#include "body/rig.h"

namespace wheelpose::body {

struct Person;

struct SkinWeights {
  std::vector<std::array<int, Rig::kMaxInfluences>> bone;      // -1: unused slot
  std::vector<std::array<float, Rig::kMaxInfluences>> weight;  // 0 in unused slots
};

// The four strongest bones of a blend of base-mesh vertices (base vertex, blend weight):
// influences summed by bone, ties broken by bone index, weights below 1e-4 dropped, sum 1.
void blend_influences(const Rig& rig, const std::vector<std::pair<int, float>>& sources,
                      std::array<int, Rig::kMaxInfluences>& bone,
                      std::array<float, Rig::kMaxInfluences>& weight);

// Per Person::vertices: the rig's weights of its base vertex; a cap centre blends its rim's.
SkinWeights body_skin_weights(const Rig& rig, const Person& person);
// Per proxy vertex: its three reference vertices blended by the proxy's barycentric weights.
SkinWeights proxy_skin_weights(const Rig& rig, const Proxy& proxy);
// Every vertex of a mesh bound to one bone.
SkinWeights rigid_skin_weights(int bone, std::size_t vertex_count);

}  // namespace wheelpose::body
