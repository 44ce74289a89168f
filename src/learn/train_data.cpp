#include "learn/train_data.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/random.h"

namespace wheelpose::learn {

namespace fs = std::filesystem;

TrainSource parse_train_source(const std::string& text) {
  TrainSource source{text, 1.0};
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || text.substr(colon + 1).find('/') != std::string::npos) {
    return source;
  }
  const std::string weight = text.substr(colon + 1);
  double value = 0;
  const auto [end, ec] = std::from_chars(weight.data(), weight.data() + weight.size(), value);
  if (ec != std::errc() || end != weight.data() + weight.size() || !(value > 0) ||
      !std::isfinite(value)) {
    throw Error("--train " + text + ": the weight after ':' must be a positive number");
  }
  source.coco = text.substr(0, colon);
  source.weight = value;
  return source;
}

fs::path image_root(const fs::path& coco) {
  const fs::path dir = coco.parent_path();
  return fs::is_directory(dir / "images") ? dir / "images" : dir;
}

TrainSet load_train_set(const std::vector<TrainSource>& sources) {
  if (sources.empty()) throw Error("no training data: give --train COCO.json");
  TrainSet set;
  for (const TrainSource& source : sources) {
    const coco::CocoGroundTruth gt = coco::load_coco_gt(source.coco, 17, false);
    const fs::path root = image_root(source.coco);
    std::vector<TrainImage> images(gt.images.size());
    for (std::size_t i = 0; i < gt.images.size(); ++i) {
      if (gt.images[i].file_name.empty()) {
        throw Error(source.coco.string() + ": image id " + std::to_string(gt.images[i].id) +
                    " has no file_name");
      }
      images[i].file = root / gt.images[i].file_name;
      images[i].weight = source.weight;
      if (!fs::is_regular_file(images[i].file)) {
        throw Error(source.coco.string() + ": image " + images[i].file.string() + " (id " +
                    std::to_string(gt.images[i].id) + ") not found");
      }
    }
    for (const coco::GtAnnotation& a : gt.annotations) {
      const int position = gt.image_position(a.image_id);
      if (position < 0 || a.bbox.w <= 0 || a.bbox.h <= 0) continue;
      TrainPerson person;
      person.box = a.bbox;
      person.ignore = a.iscrowd;
      bool labelled = false;
      if (!a.iscrowd && a.keypoints.size() == 51) {
        std::copy(a.keypoints.begin(), a.keypoints.end(), person.keypoints.begin());
        for (int k = 0; k < 17; ++k) labelled |= a.keypoints[3 * k + 2] > 0;
      }
      set.labelled_people += labelled ? 1 : 0;
      images[position].people.push_back(person);
    }
    for (TrainImage& image : images) {
      // An image is trained on around its people; crowd regions alone give no crop.
      if (std::any_of(image.people.begin(), image.people.end(),
                      [](const TrainPerson& p) { return !p.ignore; })) {
        set.images.push_back(std::move(image));
      }
    }
  }
  if (set.labelled_people == 0) {
    std::string names;
    for (const TrainSource& s : sources) names += (names.empty() ? "" : ", ") + s.coco.string();
    throw Error(names + ": no person with a labelled keypoint to train on");
  }
  return set;
}

