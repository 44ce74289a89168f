#pragma once
// The image files a folder holds, as the tools that take "a folder of images" see them.

#include <filesystem>
#include <vector>

namespace wheelpose {

// .jpg, .jpeg, .png or .bmp, in any letter case.
bool is_image_file(const std::filesystem::path& path);

// The folder's regular image files (not recursive), sorted by path. Throws Error if `dir` is not
// a readable folder.
std::vector<std::filesystem::path> image_files_in(const std::filesystem::path& dir);

}  // namespace wheelpose
