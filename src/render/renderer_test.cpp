#include "render/renderer.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/isa_test_environment.h"
#include "render/test_scenes.h"

namespace wheelpose::render {
namespace {

using testing::empty_scene;
using testing::material;
using testing::place;

// A wall facing the camera at z = −distance, filling the view.
scene::Scene wall_scene(float distance) {
  scene::Scene s = empty_scene();
  s.meshes.push_back(scene::make_box({20, 20, 0.5f}, 1));
  s.materials.push_back(material({1, 1, 1}));
  s.instances.push_back(place(0, 0, {0, 0, -distance - 0.5f}, 7, 3));
  return s;
}

TEST(Renderer, DepthOfAPlaneIsItsDistanceEverywhere) {
  Renderer r(wall_scene(3.0f));
  const FrameBuffers f = r.render();
  for (int y = 0; y < f.depth.rows; ++y) {
    for (int x = 0; x < f.depth.cols; ++x) {
      ASSERT_NEAR(f.depth.at<float>(y, x), 3.0f, 1e-3f) << x << "," << y;
      ASSERT_EQ(f.instance.at<std::uint16_t>(y, x), 7);
      ASSERT_EQ(f.semantic.at<std::uint16_t>(y, x), 3);
      const cv::Vec3f n = f.normals.at<cv::Vec3f>(y, x);
      ASSERT_NEAR(n[2], 1.0f, 1e-5f);  // facing the camera: +Z in camera space
    }
  }
}

TEST(Renderer, MotionOfAMovingWallIsItsProjectedTravel) {
  scene::Scene s = wall_scene(3.0f);
  EXPECT_TRUE(Renderer(s).render().motion.empty());  // nothing moves: no motion buffer
  s.meshes[0].motion.assign(s.meshes[0].positions.size(), Eigen::Vector3f(0.1f, -0.05f, 0));
  Renderer r(s);
  const FrameBuffers f = r.render();
  ASSERT_EQ(f.motion.type(), CV_32FC2);
  // Pinhole focal length in pixels: half the height over tan(half the vertical field of view).
  const float focal = 24.0f / std::tan(22.5f * std::numbers::pi_v<float> / 180.0f);
  for (int y = 0; y < f.motion.rows; ++y) {
    for (int x = 0; x < f.motion.cols; ++x) {
      const cv::Vec2f m = f.motion.at<cv::Vec2f>(y, x);
      ASSERT_NEAR(m[0], focal * 0.1f / 3.0f, 1e-3f) << x << "," << y;
      ASSERT_NEAR(m[1], focal * 0.05f / 3.0f, 1e-3f) << x << "," << y;  // image y points down
    }
  }
}

TEST(Renderer, DepthOfASphereMatchesTheAnalyticIntersection) {
  scene::Scene s = empty_scene(64, 48);
  s.camera.position = Eigen::Vector3f(0.3f, -0.2f, 1.0f);
  s.meshes.push_back(scene::make_sphere(1.0f, 128));
  s.materials.push_back(material({1, 1, 1}));
  const Eigen::Vector3f c(0, 0, -4);
  s.instances.push_back(place(0, 0, c, 1, 1));
  Renderer r(s);
  const FrameBuffers f = r.render();
  const float t = std::tan(0.5f * s.camera.effective_vfov());
  int checked = 0;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const Eigen::Vector3f d = Eigen::Vector3f((2 * (x + 0.5f) / 64 - 1) * t * 64 / 48,
                                                (1 - 2 * (y + 0.5f) / 48) * t, -1)
                                    .normalized();
      const Eigen::Vector3f oc = s.camera.position - c;
      const float b = oc.dot(d), disc = b * b - (oc.squaredNorm() - 1.0f);
      if (disc <= 0) {
        EXPECT_EQ(f.instance.at<std::uint16_t>(y, x), 0);
        continue;
      }
      const float hit = -b - std::sqrt(disc);
      const Eigen::Vector3f n = (s.camera.position + hit * d - c).normalized();
      if (-n.dot(d) < 0.3f) continue;  // grazing: the tessellation differs from the sphere
      EXPECT_NEAR(f.depth.at<float>(y, x), hit * -d.z(), 1e-3f) << x << "," << y;
      EXPECT_EQ(f.instance.at<std::uint16_t>(y, x), 1);
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);
}

TEST(Renderer, IdsAndNormalsPerRegion) {
  scene::Scene s = empty_scene();
  s.meshes.push_back(scene::make_box({0.5f, 0.5f, 0.5f}, 1));
  s.materials.push_back(material({1, 1, 1}));
  s.instances.push_back(place(0, 0, {-1.0f, 0, -4}, 11, 1));
  s.instances.push_back(place(0, 0, {1.0f, 0, -4}, 12, 2));
  Renderer r(s);
  const FrameBuffers f = r.render();
  // Left box around x ≈ 32 − 1/(4·tan 22.5°)·24 ≈ 17, right box ≈ 47; corners see nothing.
  EXPECT_EQ(f.instance.at<std::uint16_t>(24, 17), 11);
  EXPECT_EQ(f.semantic.at<std::uint16_t>(24, 17), 1);
  EXPECT_EQ(f.instance.at<std::uint16_t>(24, 47), 12);
  EXPECT_EQ(f.semantic.at<std::uint16_t>(24, 47), 2);
  EXPECT_EQ(f.instance.at<std::uint16_t>(24, 32), 0);
  EXPECT_EQ(f.instance.at<std::uint16_t>(0, 0), 0);
  EXPECT_EQ(f.depth.at<float>(0, 0), 0.0f);
  int hits = 0;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const cv::Vec3f n = f.normals.at<cv::Vec3f>(y, x);
      if (f.instance.at<std::uint16_t>(y, x) == 0) {
        EXPECT_EQ(n.dot(n), 0.0f);
        continue;
      }
      ++hits;
      EXPECT_NEAR(std::sqrt(n.dot(n)), 1.0f, 1e-5f);
      // Facing the camera: against the pixel's ray (camera space).
      const float t = std::tan(0.5f * s.camera.effective_vfov());
      const cv::Vec3f d((2 * (x + 0.5f) / 64 - 1) * t * 64 / 48, (1 - 2 * (y + 0.5f) / 48) * t, -1);
      EXPECT_LT(n.dot(d), 0.0f);
    }
  }
  EXPECT_GT(hits, 300);
}

