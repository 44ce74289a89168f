#include "body/assets.h"

#include <zlib.h>

#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <vector>

#include "core/archive_member.h"
#include "core/error.h"

namespace wheelpose::body {

namespace fs = std::filesystem;

namespace {

constexpr const char* kHowToGet =
    "point --assets or WHEELPOSE_ASSETS at a directory holding makehuman/ (the CC0 data of "
    "makehumancommunity/makehuman and mpfb2, listed in shared/assets/makehuman/SOURCE.md; "
    "scripts/setup.sh does not download it)";

bool has_makehuman(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "makehuman" / "mesh" / "base.obj", ec);
}

}  // namespace

fs::path locate_assets(const std::optional<fs::path>& explicit_dir) {
  if (explicit_dir) {
    if (!has_makehuman(*explicit_dir)) {
      throw Error(explicit_dir->string() + ": --assets has no makehuman/mesh/base.obj; " +
                  kHowToGet);
    }
    return *explicit_dir;
  }
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("WHEELPOSE_ASSETS"); env != nullptr && *env != '\0') {
    candidates.emplace_back(env);
  }
  candidates.emplace_back("assets");
  candidates.emplace_back("../shared/assets");
  // Beside the source checkout this binary was built from, so it works from any directory.
  candidates.emplace_back(fs::path(WHEELPOSE_SOURCE_DIR) / "assets");
  candidates.emplace_back(fs::path(WHEELPOSE_SOURCE_DIR).parent_path() / "shared" / "assets");
  candidates.emplace_back("/work/shared/assets");
  std::string tried;
  for (const fs::path& dir : candidates) {
    if (has_makehuman(dir)) return dir;
    tried += (tried.empty() ? "" : ", ") + dir.string();
  }
  throw Error("makehuman/mesh/base.obj: body assets not found (looked in " + tried + "); " +
              kHowToGet);
}

void require_asset(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw Error(path.string() + ": missing asset; " + kHowToGet);
  }
}

std::string read_asset(const fs::path& path) {
  require_asset(path);
  if (path.extension() != ".gz") {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in.good() && !in.eof()) throw Error(path.string() + ": cannot read asset; " + kHowToGet);
    return text.str();
  }
  gzFile file = gzopen(path.c_str(), "rb");
  if (file == nullptr) throw Error(path.string() + ": cannot open asset; " + kHowToGet);
  std::string out;
  char buffer[1 << 16];
  while (true) {
    const int n = gzread(file, buffer, sizeof(buffer));
    if (n < 0) {
      gzclose(file);
      throw Error(path.string() + ": corrupt gzip data; " + kHowToGet);
    }
    if (n == 0) break;
    out.append(buffer, static_cast<std::size_t>(n));
  }
  // A truncated stream reads as a short file; gzclose reports it.
  if (gzclose(file) != Z_OK) throw Error(path.string() + ": truncated gzip data; " + kHowToGet);
  return out;
}

std::string read_zip_entry(const fs::path& archive, const std::string& entry) {
  require_asset(archive);
  return read_archive_member(archive, entry);
}

fs::path sweethome3d_archive() {
  const fs::path path = "/usr/share/sweethome3d/furniture/BlendSwap-CC-BY.sh3f";
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw Error(path.string() +
                ": missing (CC-BY wheelchair); install it with `apt-get install "
                "sweethome3d-furniture` (scripts/setup.sh does)");
  }
  return path;
}

}  // namespace wheelpose::body
