#include "core/archive_member.h"

#include <unzip.h>

#include <memory>
#include <system_error>

#include "core/error.h"

namespace wheelpose {

namespace fs = std::filesystem;

std::optional<ArchiveMember> archive_member(const std::string& path) {
  const std::size_t bang = path.find("!/");
  if (bang == std::string::npos) return std::nullopt;
  return ArchiveMember{path.substr(0, bang), path.substr(bang + 2)};
}

std::string read_archive_member(const fs::path& archive, const std::string& entry) {
  std::error_code ec;
  if (!fs::is_regular_file(archive, ec)) throw Error(archive.string() + ": no such archive");
  unzFile zip = unzOpen(archive.c_str());
  if (zip == nullptr) throw Error(archive.string() + ": not a readable zip archive");
  const auto close = std::unique_ptr<void, int (*)(unzFile)>(zip, unzClose);
  if (unzLocateFile(zip, entry.c_str(), 1) != UNZ_OK) {
    throw Error(archive.string() + ": entry '" + entry + "' missing");
  }
  unz_file_info info{};
  if (unzGetCurrentFileInfo(zip, &info, nullptr, 0, nullptr, 0, nullptr, 0) != UNZ_OK ||
      unzOpenCurrentFile(zip) != UNZ_OK) {
    throw Error(archive.string() + ": entry '" + entry + "' unreadable");
  }
  std::string out(info.uncompressed_size, '\0');
  const int n = unzReadCurrentFile(zip, out.data(), static_cast<unsigned>(out.size()));
  const int crc = unzCloseCurrentFile(zip);
  if (n < 0 || static_cast<std::size_t>(n) != out.size() || crc != UNZ_OK) {
    throw Error(archive.string() + ": entry '" + entry + "' corrupt");
  }
  return out;
}

}  // namespace wheelpose