// A card of hair strands (render/strands.h) 1.5 m in front of a sunlit wall, the sun behind the
// camera: the camera sees the wall between the strands, and the strands' shadows fall on it.
TEST(Renderer, RaysAndShadowsPassBetweenHairStrands) {
  for (const float coverage : {0.0f, 0.4f}) {  // 0: an opaque card
    scene::Scene s = wall_scene(3.0f);
    s.sun.enabled = true;
    s.sun.direction = Eigen::Vector3f(0, 0, 1);
    s.sun.angular_radius_deg = 0;
    s.sun.color = Eigen::Vector3f::Ones();
    s.meshes.push_back(scene::make_plane(2, 2, 1));  // u along x, v along y once stood up
    s.materials.push_back(material({0.3f, 0.2f, 0.1f}));
    s.materials.back().strands_per_uv = coverage > 0 ? 40 : 0;  // 10 strands per metre
    s.materials.back().strand_coverage = coverage > 0 ? coverage : 0.7f;
    s.instances.push_back(place(1, 1, {0, 0, -1.5f}, 5, 5));
    s.instances.back().transform.topLeftCorner<3, 3>() =
        Eigen::AngleAxisf(0.5f * std::numbers::pi_v<float>, Eigen::Vector3f::UnitX()).matrix();
    Renderer r(s);
    const FrameBuffers f = r.render();
    int on_card = 0, on_wall = 0;
    double wall_light = 0;
    for (int y = 0; y < f.instance.rows; ++y) {
      for (int x = 0; x < f.instance.cols; ++x) {
        const int id = f.instance.at<std::uint16_t>(y, x);
        on_card += id == 5;
        if (id == 7) on_wall += 1, wall_light += f.linear.at<cv::Vec3f>(y, x)[0];
      }
    }
    const double card_share = static_cast<double>(on_card) / (on_card + on_wall);
    if (coverage == 0) {
      EXPECT_EQ(on_wall, 0);
      continue;
    }
    EXPECT_NEAR(card_share, coverage, 0.08);
    // Sunlit wall is 1 (albedo 1, intensity 1); the strands' shadows darken ~coverage of it.
    EXPECT_NEAR(wall_light / on_wall, 1 - coverage, 0.12);
  }
}

