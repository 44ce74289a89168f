#include "motion/fbx_ascii.h"

#include <bit>
#include <charconv>
#include <string_view>
#include <type_traits>

#include "core/error.h"

namespace wheelpose::motion::fbx {

namespace {

template <typename T>
void append_number(std::string& out, T value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

void append_string(std::string& out, const std::string& value) {
  if (value.find_first_of("\"\r\n") != std::string::npos) {
    throw Error("ASCII FBX cannot hold a string with quotes or line breaks: " + value,
                ErrorKind::kBadInput);
  }
  out += '"';
  const std::size_t separator = value.find(std::string_view("\x00\x01", 2));
  if (separator == std::string::npos) {
    out += value;
  } else {
    out += value.substr(separator + 2) + "::" + value.substr(0, separator);
  }
  out += '"';
}

void append_indent(std::string& out, int depth) {
  out.append(static_cast<std::size_t>(depth), '\t');
}

// `as_bits`: the FBX SDK prints KeyAttrDataFloat, packed tangent data, as the floats' bit patterns.
void append_property(std::string& out, const Property& property, int depth, bool as_bits) {
  std::visit(
      [&](const auto& value) {
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, bool>) {
          out += value ? 'T' : 'F';
        } else if constexpr (std::is_arithmetic_v<T>) {
          append_number(out, value);
        } else if constexpr (std::is_same_v<T, std::string>) {
          append_string(out, value);
        } else if constexpr (std::is_same_v<T, Bytes>) {
          throw Error("ASCII FBX cannot hold raw bytes", ErrorKind::kFailure);
        } else {
          out += '*';
          append_number(out, value.size());
          out += " {\n";
          append_indent(out, depth + 1);
          out += "a: ";
          for (std::size_t i = 0; i < value.size(); ++i) {
            if (i > 0) out += ',';
            using Element = typename T::value_type;
            if constexpr (std::is_same_v<Element, bool>) {
              out += value[i] ? '1' : '0';
            } else if constexpr (std::is_same_v<Element, float>) {
              if (as_bits) {
                append_number(out, std::bit_cast<std::int32_t>(value[i]));
              } else {
                append_number(out, value[i]);
              }
            } else {
              append_number(out, value[i]);
            }
          }
          out += '\n';
          append_indent(out, depth);
          out += '}';
        }
      },
      property);
}

void append_node(std::string& out, const Node& node, int depth) {
  append_indent(out, depth);
  out += node.name;
  out += ": ";
  for (std::size_t i = 0; i < node.properties.size(); ++i) {
    if (i > 0) out += ", ";
    append_property(out, node.properties[i], depth, node.name == "KeyAttrDataFloat");
  }
  if (has_nested_list(node)) {
    out += " {\n";
    for (const Node& child : node.children) append_node(out, child, depth + 1);
    append_indent(out, depth);
    out += '}';
  }
  out += '\n';
}

}  // namespace

std::string encode_ascii(const std::vector<Node>& top_level, std::uint32_t version) {
  std::string out = "; FBX " + std::to_string(version / 1000) + "." +
                    std::to_string(version / 100 % 10) + "." + std::to_string(version % 100) +
                    " project file\n; ----------------------------------------------------\n\n";
  for (const Node& node : top_level) append_node(out, node, 0);
  return out;
}

}  // namespace wheelpose::motion::fbx
