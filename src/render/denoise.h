#pragma once
// Edge-aware smoothing of per-pixel lighting. The renderer lights each pixel once (decoupled
// shading) and keeps the light apart from the surface colour, so the lighting can be averaged
// over neighbouring pixels of the same surface without blurring textures or edges: the noise of
// sampled shadows, lights and sky drops while silhouettes, creases and texture detail stay exact.

#include <vector>

namespace wheelpose::render {

// Where a pixel's lighting was computed (row-major, one per pixel).
struct LightingGuide {
  int surface = -1;               // geometry index; −1 = nothing lit (background)
  float normal[3] = {0, 0, 0};    // unit shading normal (world space)
  float position[3] = {0, 0, 0};  // world-space shading point
};

// A pixel's lighting: what the albedo scales (light × cos / pdf) and the specular radiance.
struct PixelLight {
  float diffuse[3] = {0, 0, 0};
  float specular[3] = {0, 0, 0};
};

// The guide as planes, one array per component, which the smoothing and edge passes read with
// branch-free (vectorisable) loops. Built once per frame and shared by both.
struct GuidePlanes {
  std::vector<int> surface;
  std::vector<float> geometry[6];  // normal x, y, z, position x, y, z
  void assign(const std::vector<LightingGuide>& guide);
  void resize(std::size_t n);
  std::size_t size() const { return surface.size(); }
};

// Working memory of denoise_lighting, kept by callers that denoise every frame.
struct DenoiseScratch {
  GuidePlanes guide;  // used by the overload that takes a LightingGuide vector
  std::vector<float> light[6], rows_done[6];
};

// Replaces each lit pixel's light by a weighted mean over its (2·radius + 1)² window, counting
// only pixels of the same surface whose normal agrees and which lie on the pixel's tangent plane
// (so an arm in front of a torso of the same mesh stays apart). Weights: a Gaussian of σ =
// radius / 2 × normal agreement × tangent-plane distance, applied separably (a row pass, then a
// column pass: 2·(2·radius + 1) taps instead of the square). Each output pixel is a pure
// function of its window, so the result does not depend on the thread count. The passes run on
// one plane per component, branch-free, so the compiler vectorises them.
void denoise_lighting(int width, int height, const std::vector<LightingGuide>& guide, int radius,
                      std::vector<PixelLight>& light, DenoiseScratch* scratch = nullptr);
// The same from guide planes already built (e.g. scratch.guide, shared with mark_edges).
void denoise_lighting(int width, int height, const GuidePlanes& guide, int radius,
                      std::vector<PixelLight>& light, DenoiseScratch& scratch);

}  // namespace wheelpose::render