TEST(Renderer, SunOnAWhiteWallGivesItsIntensity) {
  scene::Scene s = wall_scene(2.0f);
  s.sun.enabled = true;
  s.sun.direction = Eigen::Vector3f(0, 0, 1);
  s.sun.color = Eigen::Vector3f(1, 1, 1);
  s.sun.intensity = 0.5f;
  s.sun.angular_radius_deg = 0;
  s.materials[0].diffuse = Eigen::Vector3f(0.8f, 0.4f, 0.2f);
  Renderer r(s);
  const cv::Vec3f c = r.render().linear.at<cv::Vec3f>(24, 32);
  EXPECT_NEAR(c[0], 0.4f, 1e-5f);
  EXPECT_NEAR(c[1], 0.2f, 1e-5f);
  EXPECT_NEAR(c[2], 0.1f, 1e-5f);
}

TEST(Renderer, PointLightFallsOffWithTheSquareOfDistance) {
  scene::Scene s = wall_scene(2.0f);
  s.point_lights.push_back({{0, 0, -1}, {1, 1, 1}, 0.5f, 0.0f, true});  // 1 m from the wall
  s.point_lights.push_back({{0, 0, 0}, {1, 1, 1}, 50.0f, 0.0f, false});
  Renderer r(s);
  const FrameBuffers f = r.render();
  EXPECT_NEAR(f.linear.at<cv::Vec3f>(24, 32)[0], 0.5f, 0.01f);  // I / d² · cos ≈ 0.5 at the centre
  // Toward the edge the light is farther and more oblique: darker.
  EXPECT_LT(f.linear.at<cv::Vec3f>(24, 2)[0], 0.35f);
}

TEST(Renderer, ABoxBetweenSunAndWallCastsAShadow) {
  scene::Scene s = wall_scene(3.0f);
  s.sun.enabled = true;
  s.sun.direction = Eigen::Vector3f(0, 0, 1);
  s.sun.angular_radius_deg = 0;
  s.sun.color = Eigen::Vector3f::Ones();
  s.meshes.push_back(scene::make_box({0.2f, 0.2f, 0.2f}, 1));
  // Behind the camera, between the sun (at +Z) and the wall: invisible but it shadows.
  s.instances.push_back(place(1, 0, {0, 0, 1}, 9, 9));
  Renderer r(s);
  const FrameBuffers f = r.render();
  EXPECT_EQ(f.instance.at<std::uint16_t>(24, 32), 7);
  EXPECT_EQ(f.linear.at<cv::Vec3f>(24, 32)[0], 0.0f);
  EXPECT_NEAR(f.linear.at<cv::Vec3f>(2, 2)[0], 1.0f, 1e-5f);
}

