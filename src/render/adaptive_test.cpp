#include "render/adaptive.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace wheelpose::render {
namespace {

constexpr int kW = 12, kH = 8;

// A flat surface 0 facing +z at z = −1 with a uniform colour; tests then change parts of it.
struct Frame {
  std::vector<LightingGuide> guide = std::vector<LightingGuide>(kW * kH);
  std::vector<std::array<float, 3>> color =
      std::vector<std::array<float, 3>>(kW * kH, std::array<float, 3>{0.5f, 0.5f, 0.5f});
  Frame() {
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        LightingGuide& g = guide[y * kW + x];
        g.surface = 0;
        g.normal[2] = 1;
        g.position[0] = 0.01f * x;
        g.position[1] = -0.01f * y;
        g.position[2] = -1;
      }
    }
  }
  std::vector<std::uint8_t> mark(float contrast = 0.05f) const {
    std::vector<std::uint8_t> refine;
    mark_edges(kW, kH, guide, color, contrast, refine);
    return refine;
  }
};

// Columns that are marked in every row (and no other pixel is).
std::vector<int> marked_columns(const std::vector<std::uint8_t>& refine) {
  std::vector<int> columns;
  for (int x = 0; x < kW; ++x) {
    int n = 0;
    for (int y = 0; y < kH; ++y) n += refine[y * kW + x];
    if (n == kH)
      columns.push_back(x);
    else
      EXPECT_EQ(n, 0) << "column " << x << " partly marked";
  }
  return columns;
}

TEST(MarkEdges, AUniformSurfaceNeedsNoMoreSamples) {
  const Frame f;
  const auto refine = f.mark();
  EXPECT_EQ(std::count(refine.begin(), refine.end(), 1), 0);
}

TEST(MarkEdges, AnotherSurfaceMarksBothSidesOfTheBoundary) {
  Frame f;
  for (int y = 0; y < kH; ++y) {
    for (int x = 6; x < kW; ++x) f.guide[y * kW + x].surface = 1;
  }
  EXPECT_EQ(marked_columns(f.mark()), (std::vector<int>{5, 6}));
}

TEST(MarkEdges, ACreaseADepthStepAndAColourStepAreEdges) {
  Frame crease;
  for (int y = 0; y < kH; ++y) {
    for (int x = 6; x < kW; ++x) {
      // Tilted 37° about the y axis from column 5 on: positions on that plane.
      crease.guide[y * kW + x].normal[0] = 0.6f;
      crease.guide[y * kW + x].normal[2] = 0.8f;
      crease.guide[y * kW + x].position[2] = -1.0f - 0.75f * 0.01f * static_cast<float>(x - 5);
    }
  }
  EXPECT_EQ(marked_columns(crease.mark()), (std::vector<int>{5, 6}));

  Frame step;  // the same mesh, 0.3 m nearer from column 6 on (an arm in front of a torso)
  for (int y = 0; y < kH; ++y) {
    for (int x = 6; x < kW; ++x) step.guide[y * kW + x].position[2] = -0.7f;
  }
  EXPECT_EQ(marked_columns(step.mark()), (std::vector<int>{5, 6}));

  Frame colour;
  for (int y = 0; y < kH; ++y) colour.color[y * kW + 6] = {0.5f, 0.6f, 0.5f};
  EXPECT_EQ(marked_columns(colour.mark()), (std::vector<int>{5, 6, 7}));
  // Below the threshold it is no edge.
  EXPECT_TRUE(marked_columns(colour.mark(0.2f)).empty());
}

TEST(MarkEdges, BackgroundComparesColourOnly) {
  Frame f;
  for (auto& g : f.guide) g.surface = -1;
  EXPECT_TRUE(marked_columns(f.mark()).empty());
  for (int y = 0; y < kH; ++y) f.color[y * kW + 3] = {0.9f, 0.5f, 0.5f};
  EXPECT_EQ(marked_columns(f.mark()), (std::vector<int>{2, 3, 4}));
}

// Camera at the origin looking down −z, 64×48, 45° vertical field of view.
scene::Projector test_projector() {
  scene::Camera cam;
  cam.position = Eigen::Vector3f::Zero();
  cam.width = 64;
  cam.height = 48;
  cam.vfov_deg = 45;
  return scene::Projector(cam);
}

int count_marked(const std::vector<float>& vertices, const std::vector<Eigen::Vector3i>& tris) {
  const scene::Projector p = test_projector();
  std::vector<std::uint8_t> refine(static_cast<std::size_t>(p.width) * p.height, 0);
  std::vector<Sliver> slivers;
  find_slivers(p, vertices.data(), tris, slivers);
  mark_slivers(slivers, p.width, p.height, refine);
  return static_cast<int>(std::count(refine.begin(), refine.end(), 1));
}

TEST(MarkSlivers, ALongThinTriangleIsMarkedAlongItsLength) {
  // Horizontal, 1 m long at 2 m (≈ 29 px) and 1 mm tall (≈ 0.03 px).
  const std::vector<float> v = {-0.5f, 0, -2, 0.5f, 0, -2, 0.5f, 0.001f, -2};
  const int n = count_marked(v, {{0, 1, 2}});
  EXPECT_GE(n, 3 * 28);  // a band 3 px wide along it
  EXPECT_LE(n, 3 * 32);
}

TEST(MarkSlivers, SmallWideAndHiddenTrianglesAreNot) {
  // A big triangle (edge detection handles it), a sub-pixel one, and one behind the camera.
  const std::vector<float> v = {-0.5f, 0, -2, 0.5f,  0, -2, 0,    0.5f,   -2,
                                0,     0, -2, 0.01f, 0, -2, 0,    0.01f,  -2,
                                -0.5f, 0, 2,  0.5f,  0, 2,  0.5f, 0.001f, 2};
  EXPECT_EQ(count_marked(v, {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}}), 0);
}

}  // namespace
}  // namespace wheelpose::render
