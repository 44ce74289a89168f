#include "core/image_read.h"

#include <opencv2/imgcodecs.hpp>
#include <system_error>

#include "core/archive_member.h"
#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose {
namespace {

namespace fs = std::filesystem;

bool is_restart_or_stuffing(unsigned char next) {
  return next == 0x00 || (next >= 0xD0 && next <= 0xD7);
}

// Walks the JPEG marker segments from SOI to EOI (ITU T.81 B.1): a segment's length skips its
// payload (EXIF thumbnails included, so their EOI is not taken for the image's); after a scan
// header the entropy-coded data runs to the next 0xFF that is not stuffing or a restart marker.
std::string jpeg_defect(std::string_view b) {
  const std::size_t n = b.size();
  const auto at = [&](std::size_t i) { return static_cast<unsigned char>(b[i]); };
  const std::string truncated = "truncated JPEG (it ends before its end-of-image marker)";
  std::size_t pos = 2;
  while (true) {
    // Stray bytes before a marker are tolerated, as libjpeg does (with a warning).
    while (pos < n && at(pos) != 0xFF) ++pos;
    while (pos < n && at(pos) == 0xFF) ++pos;
    if (pos >= n) return truncated;
    const unsigned char marker = at(pos++);
    if (marker == 0xD9) return "";
    if (marker == 0x00 || marker == 0x01 || marker == 0xD8 || (marker >= 0xD0 && marker <= 0xD7)) {
      continue;  // no payload
    }
    if (pos + 2 > n) return truncated;
    const std::size_t length = (static_cast<std::size_t>(at(pos)) << 8) | at(pos + 1);
    if (length < 2) return "corrupt JPEG (a segment of length " + std::to_string(length) + ")";
    pos += length;
    if (pos > n) return truncated;
    if (marker != 0xDA) continue;
    while (pos + 1 < n && !(at(pos) == 0xFF && !is_restart_or_stuffing(at(pos + 1)))) ++pos;
    if (pos + 1 >= n) return truncated;
  }
}

std::string png_defect(std::string_view b) {
  // The IEND chunk: type then its CRC, the last 8 bytes of a whole PNG (tolerating trailers).
  if (b.rfind("IEND") == std::string_view::npos) {
    return "truncated PNG (it ends before its IEND chunk)";
  }
  return "";
}

}  // namespace

std::string encoded_image_defect(std::string_view bytes) {
  if (bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0xFF &&
      static_cast<unsigned char>(bytes[1]) == 0xD8) {
    return jpeg_defect(bytes);
  }
  if (bytes.starts_with("\x89PNG\r\n\x1a\n")) return png_defect(bytes);
  return "";
}

cv::Mat read_image(const fs::path& path, int flags) {
  std::string bytes;
  if (const std::optional<ArchiveMember> member = archive_member(path.string())) {
    bytes = read_archive_member(member->archive, member->entry);
  } else {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (!fs::exists(status)) throw Error(path.string() + ": no such image file");
    if (!fs::is_regular_file(status)) {
      throw Error(path.string() + ": not an image file (a folder?)");
    }
    bytes = read_file(path);
  }
  if (bytes.empty()) throw Error(path.string() + ": empty file, not an image");
  if (const std::string defect = encoded_image_defect(bytes); !defect.empty()) {
    throw Error(path.string() + ": " + defect);
  }
  cv::Mat image;
  try {
    const cv::Mat encoded(1, static_cast<int>(bytes.size()), CV_8U,
                          const_cast<char*>(bytes.data()));
    image = cv::imdecode(encoded, flags);
  } catch (const cv::Exception& e) {
    throw Error(path.string() + ": cannot decode the image (" + e.err + ")");
  }
  if (image.empty()) throw Error(path.string() + ": cannot decode the image");
  return image;
}

}  // namespace wheelpose
