#include "render/denoise.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "core/random.h"

namespace wheelpose::render {
namespace {

constexpr int kW = 40, kH = 30;

// A plane z = depth facing +z, one surface id everywhere.
std::vector<LightingGuide> plane_guide(int surface = 1, float depth = 0) {
  std::vector<LightingGuide> g(kW * kH);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      LightingGuide& p = g[y * kW + x];
      p.surface = surface;
      p.normal[2] = 1;
      p.position[0] = 0.01f * x;
      p.position[1] = 0.01f * y;
      p.position[2] = depth;
    }
  }
  return g;
}

std::vector<PixelLight> constant_light(float value) {
  std::vector<PixelLight> l(kW * kH);
  for (auto& p : l) {
    for (int k = 0; k < 3; ++k) {
      p.diffuse[k] = value;
      p.specular[k] = 0.5f * value;
    }
  }
  return l;
}

TEST(Denoise, ConstantLightingStaysConstant) {
  auto light = constant_light(0.7f);
  denoise_lighting(kW, kH, plane_guide(), 3, light);
  for (const auto& p : light) {
    ASSERT_NEAR(p.diffuse[1], 0.7f, 1e-6f);
    ASSERT_NEAR(p.specular[2], 0.35f, 1e-6f);
  }
}

TEST(Denoise, NoiseDropsAndTheMeanStays) {
  RandomStream rng(5, {"denoise"});
  std::vector<PixelLight> light(kW * kH);
  for (auto& p : light) p.diffuse[0] = static_cast<float>(rng.uniform(0, 2));  // mean 1
  auto variance = [&](const std::vector<PixelLight>& l, double& mean) {
    mean = 0;
    for (const auto& p : l) mean += p.diffuse[0];
    mean /= static_cast<double>(l.size());
    double v = 0;
    for (const auto& p : l) v += (p.diffuse[0] - mean) * (p.diffuse[0] - mean);
    return v / static_cast<double>(l.size());
  };
  double mean_before = 0, mean_after = 0;
  const double before = variance(light, mean_before);
  denoise_lighting(kW, kH, plane_guide(), 3, light);
  const double after = variance(light, mean_after);
  // σ = 1.5 px separable Gaussian: ≈ 1 / (4π σ²) of the variance of white noise in the interior.
  EXPECT_LT(after, before / 10);
  EXPECT_NEAR(mean_after, mean_before, 0.02);
}

TEST(Denoise, DoesNotMixSurfacesCreasesOrDepthSteps) {
  // Left half: surface 1 lit 1.0; right half: three regions that must stay apart from it.
  for (int variant = 0; variant < 3; ++variant) {
    auto guide = plane_guide();
    auto light = constant_light(1.0f);
    for (int y = 0; y < kH; ++y) {
      for (int x = kW / 2; x < kW; ++x) {
        LightingGuide& g = guide[y * kW + x];
        if (variant == 0) g.surface = 2;  // another object
        if (variant == 1) {               // a 90° crease of the same mesh
          g.normal[0] = 1;
          g.normal[2] = 0;
        }
        if (variant == 2) g.position[2] = -0.5f;  // same normal, 0.5 m behind
        for (int k = 0; k < 3; ++k) light[y * kW + x].diffuse[k] = 0.0f;
      }
    }
    denoise_lighting(kW, kH, guide, 3, light);
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        // Nothing of the other side gets in: the right stays exactly 0, the left 1.
        ASSERT_NEAR(light[y * kW + x].diffuse[0], x < kW / 2 ? 1.0f : 0.0f,
                    x < kW / 2 ? 1e-6f : 0.0f)
            << "variant " << variant << " at " << x << "," << y;
      }
    }
  }
}

TEST(Denoise, BackgroundPixelsAreLeftAlone) {
  auto guide = plane_guide(-1);
  auto light = constant_light(0.0f);
  light[5].diffuse[0] = 3.0f;
  denoise_lighting(kW, kH, guide, 3, light);
  EXPECT_EQ(light[5].diffuse[0], 3.0f);
  EXPECT_EQ(light[6].diffuse[0], 0.0f);
}

TEST(Denoise, SameResultWhateverTheThreadCount) {
  RandomStream rng(9, {"denoise"});
  std::vector<PixelLight> noisy(kW * kH);
  for (auto& p : noisy) p.diffuse[1] = static_cast<float>(rng.uniform01());
  auto one = noisy, two = noisy;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    denoise_lighting(kW, kH, plane_guide(), 2, one);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    denoise_lighting(kW, kH, plane_guide(), 2, two);
  }
  for (int i = 0; i < kW * kH; ++i) ASSERT_EQ(one[i].diffuse[1], two[i].diffuse[1]);
}

}  // namespace
}  // namespace wheelpose::render
