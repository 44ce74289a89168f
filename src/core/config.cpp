#include "core/config.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace wheelpose {

struct ConfigNode::Shared {
  std::string file;
};

ConfigNode::ConfigNode(std::shared_ptr<Shared> shared, YAML::Node node, std::string key_path)
    : shared_(std::move(shared)),
      node_(std::move(node)),
      key_path_(std::move(key_path)),
      used_keys_(std::make_shared<std::set<std::string>>()) {}

namespace {

YAML::Node parse_text(const std::string& text, const std::string& origin) {
  try {
    YAML::Node root = YAML::Load(text);
    if (!root || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
    return root;
  } catch (const YAML::Exception& e) {
    throw Error(origin + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }
}

}  // namespace

ConfigNode ConfigNode::load_string(const std::string& text, const std::string& origin) {
  return from_yaml(parse_text(text, origin), origin);
}

ConfigNode ConfigNode::from_yaml(YAML::Node root, const std::string& origin) {
  auto shared = std::make_shared<Shared>();
  shared->file = origin;
  if (!root || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  ConfigNode node(shared, root, "");
  if (!root.IsMap()) node.fail("the document must be a map of keys");
  return node;
}

YAML::Node ConfigNode::parse_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open config file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_text(buffer.str(), path);
}

ConfigNode ConfigNode::load_file(const std::string& path) {
  return from_yaml(parse_file(path), path);
}

void ConfigNode::fail(const std::string& what) const {
  std::string where = shared_->file;
  if (node_ && node_.Mark().line >= 0) where += ":" + std::to_string(line());
  std::string key = key_path_.empty() ? "" : " key '" + key_path_ + "':";
  throw Error(where + ":" + key + " " + what);
}

bool ConfigNode::has(const std::string& key) const {
  return node_.IsMap() && node_[key].IsDefined();
}

ConfigNode ConfigNode::child(const std::string& key) const {
  auto found = optional_child(key);
  if (!found) fail("missing required key '" + key + "'");
  return *found;
}

std::optional<ConfigNode> ConfigNode::optional_child(const std::string& key) const {
  if (!node_.IsMap()) fail("expected a map");
  YAML::Node value = node_[key];
  if (!value.IsDefined()) return std::nullopt;
  used_keys_->insert(key);
  return ConfigNode(shared_, value, key_path_.empty() ? key : key_path_ + "." + key);
}

ConfigNode ConfigNode::element(std::size_t index) const {
  if (!node_.IsSequence()) fail("expected a list");
  if (index >= node_.size()) fail("list has no element " + std::to_string(index));
  return ConfigNode(shared_, node_[index], key_path_ + "[" + std::to_string(index) + "]");
}

std::vector<std::string> ConfigNode::keys() const {
  if (!node_.IsMap()) fail("expected a map");
  std::vector<std::string> out;
  for (const auto& item : node_) out.push_back(item.first.as<std::string>());
  return out;
}

double ConfigNode::as_double() const {
  if (!node_.IsScalar()) fail("expected a number");
  try {
    double value = node_.as<double>();
    if (!std::isfinite(value)) fail("expected a finite number, got '" + node_.Scalar() + "'");
    return value;
  } catch (const YAML::Exception&) {
    fail("expected a number, got '" + node_.Scalar() + "'");
  }
}

long long ConfigNode::as_int() const {
  if (!node_.IsScalar()) fail("expected an integer");
  try {
    return node_.as<long long>();
  } catch (const YAML::Exception&) {
    fail("expected an integer, got '" + node_.Scalar() + "'");
  }
}

bool ConfigNode::as_bool() const {
  if (!node_.IsScalar()) fail("expected true or false");
  try {
    return node_.as<bool>();
  } catch (const YAML::Exception&) {
    fail("expected true or false, got '" + node_.Scalar() + "'");
  }
}

std::string ConfigNode::as_string() const {
  if (!node_.IsScalar()) fail("expected a string");
  return node_.Scalar();
}

namespace {
std::string format_number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}
}  // namespace

double ConfigNode::get_double(const std::string& key, double fallback, double min,
                              double max) const {
  auto found = optional_child(key);
  if (!found) return fallback;
  double value = found->as_double();
  if (value < min || value > max) {
    found->fail("value " + format_number(value) + " is outside [" + format_number(min) + ", " +
                format_number(max) + "]");
  }
  return value;
}

long long ConfigNode::get_int(const std::string& key, long long fallback, long long min,
                              long long max) const {
  auto found = optional_child(key);
  if (!found) return fallback;
  long long value = found->as_int();
  if (value < min || value > max) {
    found->fail("value " + std::to_string(value) + " is outside [" + std::to_string(min) + ", " +
                std::to_string(max) + "]");
  }
  return value;
}

bool ConfigNode::get_bool(const std::string& key, bool fallback) const {
  auto found = optional_child(key);
  return found ? found->as_bool() : fallback;
}

std::string ConfigNode::get_string(const std::string& key, const std::string& fallback) const {
  auto found = optional_child(key);
  return found ? found->as_string() : fallback;
}

std::string ConfigNode::get_choice(const std::string& key, const std::string& fallback,
                                   const std::vector<std::string>& allowed) const {
  auto found = optional_child(key);
  if (!found) return fallback;
  std::string value = found->as_string();
  for (const auto& option : allowed) {
    if (option == value) return value;
  }
  std::string list;
  for (const auto& option : allowed) list += (list.empty() ? "" : ", ") + option;
  found->fail("'" + value + "' is not one of: " + list);
}

void ConfigNode::finish() const {
  if (!node_.IsMap()) return;
  for (const auto& item : node_) {
    const std::string key = item.first.as<std::string>();
    if (!used_keys_->count(key)) {
      ConfigNode unknown(shared_, item.first, key_path_.empty() ? key : key_path_ + "." + key);
      unknown.fail("unknown key");
    }
  }
}

void set_dotted_key(YAML::Node root, const std::string& path, const YAML::Node& value) {
  YAML::Node node;
  node.reset(root);
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = path.find('.', start);
    const std::string key = path.substr(start, dot == std::string::npos ? dot : dot - start);
    if (key.empty()) throw Error("key '" + path + "': an empty name between dots");
    if (dot == std::string::npos) {
      node[key] = value;
      return;
    }
    YAML::Node next = node[key];
    if (!next.IsDefined() || next.IsNull()) {
      next = YAML::Node(YAML::NodeType::Map);
    } else if (!next.IsMap()) {
      throw Error("key '" + path + "': '" + path.substr(0, dot) + "' is not a map of keys");
    }
    node.reset(next);
    start = dot + 1;
  }
}

}  // namespace wheelpose
