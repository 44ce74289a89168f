#include "motion/preview.h"

#include <gif_lib.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>

#include "core/error.h"
#include "motion/export_test_support.h"

namespace wheelpose::motion {

namespace {

struct GifCloser {
  void operator()(GifFileType* gif) const {
    int error = 0;
    DGifCloseFile(gif, &error);
  }
};
using GifPtr = std::unique_ptr<GifFileType, GifCloser>;

GifPtr decode(const std::filesystem::path& path) {
  int error = 0;
  GifPtr gif(DGifOpenFileName(path.c_str(), &error));
  EXPECT_NE(gif, nullptr) << GifErrorString(error);
  if (gif && DGifSlurp(gif.get()) != GIF_OK) {
    ADD_FAILURE() << "DGifSlurp: " << GifErrorString(gif->Error);
    return nullptr;
  }
  return gif;
}

// Plays the GIF: every image is drawn over the canvas at its position (all our frames use
// DISPOSE_DO_NOT and no transparency).
std::vector<std::vector<std::uint8_t>> compose(const GifFileType& gif) {
  std::vector<std::uint8_t> canvas(static_cast<std::size_t>(gif.SWidth) * gif.SHeight,
                                   static_cast<std::uint8_t>(gif.SBackGroundColor));
  std::vector<std::vector<std::uint8_t>> frames;
  for (int i = 0; i < gif.ImageCount; ++i) {
    const GifImageDesc& d = gif.SavedImages[i].ImageDesc;
    EXPECT_LE(d.Left + d.Width, gif.SWidth);
    EXPECT_LE(d.Top + d.Height, gif.SHeight);
    for (int y = 0; y < d.Height; ++y) {
      for (int x = 0; x < d.Width; ++x) {
        canvas[static_cast<std::size_t>(d.Top + y) * gif.SWidth + d.Left + x] =
            gif.SavedImages[i].RasterBits[y * d.Width + x];
      }
    }
    frames.push_back(canvas);
  }
  return frames;
}

bool has_loop_extension(const GifFileType& gif) {
  for (int i = 0; i < gif.ImageCount; ++i) {
    const SavedImage& image = gif.SavedImages[i];
    for (int b = 0; b + 1 < image.ExtensionBlockCount; ++b) {
      const ExtensionBlock& block = image.ExtensionBlocks[b];
      const ExtensionBlock& next = image.ExtensionBlocks[b + 1];
      if (block.Function == APPLICATION_EXT_FUNC_CODE && block.ByteCount == 11 &&
          std::memcmp(block.Bytes, "NETSCAPE2.0", 11) == 0 &&
          next.Function == CONTINUE_EXT_FUNC_CODE && next.ByteCount == 3 && next.Bytes[0] == 1 &&
          next.Bytes[1] == 0 && next.Bytes[2] == 0) {
        return true;
      }
    }
  }
  return false;
}

// Mean column of the pixels of `colour` inside panel `panel` (0..3) of a frame; -1 if none.
double mean_column(const SavedImage& image, int width, int view_size, int panel,
                   std::uint8_t colour, int* count = nullptr) {
  const int x0 = (panel % 2) * view_size;
  const int y0 = (panel / 2) * view_size;
  double sum = 0;
  int n = 0;
  for (int y = y0; y < y0 + view_size; ++y) {
    for (int x = x0; x < x0 + view_size; ++x) {
      if (image.RasterBits[y * width + x] == colour) {
        sum += x - x0;
        ++n;
      }
    }
  }
  if (count != nullptr) *count = n;
  return n > 0 ? sum / n : -1;
}

double mean_row(const SavedImage& image, int width, int view_size, int panel, std::uint8_t colour) {
  const int x0 = (panel % 2) * view_size;
  const int y0 = (panel / 2) * view_size;
  double sum = 0;
  int n = 0;
  for (int y = y0; y < y0 + view_size; ++y) {
    for (int x = x0; x < x0 + view_size; ++x) {
      if (image.RasterBits[y * width + x] == colour) {
        sum += y - y0;
        ++n;
      }
    }
  }
  return n > 0 ? sum / n : -1;
}

TEST(PreviewGif, DecodesWithFramesLoopDelayAndPalette) {
  const auto dir = export_test::temp_dir("preview");
  const SkeletalMotion motion = export_test::make_test_motion(6, 30.0);
  const std::vector<Pose> positions = forward_kinematics(motion);
  PreviewOptions options;
  options.view_size = 96;
  write_preview_gif(positions, motion.fps, dir / "clip.gif", options);
  GifPtr gif = decode(dir / "clip.gif");
  ASSERT_NE(gif, nullptr);
  EXPECT_EQ(gif->SWidth, 192);
  EXPECT_EQ(gif->SHeight, 192);
  ASSERT_EQ(gif->ImageCount, 6);
  EXPECT_TRUE(has_loop_extension(*gif));
  ASSERT_NE(gif->SColorMap, nullptr);
  ASSERT_EQ(gif->SColorMap->ColorCount, kPreviewPaletteSize);
  for (int i = 0; i < kPreviewPaletteSize; ++i) {
    EXPECT_EQ(gif->SColorMap->Colors[i].Red, preview_palette()[i][0]);
    EXPECT_EQ(gif->SColorMap->Colors[i].Green, preview_palette()[i][1]);
    EXPECT_EQ(gif->SColorMap->Colors[i].Blue, preview_palette()[i][2]);
  }
  for (int i = 0; i < gif->ImageCount; ++i) {
    GraphicsControlBlock control;
    ASSERT_EQ(DGifSavedExtensionToGCB(gif.get(), i, &control), GIF_OK);
    EXPECT_EQ(control.DelayTime, 3);  // 100 / 30 fps, rounded
    EXPECT_EQ(control.DisposalMode, DISPOSE_DO_NOT);
    const SavedImage& image = gif->SavedImages[i];
    const int pixels = image.ImageDesc.Width * image.ImageDesc.Height;
    int left = 0, right = 0, centre = 0;
    for (int p = 0; p < pixels; ++p) {
      left += image.RasterBits[p] == kPreviewLeft;
      right += image.RasterBits[p] == kPreviewRight;
      centre += image.RasterBits[p] == kPreviewCentre;
    }
    EXPECT_GT(left, 0) << "frame " << i;
    EXPECT_GT(right, 0) << "frame " << i;
    EXPECT_GT(centre, 0) << "frame " << i;
  }
  // Played back (each frame drawn over the previous one), the GIF shows exactly the rendered
  // frames; the pose changes every frame, so every frame differs from the previous one.
  const std::vector<std::vector<std::uint8_t>> composed = compose(*gif);
  EXPECT_TRUE(composed == render_preview_frames(positions, 96));
  for (std::size_t i = 1; i < composed.size(); ++i) {
    EXPECT_NE(composed[i], composed[i - 1]) << "frame " << i;
  }
  // A still clip stores one full frame and then single-pixel updates.
  write_preview_gif(std::vector<Pose>(4, positions[0]), motion.fps, dir / "still.gif", options);
  GifPtr still = decode(dir / "still.gif");
  ASSERT_NE(still, nullptr);
  ASSERT_EQ(still->ImageCount, 4);
  EXPECT_EQ(still->SavedImages[0].ImageDesc.Width, 192);
  EXPECT_EQ(still->SavedImages[3].ImageDesc.Width * still->SavedImages[3].ImageDesc.Height, 1);
  const auto still_frames = compose(*still);
  EXPECT_EQ(still_frames[3], still_frames[0]);
  EXPECT_TRUE(still_frames == render_preview_frames(std::vector<Pose>(4, positions[0]), 96));
  // The options' fps overrides the clip's.
  options.fps = 10;
  write_preview_gif(positions, motion.fps, dir / "slow.gif", options);
  GifPtr slow = decode(dir / "slow.gif");
  ASSERT_NE(slow, nullptr);
  GraphicsControlBlock control;
  ASSERT_EQ(DGifSavedExtensionToGCB(slow.get(), 0, &control), GIF_OK);
  EXPECT_EQ(control.DelayTime, 10);
}

TEST(PreviewGif, ViewsShowTheDocumentedSides) {
  // T-pose standing still: left arm along +X, right arm along -X, head up, toes forward (+Z).
  SkeletalMotion motion = export_test::make_test_motion(1, 20.0);
  motion.local_rotations[0].fill(Eigen::Quaterniond::Identity());
  const std::vector<Pose> positions(3, forward_kinematics(motion, 0));
  const int view = 128;
  const auto frames = render_preview_frames(positions, view);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0], frames[1]);  // same pose, same pixels
  EXPECT_EQ(frames[1], frames[2]);
  SavedImage image{};
  image.RasterBits = const_cast<GifByteType*>(frames[0].data());
  const int width = 2 * view;
  // Front (panel 1): the subject faces the viewer, so its left (blue) is on the viewer's right.
  EXPECT_GT(mean_column(image, width, view, 1, kPreviewLeft),
            mean_column(image, width, view, 1, kPreviewRight));
  // Oblique (panel 0) looks from the front-left: left still to the right of right.
  EXPECT_GT(mean_column(image, width, view, 0, kPreviewLeft),
            mean_column(image, width, view, 0, kPreviewRight));
  // Top (panel 2): front towards the bottom, so the same left/right layout as the front view.
  EXPECT_GT(mean_column(image, width, view, 2, kPreviewLeft),
            mean_column(image, width, view, 2, kPreviewRight));
  // Upright in the front and side views: the black centre line (spine, head) lies above the
  // legs' blue/red pixels on average.
  // (The side view shows the near, right side; the left side is hidden behind it.)
  EXPECT_LT(mean_row(image, width, view, 1, kPreviewCentre),
            mean_row(image, width, view, 1, kPreviewLeft));
  EXPECT_LT(mean_row(image, width, view, 3, kPreviewCentre),
            mean_row(image, width, view, 3, kPreviewRight));
  // Side (panel 3) from the subject's right: it faces right, so the right foot (red, toes
  // forward) reaches further right than the black centre line.
  int rightmost_red = -1;
  for (int y = view; y < 2 * view; ++y) {
    for (int x = view; x < 2 * view; ++x) {
      if (frames[0][y * width + x] == kPreviewRight) rightmost_red = std::max(rightmost_red, x);
    }
  }
  const int pelvis_column =
      static_cast<int>(mean_column(image, width, view, 3, kPreviewCentre)) + view;
  EXPECT_GT(rightmost_red, pelvis_column + 5);
}

TEST(PreviewGif, RejectsBadInputAndPaths) {
  const SkeletalMotion motion = export_test::make_test_motion(2, 20.0);
  const std::vector<Pose> positions = forward_kinematics(motion);
  EXPECT_THROW(write_preview_gif(positions, 20.0, "/nonexistent_dir/p.gif"), Error);
  try {
    write_preview_gif({}, 20.0, "/tmp/never.gif");
    FAIL() << "empty clip accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
  }
  EXPECT_THROW(write_preview_gif(positions, 0.0, "/tmp/never.gif"), Error);
  std::vector<Pose> broken = positions;
  broken[1][kLeftWrist].x() = NAN;
  EXPECT_THROW(write_preview_gif(broken, 20.0, "/tmp/never.gif"), Error);
  PreviewOptions tiny;
  tiny.view_size = 4;
  EXPECT_THROW(write_preview_gif(positions, 20.0, "/tmp/never.gif", tiny), Error);
  EXPECT_FALSE(std::filesystem::exists("/tmp/never.gif"));
}

}  // namespace
}  // namespace wheelpose::motion