// A wall the sun only grazes (straight down), above a wide sunlit floor: direct light leaves it
// black; one bounce lights it with the floor's radiance times the view factor of a vertical
// surface to an infinite floor below it, 1/2, whatever the height — a_wall × a_floor × I / 2.
TEST(Renderer, OneBounceLightsAGrazedWallWithHalfTheFloorsRadiance) {
  scene::Scene s = wall_scene(2.0f);
  s.materials[0].diffuse = Eigen::Vector3f(0.8f, 0.8f, 0.8f);
  s.meshes.push_back(scene::make_plane(200, 200, 1));
  s.materials.push_back(material({0.5f, 0.25f, 0.5f}));
  s.instances.push_back(place(1, 1, {0, -1, 0}, 8, 4));  // below the camera's view of the wall
  s.sun.enabled = true;
  s.sun.direction = Eigen::Vector3f(0, 1, 0);
  s.sun.color = Eigen::Vector3f::Ones();
  s.sun.intensity = 1.0f;
  s.sun.angular_radius_deg = 0;
  const FrameBuffers direct = Renderer(s).render({.spp = 4});
  const FrameBuffers bounced = Renderer(s).render({.spp = 4, .bounce = true});
  ASSERT_EQ(cv::countNonZero(bounced.instance == 7), 64 * 48);  // only the wall in view
  EXPECT_EQ(cv::norm(direct.linear, cv::NORM_INF), 0.0);
  const cv::Scalar top = cv::mean(bounced.linear(cv::Rect(0, 0, 64, 24)));
  const cv::Scalar bottom = cv::mean(bounced.linear(cv::Rect(0, 24, 64, 24)));
  std::printf("[ NOTE ] wall: top %.4f %.4f %.4f, bottom %.4f %.4f %.4f\n", top[0], top[1], top[2],
              bottom[0], bottom[1], bottom[2]);
  for (int c = 0; c < 3; ++c) {
    const double expected = 0.8 * s.materials[1].diffuse[c] / 2;
    EXPECT_NEAR(top[c], expected, 0.05 * expected) << "channel " << c;
    EXPECT_NEAR(bottom[c], expected, 0.05 * expected) << "channel " << c;
  }
  // One bounce ray per pixel is noisy; smoothed over a wider window than the direct light the
  // evenly lit wall comes out even (the direct light's 7×7 window left 17 % noise).
  cv::Scalar mean, deviation;
  cv::meanStdDev(bounced.linear(cv::Rect(8, 8, 48, 32)), mean, deviation);
  std::printf("[ NOTE ] wall noise: %.3f of the mean\n", deviation[0] / mean[0]);
  EXPECT_LT(deviation[0] / mean[0], 0.07);
}

TEST(Renderer, SolarSunBelowTheHorizonGivesNoLight) {
  scene::Scene s = wall_scene(2.0f);
  s.sun.enabled = true;
  s.sun.solar = scene::SolarPosition{0.0f, 172.0f, 45.0f};  // midnight
  Renderer r(s);
  EXPECT_EQ(r.render().linear.at<cv::Vec3f>(24, 32)[1], 0.0f);
}

TEST(Renderer, SameImageWhateverTheThreadCount) {
  const scene::Scene s = testing::shadow();
  FrameBuffers one, two;
  for (const bool bounce : {false, true}) {
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
      one = Renderer(s).render({.spp = 3, .bounce = bounce});
    }
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
      two = Renderer(s).render({.spp = 3, .bounce = bounce});
    }
    EXPECT_EQ(cv::norm(one.linear, two.linear, cv::NORM_INF), 0.0) << "bounce " << bounce;
    EXPECT_EQ(cv::norm(one.rgb, two.rgb, cv::NORM_INF), 0.0) << "bounce " << bounce;
  }
  // And a different seed gives a different (noisy) image.
  scene::Scene other = s;
  other.seed = 99;
  EXPECT_GT(cv::norm(Renderer(other).render({.spp = 3}).linear, one.linear, cv::NORM_INF), 0.0);
}

TEST(Renderer, GroundTruthDoesNotDependOnSamplesOrLens) {
  scene::Scene s = testing::depth_of_field();
  const FrameBuffers a = Renderer(s).render({.spp = 1});
  const FrameBuffers b = Renderer(s).render({.spp = 4});
  s.camera.aperture_radius = 0;
  const FrameBuffers c = Renderer(s).render({.spp = 1});
  EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.depth, c.depth, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.instance, c.instance, cv::NORM_INF), 0.0);
}

TEST(Renderer, RayQueryFindsTheFirstHitTowardAPoint) {
  Renderer r(wall_scene(3.0f));
  const RayQuery behind = r.first_hit_toward({0.5f, 0.2f, -5.0f});
  ASSERT_TRUE(behind.hit);
  const float expected = 3.0f * Eigen::Vector3f(0.5f, 0.2f, -5.0f).norm() / 5.0f;
  EXPECT_NEAR(behind.distance, expected, 1e-4f);
  EXPECT_EQ(behind.instance_id, 7);
  EXPECT_EQ(behind.instance_index, 0);
  EXPECT_NEAR(behind.position.z(), -3.0f, 1e-4f);
  const RayQuery in_front = r.first_hit_toward({0, 0, -1});
  EXPECT_GT(in_front.distance, 1.0f);  // the point is visible: the first hit lies beyond it
  EXPECT_FALSE(r.cast({0, 0, 0}, {0, 0, 1}).hit);
  EXPECT_FALSE(r.cast({0, 0, 0}, {0, 0, -1}, 2.0f).hit);
}

