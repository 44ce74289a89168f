#pragma once
// Reading YAML configuration into typed options. Every accessor records which keys were read so
// that finish() can reject unknown keys; every error names file:line and the full key path.

#include <yaml-cpp/yaml.h>

#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace wheelpose {

class ConfigNode {
 public:
  // Parses a YAML file; a missing file or a syntax error throws Error naming file:line.
  static ConfigNode load_file(const std::string& path);
  // Parses YAML text; `origin` names it in messages (e.g. "<built-in paper preset>").
  static ConfigNode load_string(const std::string& text, const std::string& origin);
  // Reads a YAML file into a document to edit before wrapping it (from_yaml); a missing file or a
  // syntax error throws Error naming file:line.
  static YAML::Node parse_file(const std::string& path);
  // Wraps a parsed document (e.g. one edited after loading); `origin` names it in messages.
  static ConfigNode from_yaml(YAML::Node root, const std::string& origin);

  bool has(const std::string& key) const;
  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }
  bool is_null() const { return !node_ || node_.IsNull(); }
  std::size_t size() const { return node_.size(); }

  // Child access marks the key as used. child() of a missing key throws; optional_child() doesn't.
  ConfigNode child(const std::string& key) const;
  std::optional<ConfigNode> optional_child(const std::string& key) const;
  ConfigNode element(std::size_t index) const;
  std::vector<std::string> keys() const;

  double as_double() const;
  long long as_int() const;
  bool as_bool() const;
  std::string as_string() const;

  // Typed getters with a default used when the key is absent, and an inclusive allowed range.
  double get_double(const std::string& key, double fallback, double min, double max) const;
  long long get_int(const std::string& key, long long fallback, long long min, long long max) const;
  bool get_bool(const std::string& key, bool fallback) const;
  std::string get_string(const std::string& key, const std::string& fallback) const;
  std::string get_choice(const std::string& key, const std::string& fallback,
                         const std::vector<std::string>& allowed) const;

  // Throws naming the first key of this map that no accessor has read.
  void finish() const;

  // "file:line: key 'a.b.c': <what>" — for callers that validate values themselves.
  [[noreturn]] void fail(const std::string& what) const;
  const std::string& path() const { return key_path_; }
  int line() const { return node_.Mark().line + 1; }

 private:
  struct Shared;
  ConfigNode(std::shared_ptr<Shared> shared, YAML::Node node, std::string key_path);
  std::shared_ptr<Shared> shared_;
  YAML::Node node_;
  std::string key_path_;
  std::shared_ptr<std::set<std::string>> used_keys_;
};

// Writes `value` at `path` (dotted keys, "a.b.c") of a map document, creating maps on the way:
// how an experiment's variants and `generate --set` change one key of a file. Throws Error when a
// key on the way holds something other than a map.
void set_dotted_key(YAML::Node root, const std::string& path, const YAML::Node& value);

}  // namespace wheelpose
