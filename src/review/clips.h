#pragma once
// The clips shown in a review study: each folder given to `serve --clips` is one group (named by
// the folder), holding seated-clip JSON files shown in file-name order. The page receives a compact
// copy of each clip (positions rounded to millimetres) prepared once at start-up.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "review/store.h"

namespace wheelpose::review {

struct ClipGroup {
  std::string name;
  std::vector<std::string> clip_ids;
};

class ClipCatalog {
 public:
  // Reads every *.json seated clip of each folder; throws Error naming the file that is bad, an
  // empty folder or two folders with the same name.
  explicit ClipCatalog(const std::vector<std::filesystem::path>& folders);

  const std::vector<ClipGroup>& groups() const { return groups_; }
  const std::vector<ClipRecord>& records() const { return records_; }
  bool contains(const std::string& clip_id) const { return payloads_.count(clip_id) > 0; }
  // JSON text {id, fps, joints, parents, frames: [[x,y,z, ... 23 joints] per frame]}.
  const std::string& payload(const std::string& clip_id) const { return payloads_.at(clip_id); }
  std::size_t size() const { return records_.size(); }

 private:
  std::vector<ClipGroup> groups_;
  std::vector<ClipRecord> records_;
  std::map<std::string, std::string> payloads_;
};

}  // namespace wheelpose::review