TEST(Renderer, EmptySceneShowsTheBackground) {
  scene::Scene s = empty_scene(16, 8);
  s.background.color = {0.5f, 0.25f, 0.0f};
  const FrameBuffers f = Renderer(s).render({.spp = 2});
  EXPECT_EQ(f.linear.at<cv::Vec3f>(3, 3), cv::Vec3f(0.5f, 0.25f, 0.0f));
  EXPECT_EQ(f.rgb.at<cv::Vec3b>(3, 3), cv::Vec3b(188, 137, 0));  // sRGB of 0.5 and 0.25
}

}  // namespace
}  // namespace wheelpose::render

namespace wheelpose::render {
namespace {

// A wall lit only by an environment. With a map of constant radiance L the importance-sampled
// estimate must converge to the uniform sky's albedo × L (half the sphere is behind the wall,
// so a wrong pdf or a lost cosine shows up as a factor); with a map bright on one side only,
// the side facing the bright half gets more light.
// Root-mean-square difference of two linear images.
double rms(const cv::Mat& a, const cv::Mat& b) {
  return cv::norm(a, b, cv::NORM_L2) / std::sqrt(static_cast<double>(a.total() * a.channels()));
}

// Decoupled shading (one light sample per pixel, reused by the other samples, denoised) must
// converge to what lighting every sample gives, and with less noise than lighting one sample.
TEST(Renderer, DecoupledShadingMatchesBruteForceWithLessNoise) {
  const scene::Scene s = testing::shadow();
  const cv::Mat reference =
      Renderer(s)
          .render({.spp = 64, .light_samples = 64, .denoise_radius = 0, .post = false})
          .linear;
  const cv::Mat decoupled = Renderer(s).render({.spp = 4, .post = false}).linear;
  const cv::Mat raw =
      Renderer(s).render({.spp = 4, .light_samples = 1, .denoise_radius = 0, .post = false}).linear;
  const cv::Scalar mean_ref = cv::mean(reference), mean_dec = cv::mean(decoupled);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean_dec[c], mean_ref[c], 0.03 * mean_ref[c]) << c;
  const double error_decoupled = rms(decoupled, reference), error_raw = rms(raw, reference);
  EXPECT_LT(error_decoupled, 0.7 * error_raw) << error_decoupled << " vs " << error_raw;
}

// Light samples are stratified across pixels (render/strata.h), so the mean of an aligned 8×8
// block of one-sample, unsmoothed lighting lies closer to the converged value than the mean
// of 64 independent samples: with those, the squared error of a block mean would be about the
// mean squared error of a pixel / 64 (measured: 1.00 of it with white-noise samples, 0.40 with
// the strata).
TEST(Renderer, LightSamplesAreStratifiedAcrossPixels) {
  scene::Scene s = testing::shadow();  // 64×48: 8×6 blocks
  s.environment = scene::Environment{};
  s.environment->color = Eigen::Vector3f(0.3f, 0.3f, 0.3f);  // sky occlusion beside the box
  const RenderOptions one_sample{.spp = 1, .denoise_radius = 0, .post = false};
  auto render_seed = [&](std::uint64_t seed) {
    scene::Scene seeded = s;
    seeded.seed = seed;
    return Renderer(seeded).render(one_sample).linear;
  };
  // Sample 0 goes through the pixel centre, so the mean over seeds converges per pixel.
  constexpr int kSeeds = 96;
  cv::Mat converged = cv::Mat::zeros(48, 64, CV_32FC3);
  for (int seed = 0; seed < kSeeds; ++seed) converged += render_seed(1000 + seed) / kSeeds;
  double pixel_error = 0, block_error = 0;
  for (int seed = 0; seed < 8; ++seed) {
    const cv::Mat error = render_seed(static_cast<std::uint64_t>(seed)) - converged;
    const cv::Mat squared = error.mul(error);
    const cv::Scalar mean_squared = cv::mean(squared);
    pixel_error += mean_squared[0] + mean_squared[1] + mean_squared[2];
    cv::Mat block_means;
    cv::resize(error, block_means, cv::Size(8, 6), 0, 0, cv::INTER_AREA);
    const cv::Mat block_squared = block_means.mul(block_means);
    const cv::Scalar block_mean_squared = cv::mean(block_squared);
    block_error += block_mean_squared[0] + block_mean_squared[1] + block_mean_squared[2];
  }
  ASSERT_GT(pixel_error, 0.0);
  EXPECT_LT(block_error, 0.7 * pixel_error / 64.0) << block_error << " vs " << pixel_error / 64;
}

// With every sample lighting and no smoothing, a pixel's samples on one untextured surface give
// the brute-force estimate: Σ albedo × mean lighting = Σ albedo × lighting per sample.
TEST(Renderer, AllLightSamplesWithoutDenoisingIsBruteForceOnPlainSurfaces) {
  const scene::Scene s = testing::shadow();
  const cv::Mat a =
      Renderer(s)
          .render({.spp = 16, .light_samples = 16, .denoise_radius = 0, .post = false})
          .linear;
  const cv::Mat b =
      Renderer(s)
          .render({.spp = 16, .light_samples = 16, .denoise_radius = 0, .post = false})
          .linear;
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);  // deterministic
  const cv::Mat fewer =
      Renderer(s)
          .render({.spp = 16, .light_samples = 4, .denoise_radius = 0, .post = false})
          .linear;
  EXPECT_GT(cv::norm(a, fewer, cv::NORM_INF), 0.0);  // the option is honoured
  EXPECT_NEAR(cv::mean(fewer)[1], cv::mean(a)[1], 0.03 * cv::mean(a)[1]);
}

