#include "motion/preview.h"

#include <gif_lib.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <span>
#include <string>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose::motion {

namespace {

constexpr double kFloorGridStep = 0.5;  // metres between floor grid lines
constexpr double kFloorMargin = 0.5;    // floor extends this far beyond the motion's footprint
constexpr double kPanelMargin = 0.06;   // fraction of a panel left empty on each side

// An orthographic camera: screen axes `right` and `up` (world units), viewing along `forward`.
struct View {
  const char* label;
  Eigen::Vector3d right, up, forward;
};

// Camera placed on the unit sphere at azimuth `azimuth` (from +Z towards +X) and elevation
// `elevation` above the horizon, looking at the origin with world +Y up on screen.
View orbit_view(const char* label, double azimuth_deg, double elevation_deg) {
  const double az = azimuth_deg * std::numbers::pi / 180;
  const double el = elevation_deg * std::numbers::pi / 180;
  const Eigen::Vector3d eye(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
  const Eigen::Vector3d forward = -eye;
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitY()).normalized();
  return {label, right, right.cross(forward), forward};
}

const std::array<View, 4>& views() {
  static const std::array<View, 4> table = {
      orbit_view("oblique", 45, 45),
      orbit_view("front", 0, 0),
      // Straight down, with the subject's front towards the bottom of the panel.
      View{"top", Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, -1, 0)},
      orbit_view("side", -90, 0),
  };
  return table;
}

std::uint8_t bone_colour(int joint) {
  const std::string_view name = joint_name(joint);
  if (name.starts_with("left_")) return kPreviewLeft;
  if (name.starts_with("right_")) return kPreviewRight;
  return kPreviewCentre;
}

std::uint8_t joint_colour(int joint) {
  switch (bone_colour(joint)) {
    case kPreviewLeft:
      return kPreviewLeftJoint;
    case kPreviewRight:
      return kPreviewRightJoint;
    default:
      return kPreviewCentre;
  }
}

void check_positions(const std::vector<Pose>& positions) {
  if (positions.empty()) throw Error("preview: the clip has no frames", ErrorKind::kBadInput);
  for (std::size_t f = 0; f < positions.size(); ++f) {
    for (int j = 0; j < kJointCount; ++j) {
      if (!positions[f][j].allFinite()) {
        throw Error("preview: frame " + std::to_string(f) + ": position of '" +
                        std::string(joint_name(j)) + "' is not finite",
                    ErrorKind::kBadInput);
      }
    }
  }
}

// Everything fixed for the clip: floor, and per view the screen mapping.
struct Layout {
  double floor_y = 0;
  Eigen::Vector2d floor_min, floor_max;   // x, z extent of the floor grid
  double scale = 1;                       // pixels per metre, shared by all views
  std::array<Eigen::Vector2d, 4> centre;  // world screen-coordinates at each panel's centre
};

Layout make_layout(const std::vector<Pose>& positions, int view_size) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-INFINITY);
  for (const Pose& pose : positions) {
    for (const Eigen::Vector3d& p : pose) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  Layout layout;
  layout.floor_y = lo.y();
  layout.floor_min = Eigen::Vector2d(lo.x(), lo.z()).array() - kFloorMargin;
  layout.floor_max = Eigen::Vector2d(hi.x(), hi.z()).array() + kFloorMargin;
  // Snap the floor to the grid so lines sit at whole multiples of the step.
  layout.floor_min = (layout.floor_min / kFloorGridStep).array().floor() * kFloorGridStep;
  layout.floor_max = (layout.floor_max / kFloorGridStep).array().ceil() * kFloorGridStep;
  // Frame the motion's bounding box (not the floor) in every view with one common scale.
  const double usable = view_size * (1 - 2 * kPanelMargin);
  double scale = INFINITY;
  for (std::size_t v = 0; v < views().size(); ++v) {
    Eigen::Vector2d smin = Eigen::Vector2d::Constant(INFINITY);
    Eigen::Vector2d smax = Eigen::Vector2d::Constant(-INFINITY);
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d p((corner & 1) ? hi.x() : lo.x(), (corner & 2) ? hi.y() : lo.y(),
                              (corner & 4) ? hi.z() : lo.z());
      const Eigen::Vector2d s(p.dot(views()[v].right), p.dot(views()[v].up));
      smin = smin.cwiseMin(s);
      smax = smax.cwiseMax(s);
    }
    layout.centre[v] = (smin + smax) / 2;
    const double extent = std::max({smax.x() - smin.x(), smax.y() - smin.y(), 0.5});
    scale = std::min(scale, usable / extent);
  }
  layout.scale = scale;
  return layout;
}

