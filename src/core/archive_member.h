#pragma once
// Files inside zip archives (the sweethome3d furniture catalogues are zips), named the way Java
// names a jar's entries: "ARCHIVE!/ENTRY", e.g.
// "/usr/share/sweethome3d/furniture/BlendSwap-CC-0.sh3f!/blendswap-cc-0/couch/Plain001.jpg".
// read_image (core/image_read.h) takes such paths wherever it takes a file.

#include <filesystem>
#include <optional>
#include <string>

namespace wheelpose {

struct ArchiveMember {
  std::filesystem::path archive;
  std::string entry;
};

// The archive and entry of an "ARCHIVE!/ENTRY" path; nullopt for a plain path.
std::optional<ArchiveMember> archive_member(const std::string& path);

// One entry's bytes (its CRC checked). Throws Error naming the archive, and the entry when the
// archive is there but the entry is missing or corrupt.
std::string read_archive_member(const std::filesystem::path& archive, const std::string& entry);

}  // namespace wheelpose
