#pragma once
// ASCII FBX encoding of a node tree (fbx_node.h), in the FBX SDK's layout: "Name: values" per
// node, children in braces indented by tabs, strings quoted ("name\x00\x01Class" printed as
// "Class::name"), arrays as "*count { a: v,v,... }", numbers in their shortest exact decimal form.
// Raw bytes have no ASCII form and are refused, as are strings holding quotes or line breaks.

#include <cstdint>
#include <string>
#include <vector>

#include "motion/fbx_node.h"

namespace wheelpose::motion::fbx {

std::string encode_ascii(const std::vector<Node>& top_level, std::uint32_t version);

}  // namespace wheelpose::motion::fbx
