#include "core/image_read.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>
#include <random>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose {
namespace {

namespace fs = std::filesystem;

std::string encode(const std::string& ext) {
  cv::Mat image(48, 64, CV_8UC3);
  cv::randu(image, 0, 255);  // noise: the entropy-coded data holds many 0xFF bytes to stuff
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(ext, image, bytes));
  return std::string(bytes.begin(), bytes.end());
}

std::string read_error(const fs::path& path) {
  try {
    read_image(path, cv::IMREAD_COLOR);
    return "";
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 2);
    return e.what();
  }
}

TEST(ImageRead, WholeImagesHaveNoDefect) {
  EXPECT_EQ(encoded_image_defect(encode(".jpg")), "");
  EXPECT_EQ(encoded_image_defect(encode(".png")), "");
  EXPECT_EQ(encoded_image_defect("BM not checked"), "");
  // Bytes after the end-of-image marker (some cameras append data) are allowed.
  EXPECT_EQ(encoded_image_defect(encode(".jpg") + "trailer"), "");
}

TEST(ImageRead, EveryTruncationOfAJpegIsFound) {
  const std::string whole = encode(".jpg");
  for (std::size_t keep = 2; keep + 2 <= whole.size(); keep += 37) {
    EXPECT_EQ(encoded_image_defect(whole.substr(0, keep)),
              "truncated JPEG (it ends before its end-of-image marker)")
        << keep << " of " << whole.size() << " bytes";
  }
  const std::string png = encode(".png");
  EXPECT_EQ(encoded_image_defect(png.substr(0, png.size() / 2)),
            "truncated PNG (it ends before its IEND chunk)");
}

TEST(ImageRead, AThumbnailsEndMarkerIsNotTheImages) {
  // An APP1 segment that holds a whole thumbnail (SOI ... EOI) before the real image data.
  const std::string whole = encode(".jpg");
  const std::string thumbnail = "\xFF\xD8\xFF\xD9";
  std::string app1 = "\xFF\xE1";
  app1 += static_cast<char>(0);
  app1 += static_cast<char>(2 + thumbnail.size());
  app1 += thumbnail;
  const std::string with_thumbnail = whole.substr(0, 2) + app1 + whole.substr(2);
  EXPECT_EQ(encoded_image_defect(with_thumbnail), "");
  EXPECT_NE(encoded_image_defect(with_thumbnail.substr(0, with_thumbnail.size() / 2)), "");
}

// Fuzzing: truncated and byte-flipped JPEGs and PNGs either decode or fail with one Error;
// none crashes, and none that was cut short decodes.
TEST(ImageRead, DamagedImagesDecodeOrFailCleanly) {
  const fs::path dir = fs::temp_directory_path() / ("wheelpose_image_fuzz_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  ensure_directory(dir);
  std::mt19937 random(7);
  int decoded = 0, refused = 0;
  for (const std::string ext : {".jpg", ".png"}) {
    const std::string whole = encode(ext);
    for (int trial = 0; trial < 60; ++trial) {
      std::string bytes = whole;
      const bool cut = trial % 2 == 0;
      if (cut) bytes.resize(2 + random() % (bytes.size() - 12));
      for (int flips = 0; flips < 3; ++flips) {
        bytes[random() % bytes.size()] = static_cast<char>(random() % 256);
      }
      const fs::path file = dir / ("f" + ext);
      write_file_atomic(file, std::string_view(bytes));
      try {
        const cv::Mat image = read_image(file, cv::IMREAD_COLOR);
        EXPECT_FALSE(image.empty());
        EXPECT_FALSE(cut && ext == ".jpg") << "a cut JPEG decoded (" << bytes.size() << " bytes)";
        ++decoded;
      } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(file.string() + ": ", 0), 0u) << e.what();
        ++refused;
      }
    }
  }
  EXPECT_GT(decoded, 0);
  EXPECT_GT(refused, 0);
  fs::remove_all(dir);
}

TEST(ImageRead, BadFilesAreOneLineNamingThem) {
  const fs::path dir = fs::temp_directory_path() / ("wheelpose_image_read_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  ensure_directory(dir / "folder.jpg");
  const std::string jpeg = encode(".jpg");
  write_file_atomic(dir / "whole.jpg", std::string_view(jpeg));
  write_file_atomic(dir / "cut.jpg", std::string_view(jpeg).substr(0, jpeg.size() - 40));
  write_file_atomic(dir / "empty.png", std::string_view(""));
  write_file_atomic(dir / "text.png", std::string_view("not an image at all"));

  const cv::Mat image = read_image(dir / "whole.jpg", cv::IMREAD_COLOR);
  EXPECT_EQ(image.cols, 64);
  EXPECT_EQ(image.rows, 48);
  EXPECT_EQ(read_error(dir / "missing.jpg"), (dir / "missing.jpg").string() + ": no such image file");
  EXPECT_EQ(read_error(dir / "folder.jpg"),
            (dir / "folder.jpg").string() + ": not an image file (a folder?)");
  EXPECT_EQ(read_error(dir / "cut.jpg"),
            (dir / "cut.jpg").string() + ": truncated JPEG (it ends before its end-of-image marker)");
  EXPECT_EQ(read_error(dir / "empty.png"), (dir / "empty.png").string() + ": empty file, not an image");
  EXPECT_EQ(read_error(dir / "text.png"), (dir / "text.png").string() + ": cannot decode the image");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wheelpose
