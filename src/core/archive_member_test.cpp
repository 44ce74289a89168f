#include "core/archive_member.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <zip.h>

#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "core/image_read.h"

namespace wheelpose {
namespace {

namespace fs = std::filesystem;

// A zip holding `entry` with `bytes`, written with minizip's own writer.
void write_zip(const fs::path& archive, const std::string& entry, const std::string& bytes) {
  zipFile zip = zipOpen(archive.c_str(), APPEND_STATUS_CREATE);
  ASSERT_NE(zip, nullptr);
  ASSERT_EQ(zipOpenNewFileInZip(zip, entry.c_str(), nullptr, nullptr, 0, nullptr, 0, nullptr,
                                Z_DEFLATED, Z_DEFAULT_COMPRESSION),
            ZIP_OK);
  ASSERT_EQ(zipWriteInFileInZip(zip, bytes.data(), static_cast<unsigned>(bytes.size())), ZIP_OK);
  ASSERT_EQ(zipCloseFileInZip(zip), ZIP_OK);
  ASSERT_EQ(zipClose(zip, nullptr), ZIP_OK);
}

std::string error_of(const std::string& path) {
  try {
    read_image(path, cv::IMREAD_COLOR);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(ArchiveMember, SplitsAtTheFirstBangSlash) {
  const auto member = archive_member("/a/b.sh3f!/dir/c.jpg");
  ASSERT_TRUE(member.has_value());
  EXPECT_EQ(member->archive, fs::path("/a/b.sh3f"));
  EXPECT_EQ(member->entry, "dir/c.jpg");
  EXPECT_FALSE(archive_member("/a/b/c.jpg").has_value());
}

// An image inside a zip decodes to the same pixels as the file; a missing entry or archive is
// one error naming both.
TEST(ArchiveMember, ReadImageTakesAZipEntry) {
  const fs::path dir = fs::temp_directory_path() / ("wheelpose_zip_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  cv::Mat image(6, 8, CV_8UC3);
  cv::randu(image, 0, 255);
  std::vector<std::uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", image, png));
  write_zip(dir / "pack.zip", "fabrics/a.png", std::string(png.begin(), png.end()));

  const cv::Mat back =
      read_image((dir / "pack.zip").string() + "!/fabrics/a.png", cv::IMREAD_COLOR);
  ASSERT_EQ(back.size(), image.size());
  EXPECT_EQ(cv::norm(back, image, cv::NORM_INF), 0.0);

  const std::string missing_entry = error_of((dir / "pack.zip").string() + "!/fabrics/b.png");
  EXPECT_NE(missing_entry.find("pack.zip: entry 'fabrics/b.png' missing"), std::string::npos)
      << missing_entry;
  const std::string missing_archive = error_of((dir / "gone.zip").string() + "!/a.png");
  EXPECT_NE(missing_archive.find("gone.zip: no such archive"), std::string::npos)
      << missing_archive;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wheelpose
