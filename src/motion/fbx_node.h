#pragma once
// An FBX document as the tree that both FBX encodings share: nodes with a name, typed properties
// and child nodes. fbx_binary.h and fbx_ascii.h turn a tree into bytes; fbx_document.h fills one
// from a motion, so the binary and the ASCII file say the same thing.

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace wheelpose::motion::fbx {

// Raw bytes ('R'), as opposed to a string ('S').
struct Bytes {
  std::string data;
  bool operator==(const Bytes&) const = default;
};

// One value of a node, in the order of the binary type codes
// C, Y, I, L, F, D, S, R, f, d, l, i, b.
using Property =
    std::variant<bool, std::int16_t, std::int32_t, std::int64_t, float, double, std::string, Bytes,
                 std::vector<float>, std::vector<double>, std::vector<std::int64_t>,
                 std::vector<std::int32_t>, std::vector<bool>>;

// The binary encoding's one-letter type code of a property.
char type_code(const Property& property);

struct Node {
  std::string name;
  std::vector<Property> properties;
  std::vector<Node> children;

  // Appends a child and returns it, so that trees are built in place.
  Node& add(std::string child_name, std::vector<Property> child_properties = {});
  // The first child called `child_name`, or nullptr.
  const Node* find(std::string_view child_name) const;

  bool operator==(const Node&) const = default;
};

// Whether `node` is written with a nested list (braces in ASCII, a null record ending the
// children in binary): nodes with children or without properties, and AnimationStack and
// AnimationLayer always (the FBX SDK and Assimp expect a scope for those even when empty).
bool has_nested_list(const Node& node);

// How FBX stores an object's name with its class: "name\x00\x01Class" (ASCII files show
// "Class::name").
std::string object_name(std::string_view name, std::string_view object_class);

// A Properties70 entry: P: name, type, label, flags, values...
Node& add_p(Node& properties70, std::string_view name, std::string_view type,
            std::string_view label, std::string_view flags, std::vector<Property> values = {});

}  // namespace wheelpose::motion::fbx
