#pragma once
// Finding and reading the body assets (MakeHuman CC0 data and the sweethome3d wheelchair).
// The asset root is searched in order: --assets DIR, $WHEELPOSE_ASSETS, ./assets,
// ../shared/assets, then assets/ and ../shared/assets beside the source checkout the binary was
// built from, then /work/shared/assets. A missing or unreadable file throws Error naming the
// file and how to get it.

#include <filesystem>
#include <optional>
#include <string>

namespace wheelpose::body {

// The directory holding makehuman/ (throws Error listing where it looked when none does).
std::filesystem::path locate_assets(const std::optional<std::filesystem::path>& explicit_dir);

// Throws Error "<path>: missing ..." with instructions when `path` is not a readable file.
void require_asset(const std::filesystem::path& path);

// Whole file, transparently gunzipped when it ends in .gz; Error names the file when corrupt.
std::string read_asset(const std::filesystem::path& path);

// One entry of a zip archive; Error names the archive and entry.
std::string read_zip_entry(const std::filesystem::path& archive, const std::string& entry);

// The sweethome3d furniture archive holding the CC-BY wheelchair.
std::filesystem::path sweethome3d_archive();

}  // namespace wheelpose::body