cv::Point to_pixel(const Layout& layout, std::size_t v, int view_size, const Eigen::Vector3d& p) {
  const View& view = views()[v];
  const Eigen::Vector2d s(p.dot(view.right), p.dot(view.up));
  const Eigen::Vector2d d = (s - layout.centre[v]) * layout.scale;
  const int ox = static_cast<int>(v % 2) * view_size;
  const int oy = static_cast<int>(v / 2) * view_size;
  return cv::Point(ox + static_cast<int>(std::lround(view_size / 2.0 + d.x())),
                   oy + static_cast<int>(std::lround(view_size / 2.0 - d.y())));
}

void draw_frame(cv::Mat& image, const Layout& layout, const Pose& pose, int view_size) {
  image.setTo(cv::Scalar(kPreviewBackground));
  const int thickness = std::max(1, view_size / 128);
  const int radius = std::max(1, view_size / 85);
  for (std::size_t v = 0; v < views().size(); ++v) {
    const View& view = views()[v];
    // Each panel draws only inside its own square.
    const cv::Rect panel(static_cast<int>(v % 2) * view_size, static_cast<int>(v / 2) * view_size,
                         view_size, view_size);
    cv::Mat roi = image(panel);
    const cv::Point offset(panel.x, panel.y);
    auto pixel = [&](const Eigen::Vector3d& p) {
      return to_pixel(layout, v, view_size, p) - offset;
    };
    for (double x = layout.floor_min.x(); x <= layout.floor_max.x() + 1e-9; x += kFloorGridStep) {
      cv::line(roi, pixel({x, layout.floor_y, layout.floor_min.y()}),
               pixel({x, layout.floor_y, layout.floor_max.y()}), cv::Scalar(kPreviewFloor), 1,
               cv::LINE_8);
    }
    for (double z = layout.floor_min.y(); z <= layout.floor_max.y() + 1e-9; z += kFloorGridStep) {
      cv::line(roi, pixel({layout.floor_min.x(), layout.floor_y, z}),
               pixel({layout.floor_max.x(), layout.floor_y, z}), cv::Scalar(kPreviewFloor), 1,
               cv::LINE_8);
    }
    // Painter's order: far bones first, so the near side of the body is drawn on top.
    std::array<int, kJointCount - 1> bones{};
    int count = 0;
    for (int j = 0; j < kJointCount; ++j) {
      if (joint_parent(j) >= 0) bones[count++] = j;
    }
    auto depth = [&](int j) { return -(pose[j] + pose[joint_parent(j)]).dot(view.forward); };
    std::stable_sort(bones.begin(), bones.end(), [&](int a, int b) { return depth(a) < depth(b); });
    for (int j : bones) {
      cv::line(roi, pixel(pose[joint_parent(j)]), pixel(pose[j]), cv::Scalar(bone_colour(j)),
               thickness, cv::LINE_8);
    }
    for (int j = 0; j < kJointCount; ++j) {
      cv::circle(roi, pixel(pose[j]), radius, cv::Scalar(joint_colour(j)), cv::FILLED, cv::LINE_8);
    }
    cv::putText(roi, view.label, cv::Point(4, 4 + std::max(8, view_size / 20)),
                cv::FONT_HERSHEY_PLAIN, std::max(0.6, view_size / 256.0), cv::Scalar(kPreviewText),
                1, cv::LINE_8);
    cv::rectangle(roi, cv::Rect(0, 0, view_size, view_size), cv::Scalar(kPreviewFloor), 1,
                  cv::LINE_8);
  }
}

// Smallest rectangle holding every pixel that differs between two frames; a single pixel when
// nothing changed (a GIF frame cannot be empty).
cv::Rect changed_rectangle(const std::vector<std::uint8_t>& before,
                           const std::vector<std::uint8_t>& after, int size) {
  int x0 = size, y0 = size, x1 = -1, y1 = -1;
  for (int y = 0; y < size; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * size;
    for (int x = 0; x < size; ++x) {
      if (before[row + x] != after[row + x]) {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
    }
  }
  if (x1 < 0) return cv::Rect(0, 0, 1, 1);
  return cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
}

int append_to_buffer(GifFileType* gif, const GifByteType* data, int length) {
  auto* buffer = static_cast<std::vector<std::uint8_t>*>(gif->UserData);
  buffer->insert(buffer->end(), data, data + length);
  return length;
}

}  // namespace

const std::array<std::array<std::uint8_t, 3>, kPreviewPaletteSize>& preview_palette() {
  static const std::array<std::array<std::uint8_t, 3>, kPreviewPaletteSize> palette = {{
      {255, 255, 255},  // background
      {0, 0, 0},        // centre
      {30, 90, 255},    // left
      {235, 30, 30},    // right
      {205, 205, 205},  // floor
      {120, 120, 120},  // text
      {0, 30, 150},     // left joints
      {140, 0, 0},      // right joints
  }};
  return palette;
}

