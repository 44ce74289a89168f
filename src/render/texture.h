#pragma once
// Colour sources for materials, backgrounds and environments: decoded images (linear RGB,
// bilinear, wrapping) and procedural patterns evaluated on UVs.

#include <opencv2/core.hpp>
#include <string>

#include "core/srgb.h"
#include "scene/scene.h"

namespace wheelpose::render {

// Reads an image file as linear RGB floats (CV_32FC3, RGB order). 8/16-bit images are sRGB
// decoded; float images (.hdr) are taken as linear. `what` names the scene entry for errors
// (e.g. "/materials/2/texture/path"); an unreadable or zero-size image throws Error.
cv::Mat load_linear_image(const std::string& path, const std::string& what);

// An image's brightness detail for TextureKind::kImageDetail: its luminance, shrunk to at most
// kDetailSize pixels a side (a photo's weave finer than that would only alias on a garment a
// few hundred pixels tall), divided by its mean so it averages 1; the same in all three
// channels. Decoded once per path per process.
inline constexpr int kDetailSize = 128;
cv::Mat load_detail_image(const std::string& path, const std::string& what);

// Bilinear lookup with wrap-around; u to the right, v downward, both in image widths/heights.
Eigen::Vector3f sample_bilinear(const cv::Mat& image, float u, float v);

// The pattern value t ∈ [0, 1] of a procedural texture at uv (already multiplied by scale).
// `footprint` is the width of one pixel in the same units (0 = a point): noise octaves and
// fabric threads finer than that fade to their mean, a cheap stand-in for filtering the pattern
// over the pixel.
float procedural_pattern(const scene::Texture& texture, float u, float v, float footprint = 0);

// Rotates the hue of a linear RGB colour about the grey axis by `degrees`, keeping R+G+B
// (negative results clamp to 0). hue_rotation is the matrix, for callers that reuse it.
Eigen::Vector3f rotate_hue(const Eigen::Vector3f& rgb, float degrees);
Eigen::Matrix3f hue_rotation(float degrees);

// A texture ready to evaluate (the image decoded once).
class TextureSampler {
 public:
  TextureSampler() = default;
  TextureSampler(const scene::Texture& texture, const std::string& resolved_path,
                 const std::string& what);
  bool active() const { return texture_.kind != scene::TextureKind::kNone; }
  // The colour at uv: a multiplier for image textures, the blended colours for procedural ones.
  // `footprint`: one pixel's width in uv units (see procedural_pattern; images ignore it).
  Eigen::Vector3f at(float u, float v, float footprint = 0) const;
  // Whether `at` uses the footprint (noise-based procedural patterns).
  bool filters_detail() const;
  const cv::Mat& image() const { return image_; }

 private:
  scene::Texture texture_;
  cv::Mat image_;
};

}  // namespace wheelpose::render