// Adaptive anti-aliasing gives every pixel either exactly what uniform sampling gives it (edge
// pixels) or exactly what its first sample gives it (on plain surfaces the two often agree);
// every pixel next to another instance is refined.
TEST(Renderer, AdaptivePixelsTakeTheUniformValueOrTheFirstSamplesValue) {
  for (const scene::Scene& s : {testing::lit_sphere(), testing::textured_plane()}) {
    Renderer r(s);
    const FrameBuffers adaptive = r.render({.spp = 4, .post = false});
    const double refined = r.timings().refined_fraction;
    const FrameBuffers uniform = r.render({.spp = 4, .adaptive_contrast = -1, .post = false});
    EXPECT_EQ(r.timings().refined_fraction, 1.0);
    const FrameBuffers first = r.render({.spp = 1, .post = false});
    EXPECT_GT(refined, 0.02);
    EXPECT_LT(refined, 0.8);
    int as_uniform = 0;
    for (int y = 0; y < s.camera.height; ++y) {
      for (int x = 0; x < s.camera.width; ++x) {
        const cv::Vec3f a = adaptive.linear.at<cv::Vec3f>(y, x);
        const bool same_as_uniform = a == uniform.linear.at<cv::Vec3f>(y, x);
        const bool same_as_first = a == first.linear.at<cv::Vec3f>(y, x);
        ASSERT_TRUE(same_as_uniform || same_as_first) << x << "," << y;
        as_uniform += same_as_uniform && !same_as_first;
        const auto id = adaptive.instance.at<std::uint16_t>(y, x);
        bool at_edge = false;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = x + dx, qy = y + dy;
            if (qx >= 0 && qy >= 0 && qx < s.camera.width && qy < s.camera.height)
              at_edge |= adaptive.instance.at<std::uint16_t>(qy, qx) != id;
          }
        }
        if (at_edge) {
          EXPECT_TRUE(same_as_uniform) << x << "," << y;
        }
      }
    }
    EXPECT_GT(as_uniform, 0);  // edge pixels that more samples changed
  }
}