std::vector<std::vector<std::uint8_t>> render_preview_frames(const std::vector<Pose>& positions,
                                                             int view_size) {
  check_positions(positions);
  if (view_size < 32 || view_size > 4096) {
    throw Error("preview: view size must be 32..4096 pixels, got " + std::to_string(view_size),
                ErrorKind::kBadInput);
  }
  const Layout layout = make_layout(positions, view_size);
  cv::Mat image(2 * view_size, 2 * view_size, CV_8UC1);
  std::vector<std::vector<std::uint8_t>> frames;
  frames.reserve(positions.size());
  for (const Pose& pose : positions) {
    draw_frame(image, layout, pose, view_size);
    frames.emplace_back(image.data, image.data + image.total());
  }
  return frames;
}

void write_preview_gif(const std::vector<Pose>& positions, double fps,
                       const std::filesystem::path& path, const PreviewOptions& options) {
  const double rate = options.fps > 0 ? options.fps : fps;
  if (!(std::isfinite(rate) && rate > 0)) {
    throw Error(path.string() + ": preview fps must be positive, got " + std::to_string(rate),
                ErrorKind::kBadInput);
  }
  const std::vector<std::vector<std::uint8_t>> frames =
      render_preview_frames(positions, options.view_size);
  const int size = 2 * options.view_size;
  const int delay = std::max(2, static_cast<int>(std::lround(100.0 / rate)));

  std::vector<std::uint8_t> buffer;
  int error = 0;
  GifFileType* gif = EGifOpen(&buffer, append_to_buffer, &error);
  if (gif == nullptr) {
    throw Error(path.string() + ": cannot start GIF: " + GifErrorString(error),
                ErrorKind::kFailure);
  }
  auto fail = [&](const char* what) {
    const std::string reason = GifErrorString(gif->Error) ? GifErrorString(gif->Error) : "?";
    EGifCloseFile(gif, &error);
    throw Error(path.string() + ": GIF " + what + " failed: " + reason, ErrorKind::kFailure);
  };
  GifColorType colours[kPreviewPaletteSize];
  for (int i = 0; i < kPreviewPaletteSize; ++i) {
    colours[i] = {preview_palette()[i][0], preview_palette()[i][1], preview_palette()[i][2]};
  }
  ColorMapObject* map = GifMakeMapObject(kPreviewPaletteSize, colours);
  EGifSetGifVersion(gif, true);  // GIF89a: needed for delays and the loop extension
  const int screen_ok = EGifPutScreenDesc(gif, size, size, 8, kPreviewBackground, map);
  GifFreeMapObject(map);  // the encoder keeps its own copy
  if (screen_ok == GIF_ERROR) fail("screen descriptor");
  // NETSCAPE2.0 application extension: loop forever (count 0).
  static const GifByteType kNetscape[] = "NETSCAPE2.0";
  static const GifByteType kLoopForever[] = {1, 0, 0};
  if (EGifPutExtensionLeader(gif, APPLICATION_EXT_FUNC_CODE) == GIF_ERROR ||
      EGifPutExtensionBlock(gif, 11, kNetscape) == GIF_ERROR ||
      EGifPutExtensionBlock(gif, 3, kLoopForever) == GIF_ERROR ||
      EGifPutExtensionTrailer(gif) == GIF_ERROR) {
    fail("loop extension");
  }
  GraphicsControlBlock control{};
  control.DisposalMode = DISPOSE_DO_NOT;
  control.UserInputFlag = false;
  control.DelayTime = delay;
  control.TransparentColor = NO_TRANSPARENT_COLOR;
  GifByteType control_bytes[4];
  EGifGCBToExtension(&control, control_bytes);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    // Frames are drawn over the previous one (DISPOSE_DO_NOT), so only the rectangle that
    // changed is stored: the floor and labels never change, which shrinks files several-fold.
    const cv::Rect rect =
        f == 0 ? cv::Rect(0, 0, size, size) : changed_rectangle(frames[f - 1], frames[f], size);
    if (EGifPutExtension(gif, GRAPHICS_EXT_FUNC_CODE, 4, control_bytes) == GIF_ERROR) {
      fail("frame delay");
    }
    if (EGifPutImageDesc(gif, rect.x, rect.y, rect.width, rect.height, false, nullptr) ==
        GIF_ERROR) {
      fail("image descriptor");
    }
    for (int row = rect.y; row < rect.y + rect.height; ++row) {
      // giflib takes non-const rows but does not modify them.
      auto* line = const_cast<GifPixelType*>(frames[f].data() +
                                             static_cast<std::size_t>(row) * size + rect.x);
      if (EGifPutLine(gif, line, rect.width) == GIF_ERROR) fail("pixel data");
    }
  }
  if (EGifCloseFile(gif, &error) == GIF_ERROR) {
    throw Error(path.string() + ": GIF close failed: " + GifErrorString(error),
                ErrorKind::kFailure);
  }
  write_file_atomic(path, std::span<const std::uint8_t>(buffer));
}

}  // namespace wheelpose::motion
