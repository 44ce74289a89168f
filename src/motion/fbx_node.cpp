#include "motion/fbx_node.h"

#include <utility>

namespace wheelpose::motion::fbx {

char type_code(const Property& property) {
  static constexpr char kCodes[] = "CYILFDSRfdlib";
  static_assert(sizeof(kCodes) - 1 == std::variant_size_v<Property>);
  return kCodes[property.index()];
}

Node& Node::add(std::string child_name, std::vector<Property> child_properties) {
  children.push_back(Node{std::move(child_name), std::move(child_properties), {}});
  return children.back();
}

const Node* Node::find(std::string_view child_name) const {
  for (const Node& child : children) {
    if (child.name == child_name) return &child;
  }
  return nullptr;
}

bool has_nested_list(const Node& node) {
  return !node.children.empty() || node.properties.empty() || node.name == "AnimationStack" ||
         node.name == "AnimationLayer";
}

std::string object_name(std::string_view name, std::string_view object_class) {
  std::string result(name);
  result += std::string_view("\x00\x01", 2);
  result += object_class;
  return result;
}

Node& add_p(Node& properties70, std::string_view name, std::string_view type,
            std::string_view label, std::string_view flags, std::vector<Property> values) {
  std::vector<Property> properties = {std::string(name), std::string(type), std::string(label),
                                      std::string(flags)};
  for (Property& value : values) properties.push_back(std::move(value));
  return properties70.add("P", std::move(properties));
}

}  // namespace wheelpose::motion::fbx