// A bar 0.3 px tall lying between two rows of pixel centres: no first sample sees it, so only
// the sliver test can send its pixels the samples that find it.
TEST(Renderer, AdaptiveFindsABarThinnerThanAPixelBetweenPixelCentres) {
  scene::Scene s = wall_scene(4.0f);
  s.materials.push_back(material({0, 0, 0}));
  const float distance = 2.0f;
  const float tan_half = std::tan(0.5f * s.camera.effective_vfov());
  auto world_y = [&](float film_y) {
    return (1.0f - 2.0f * film_y / static_cast<float>(s.camera.height)) * tan_half * distance;
  };
  const float top = world_y(20.05f), bottom = world_y(20.35f);  // centres are at 19.5 and 20.5
  s.meshes.push_back(scene::make_box({1.0f, 0.5f * (top - bottom), 0.01f}, 1));
  s.instances.push_back(place(1, 1, {0, 0.5f * (top + bottom), -distance}, 9, 4));
  s.environment = scene::Environment{};
  Renderer r(s);
  const FrameBuffers first = r.render({.spp = 1, .post = false});
  EXPECT_EQ(cv::countNonZero(first.instance == 9), 0);  // no pixel centre hits the bar
  const FrameBuffers adaptive = r.render({.spp = 8, .post = false});
  const FrameBuffers uniform = r.render({.spp = 8, .adaptive_contrast = -1, .post = false});
  const cv::Rect row(10, 20, 44, 1);
  EXPECT_EQ(cv::norm(adaptive.linear(row), uniform.linear(row), cv::NORM_INF), 0.0);
  // The bar darkens the row: samples found it.
  EXPECT_LT(cv::mean(adaptive.linear(row))[0], 0.9 * cv::mean(first.linear(row))[0]);
}

TEST(Renderer, RejectsBadSamplingOptions) {
  Renderer r(wall_scene(2.0f));
  EXPECT_THROW(r.render({.spp = 0}), Error);
  EXPECT_THROW(r.render({.spp = 2, .light_samples = 3}), Error);
  EXPECT_THROW(r.render({.spp = 2, .light_samples = 0}), Error);
  EXPECT_THROW(r.render({.spp = 2, .denoise_radius = -1}), Error);
}

// A map with a tiny, very bright sun (like Blender's HDRIs: 34 000 against a mean of 1) must not
// give fireflies: every pixel of a plain wall lit by it stays near the image mean.
TEST(Renderer, EnvironmentMapWithASmallSunHasNoFireflies) {
  const std::string dir = ::testing::TempDir();
  cv::Mat map(64, 128, CV_32FC3, cv::Scalar::all(0.5));
  // Straight behind the camera (+Z, which the wall faces): column 0, the horizon rows.
  for (int y = 31; y <= 32; ++y) map.at<cv::Vec3f>(y, 0) = cv::Vec3f(20000, 20000, 20000);
  cv::imwrite(dir + "/small_sun.exr", map);
  scene::Scene s = wall_scene(2.0f);
  scene::Environment sky;
  sky.path = dir + "/small_sun.exr";
  s.environment = sky;
  const cv::Mat linear =
      Renderer(s).render({.spp = 4, .light_samples = 4, .denoise_radius = 0, .post = false}).linear;
  double low = 0, high = 0;
  cv::minMaxLoc(linear.reshape(1), &low, &high);
  const double mean = cv::mean(linear)[0];
  EXPECT_GT(mean, 0.0);
  EXPECT_LT(high, 3.0 * mean) << "max " << high << " mean " << mean;
}

TEST(Renderer, EnvironmentMapSamplingMatchesTheUniformSky) {
  const std::string dir = ::testing::TempDir();
  cv::Mat flat(64, 128, CV_32FC3, cv::Scalar::all(0.25));
  cv::imwrite(dir + "/flat.exr", flat);
  scene::Scene s = wall_scene(2.0f);
  s.materials[0].diffuse = Eigen::Vector3f(0.8f, 0.8f, 0.8f);
  scene::Environment uniform;
  uniform.color = Eigen::Vector3f(0.25f, 0.25f, 0.25f);
  s.environment = uniform;
  // Every sample lights, unsmoothed: this checks the estimator, not the denoiser.
  const RenderOptions brute{.spp = 16, .light_samples = 16, .denoise_radius = 0, .post = false};
  const FrameBuffers expected = Renderer(s).render(brute);
  scene::Environment mapped;
  mapped.path = dir + "/flat.exr";
  s.environment = mapped;
  const FrameBuffers actual = Renderer(s).render(brute);
  const double e = cv::mean(expected.linear)[0], a = cv::mean(actual.linear)[0];
  EXPECT_NEAR(e, 0.8 * 0.25, 0.01);
  EXPECT_NEAR(a, e, 0.02 * e);
}

}  // namespace
}  // namespace wheelpose::render
