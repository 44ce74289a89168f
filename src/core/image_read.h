#pragma once
// Reading an image file the way every command that takes photos should: one Error naming the
// file for anything short of a whole, decodable image. OpenCV alone decodes a truncated JPEG
// into a half-grey picture with only libjpeg's bare "Premature end of JPEG file" on stderr, and
// prints its own warning for a missing file; neither names the file or stops the run.

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <string_view>

namespace wheelpose {

// What is wrong with an encoded image's structure, or "" when nothing is: a JPEG must reach
// its end-of-image marker, a PNG its IEND chunk. Other formats are left to the decoder.
std::string encoded_image_defect(std::string_view bytes);

// Decodes `path` with cv::imdecode `flags` (e.g. cv::IMREAD_COLOR, BGR order); an
// "ARCHIVE!/ENTRY" path reads the entry of a zip (core/archive_member.h). Throws Error (exit 2)
// naming the file when it is missing, not a file, truncated, or does not decode.
cv::Mat read_image(const std::filesystem::path& path, int flags);

}  // namespace wheelpose
