#pragma once
// Binary FBX encoding of a node tree (fbx_node.h), as Blender's importer, Assimp and the Autodesk
// FBX SDK read it:
//  * header: "Kaydara FBX Binary  \0\x1a\0" and the version (uint32);
//  * records: end offset (from the file start), property count, property bytes, name length
//    (uint8) and name, the properties (a type code, then the value: little-endian numbers;
//    strings and raw bytes with a uint32 length; arrays as length, encoding 0 = uncompressed,
//    byte length, values), then the children followed by a null record. Offsets and counts are
//    uint32 before version 7500 (null record 13 zero bytes), uint64 from 7500 (25 bytes);
//  * a null record ends the top level, then the footer: a fixed 16-byte id, zeros up to a
//    multiple of 16 bytes, 4 zero bytes, the version again, 120 zero bytes, a fixed 16-byte
//    magic.
// Arrays are written uncompressed, so the same tree always gives the same bytes.

#include <cstdint>
#include <string>
#include <vector>

#include "motion/fbx_node.h"

namespace wheelpose::motion::fbx {

inline constexpr char kBinaryMagic[] = "Kaydara FBX Binary  \0\x1a";  // + the array's own \0

// Throws Error when a name is longer than 255 bytes or the file outgrows 32-bit offsets.
std::string encode_binary(const std::vector<Node>& top_level, std::uint32_t version);

}  // namespace wheelpose::motion::fbx
