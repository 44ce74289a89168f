#pragma once
// Adaptive anti-aliasing: which pixels need more samples than their first ones. A pixel whose
// 3×3 neighbourhood is one surface, smoothly curved, at one depth and of one colour looks the
// same with one sample as with many (procedural textures are already filtered by the pixel's
// footprint); only edges of any kind gain from more.

#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "render/denoise.h"
#include "scene/projector.h"

namespace wheelpose::render {

// Sets refine[i] = 1 for every pixel that differs from one of its 8 neighbours in surface, in
// normal (more than ≈ 18°), in depth (the neighbour lies more than 30° off the pixel's tangent
// plane) or in colour (a channel of `color`, the first samples' albedo or background radiance,
// differs by more than `contrast`); 0 otherwise. Both sides of an edge are marked. Pure per
// pixel, so independent of the thread count.
void mark_edges(int width, int height, const std::vector<LightingGuide>& guide,
                const std::vector<std::array<float, 3>>& color, float contrast,
                std::vector<std::uint8_t>& refine);
// The same from planes: the guide's (the renderer builds them once for this and the smoothing)
// and one per colour channel.
void mark_edges(int width, int height, const GuidePlanes& guide,
                const std::vector<float> (&color)[3], float contrast,
                std::vector<std::uint8_t>& refine);

// A triangle that projects thinner than a pixel but longer than two (wheel spokes, wires, chair
// legs far away): the first samples may miss such a part along its whole length, so no edge
// shows. Its longest edge, in pixel coordinates.
struct Sliver {
  cv::Point from, to;
};

// Appends the slivers among `triangles` (vertices: 3 floats each, world space). Triangles with a
// vertex behind the camera are skipped.
void find_slivers(const scene::Projector& projector, const float* vertices,
                  const std::vector<Eigen::Vector3i>& triangles, std::vector<Sliver>& out);

// Sets refine = 1 in a band 3 pixels wide along each sliver (refine: width × height, row-major).
void mark_slivers(const std::vector<Sliver>& slivers, int width, int height,
                  std::vector<std::uint8_t>& refine);

}  // namespace wheelpose::render