namespace {

// The 2×3 affine map from image pixels to the network input: person centre (jittered) to the
// input centre, scaled, rotated, optionally mirrored.
cv::Matx23d input_transform(const cv::Point2d& centre, double scale, double degrees, bool flip,
                            int size) {
  const double angle = degrees * std::numbers::pi / 180.0;
  const double c = std::cos(angle) * scale, s = std::sin(angle) * scale;
  const double mirror = flip ? -1.0 : 1.0;
  // x' = mirror * (c (x - cx) - s (y - cy)) + size/2;  y' = s (x - cx) + c (y - cy) + size/2
  const double half = size / 2.0;
  return cv::Matx23d(mirror * c, -mirror * s, half - mirror * (c * centre.x - s * centre.y), s, c,
                     half - (s * centre.x + c * centre.y));
}

// The input image for continuous transform `m` (labels' coordinates: pixel i spans [i, i + 1)).
// A shrink goes through an area filter first, as predict's letterbox does: a bilinear warp that
// shrinks 2.5× samples every 2.5th pixel, and a network trained on such aliased inputs is
// scored on smooth ones. OpenCV's warp indexes pixels by their centres (index i is continuous
// i + 0.5), so the matrix is shifted to match, or every label would sit a fraction of a pixel
// off its pixels, by a different amount with and without a flip.
cv::Mat warp_image(const cv::Mat& rgb, const cv::Matx23d& m, double scale, int size) {
  cv::Mat source = rgb;
  cv::Matx23d a = m;
  if (scale < 1) {
    const int w = std::max(1, static_cast<int>(std::lround(rgb.cols * scale)));
    const int h = std::max(1, static_cast<int>(std::lround(rgb.rows * scale)));
    cv::resize(rgb, source, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    const double fx = static_cast<double>(w) / rgb.cols, fy = static_cast<double>(h) / rgb.rows;
    a = cv::Matx23d(m(0, 0) / fx, m(0, 1) / fy, m(0, 2), m(1, 0) / fx, m(1, 1) / fy, m(1, 2));
  }
  cv::Matx23d by_index = a;
  by_index(0, 2) += 0.5 * (a(0, 0) + a(0, 1)) - 0.5;
  by_index(1, 2) += 0.5 * (a(1, 0) + a(1, 1)) - 0.5;
  cv::Mat out;
  cv::warpAffine(source, out, by_index, cv::Size(size, size), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                 cv::Scalar(0, 0, 0));
  return out;
}

void jitter_colours(cv::Mat& rgb, RandomStream& random, double amount) {
  if (amount <= 0) return;
  const double brightness = random.uniform(1 - amount, 1 + amount);
  const double contrast = random.uniform(1 - amount, 1 + amount);
  const double saturation = random.uniform(1 - amount, 1 + amount);
  cv::Mat f;
  rgb.convertTo(f, CV_32FC3);
  cv::Mat grey;
  cv::cvtColor(f, grey, cv::COLOR_RGB2GRAY);
  const double mean = cv::mean(grey)[0];
  cv::Mat grey3;
  cv::cvtColor(grey, grey3, cv::COLOR_GRAY2RGB);
  cv::addWeighted(f, saturation, grey3, 1 - saturation, 0, f);  // around each pixel's grey
  f.convertTo(f, -1, contrast, mean * (1 - contrast));          // around the image mean
  f.convertTo(rgb, CV_8UC3, brightness);                        // saturates to 0..255
}

}  // namespace

TrainSample augment(const cv::Mat& rgb, const std::vector<TrainPerson>& people,
                    const std::vector<std::pair<int, int>>& flip_pairs, const AugmentOptions& o,
                    std::uint64_t random_seed, std::uint64_t key) {
  std::vector<std::size_t> anchors;  // the crop centres on a person, never a crowd region
  for (std::size_t i = 0; i < people.size(); ++i) {
    if (!people[i].ignore) anchors.push_back(i);
  }
  WHEELPOSE_CHECK(!rgb.empty() && !anchors.empty());
  RandomStream random(random_seed, {"augment", key});
  const TrainPerson& anchor =
      people[anchors[static_cast<std::size_t>(random.uniform_int(0, std::ssize(anchors) - 1))]];
  double scale = 0;
  if (o.person_size_max > 0) {
    const double side = std::max({anchor.box.w, anchor.box.h, 1.0});
    scale =
        std::exp(random.uniform(std::log(o.person_size_min), std::log(o.person_size_max))) / side;
  } else {
    const double base = static_cast<double>(o.target_longer_side) / std::max(rgb.cols, rgb.rows);
    scale = base * std::exp(random.uniform(std::log(o.scale_min), std::log(o.scale_max)));
  }
  const double shift = o.input_size * o.shift_fraction / scale;
  const cv::Point2d centre(anchor.box.x + anchor.box.w / 2 + random.uniform(-shift, shift),
                           anchor.box.y + anchor.box.h / 2 + random.uniform(-shift, shift));
  const double degrees = random.uniform(-o.rotate_degrees, o.rotate_degrees);
  const bool flip = random.uniform01() < o.flip_probability;  // one draw whatever p is
  const cv::Matx23d m = input_transform(centre, scale, degrees, flip, o.input_size);

  TrainSample sample;
  sample.rgb = warp_image(rgb, m, scale, o.input_size);
  auto map = [&](double x, double y) {
    return cv::Point2d(m(0, 0) * x + m(0, 1) * y + m(0, 2), m(1, 0) * x + m(1, 1) * y + m(1, 2));
  };
  const double size = o.input_size;
  for (const TrainPerson& p : people) {
    TrainPerson out;
    out.ignore = p.ignore;
    if (p.ignore) {
      // A region, not a person: the box of its mapped corners, so rotation never shrinks it.
      double x0 = size, y0 = size, x1 = 0, y1 = 0;
      for (const double fx : {0.0, 1.0}) {
        for (const double fy : {0.0, 1.0}) {
          const cv::Point2d q = map(p.box.x + fx * p.box.w, p.box.y + fy * p.box.h);
          x0 = std::min(x0, q.x), x1 = std::max(x1, q.x), y0 = std::min(y0, q.y);
          y1 = std::max(y1, q.y);
        }
      }
      x0 = std::clamp(x0, 0.0, size), x1 = std::clamp(x1, 0.0, size);
      y0 = std::clamp(y0, 0.0, size), y1 = std::clamp(y1, 0.0, size);
      if (x1 - x0 < 1 || y1 - y0 < 1) continue;  // left the input
      out.box = {x0, y0, x1 - x0, y1 - y0};
      sample.people.push_back(out);
      continue;
    }
    // The box of the ellipse inscribed in the person's box, carried through the transform:
    // exact without rotation, and under rotation far closer to the rotated person's own box
    // than the rotated corners, which would teach the box head to draw every box too wide.
    const cv::Point2d c = map(p.box.x + p.box.w / 2, p.box.y + p.box.h / 2);
    const double a = p.box.w / 2, b = p.box.h / 2;
    const double half_w = std::hypot(m(0, 0) * a, m(0, 1) * b);
    const double half_h = std::hypot(m(1, 0) * a, m(1, 1) * b);
    double x0 = c.x - half_w, x1 = c.x + half_w, y0 = c.y - half_h, y1 = c.y + half_h;
    x0 = std::clamp(x0, 0.0, size), x1 = std::clamp(x1, 0.0, size);
    y0 = std::clamp(y0, 0.0, size), y1 = std::clamp(y1, 0.0, size);
    if (x1 - x0 < 2 || y1 - y0 < 2) continue;  // left the input
    out.box = {x0, y0, x1 - x0, y1 - y0};
    for (int k = 0; k < 17; ++k) {
      const double v = p.keypoints[3 * k + 2];
      const cv::Point2d q = map(p.keypoints[3 * k], p.keypoints[3 * k + 1]);
      const bool inside = v > 0 && q.x >= 0 && q.y >= 0 && q.x < size && q.y < size;
      out.keypoints[3 * k] = inside ? q.x : 0;
      out.keypoints[3 * k + 1] = inside ? q.y : 0;
      out.keypoints[3 * k + 2] = inside ? v : 0;
    }
    if (flip) {
      for (const auto& [a, b] : flip_pairs) {
        for (int c = 0; c < 3; ++c) std::swap(out.keypoints[3 * a + c], out.keypoints[3 * b + c]);
      }
    }
    sample.people.push_back(out);
  }

  jitter_colours(sample.rgb, random, o.color_jitter);
  if (random.bernoulli(o.blur_probability)) {
    const double sigma = random.uniform(0.5, 1.5);
    cv::GaussianBlur(sample.rgb, sample.rgb, cv::Size(0, 0), sigma);
  }
  if (random.bernoulli(o.jpeg_probability)) {
    const int quality = static_cast<int>(random.uniform_int(40, 95));
    std::vector<std::uint8_t> encoded;
    cv::imencode(".jpg", sample.rgb, encoded, {cv::IMWRITE_JPEG_QUALITY, quality});
    sample.rgb = cv::imdecode(encoded, cv::IMREAD_COLOR);  // channel order kept as given
  }
  return sample;
}

std::size_t pick_image(const std::vector<double>& cumulative_weights, std::uint64_t seed,
                       std::int64_t step, int slot) {
  WHEELPOSE_CHECK(!cumulative_weights.empty());
  RandomStream random(seed, {"pick", static_cast<std::uint64_t>(step), slot});
  const double u = random.uniform01() * cumulative_weights.back();
  const auto it = std::upper_bound(cumulative_weights.begin(), cumulative_weights.end(), u);
  return std::min<std::size_t>(it - cumulative_weights.begin(), cumulative_weights.size() - 1);
}

}  // namespace wheelpose::learn
