#pragma once
// Header-only helper for FBX tests: a strict reader of binary FBX back into the node tree, written
// from the format description (not from the writer), so a round trip checks the layout: header,
// record offsets and lengths, null records, the footer's alignment and its fixed bytes.

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "motion/fbx_node.h"

namespace wheelpose::motion::fbx::testing {

class BinaryReader {
 public:
  explicit BinaryReader(const std::string& bytes) : bytes_(bytes) {}

  // Throws std::runtime_error on any deviation from the layout.
  std::vector<Node> read(std::uint32_t* version_out = nullptr) {
    static const std::string kMagic("Kaydara FBX Binary  \0\x1a\0", 23);
    if (bytes_.compare(0, kMagic.size(), kMagic) != 0) fail("bad magic");
    pos_ = kMagic.size();
    const std::uint32_t version = get<std::uint32_t>();
    wide_ = version >= 7500;
    if (version_out) *version_out = version;
    std::vector<Node> nodes;
    while (true) {
      Node node;
      if (!read_node(node)) break;
      nodes.push_back(std::move(node));
    }
    // Footer: 16-byte id, zeros to a multiple of 16, 4 zeros, version, 120 zeros, 16-byte magic.
    pos_ += 16;
    while (pos_ % 16 != 0) expect_zero();
    for (int i = 0; i < 4; ++i) expect_zero();
    if (get<std::uint32_t>() != version) fail("footer version");
    for (int i = 0; i < 120; ++i) expect_zero();
    static const unsigned char kEnd[16] = {0xf8, 0x5a, 0x8c, 0x6a, 0xde, 0xf5, 0xd9, 0x7e,
                                           0xec, 0xe9, 0x0c, 0xe3, 0x75, 0x8f, 0x29, 0x0b};
    if (bytes_.compare(pos_, 16, std::string(reinterpret_cast<const char*>(kEnd), 16)) != 0) {
      fail("footer magic");
    }
    pos_ += 16;
    if (pos_ != bytes_.size()) fail("bytes after the footer");
    return nodes;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(what + " at byte " + std::to_string(pos_));
  }
  void need(std::size_t n) const {
    if (pos_ + n > bytes_.size()) fail("truncated");
  }
  template <typename T>
  T get() {
    need(sizeof(T));
    std::uint64_t bits = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) {
      bits |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes_[pos_ + i])) << (8 * i);
    }
    pos_ += sizeof(T);
    using Bits = std::conditional_t<
        sizeof(T) == 1, std::uint8_t,
        std::conditional_t<sizeof(T) == 2, std::uint16_t,
                           std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
    return std::bit_cast<T>(static_cast<Bits>(bits));
  }
  std::uint64_t word() { return wide_ ? get<std::uint64_t>() : get<std::uint32_t>(); }
  std::string take(std::size_t n) {
    need(n);
    std::string s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  void expect_zero() {
    if (get<std::uint8_t>() != 0) fail("expected a zero byte");
  }
  template <typename T>
  std::vector<T> array() {
    const std::uint32_t length = get<std::uint32_t>();
    if (get<std::uint32_t>() != 0) fail("compressed array");
    if (get<std::uint32_t>() != length * sizeof(T)) fail("array byte length");
    std::vector<T> values;
    for (std::uint32_t i = 0; i < length; ++i) values.push_back(get<T>());
    return values;
  }
  Property property() {
    const char code = static_cast<char>(get<std::uint8_t>());
    switch (code) {
      case 'C':
        return get<std::uint8_t>() != 0;
      case 'Y':
        return get<std::int16_t>();
      case 'I':
        return get<std::int32_t>();
      case 'L':
        return get<std::int64_t>();
      case 'F':
        return get<float>();
      case 'D':
        return get<double>();
      case 'S':
        return take(get<std::uint32_t>());
      case 'R':
        return Bytes{take(get<std::uint32_t>())};
      case 'f':
        return array<float>();
      case 'd':
        return array<double>();
      case 'l':
        return array<std::int64_t>();
      case 'i':
        return array<std::int32_t>();
      case 'b': {
        std::vector<bool> values;
        for (std::uint8_t b : array<std::uint8_t>()) values.push_back(b != 0);
        return values;
      }
      default:
        fail(std::string("unknown property type '") + code + "'");
    }
  }
  bool read_node(Node& node) {
    const std::size_t record_start = pos_;
    const std::uint64_t end = word();
    const std::uint64_t count = word();
    const std::uint64_t property_bytes = word();
    const std::uint8_t name_length = get<std::uint8_t>();
    if (end == 0) {
      if (count != 0 || property_bytes != 0 || name_length != 0) fail("bad null record");
      return false;
    }
    if (end <= record_start || end > bytes_.size()) fail("end offset out of range");
    node.name = take(name_length);
    const std::size_t properties_start = pos_;
    for (std::uint64_t i = 0; i < count; ++i) node.properties.push_back(property());
    if (pos_ - properties_start != property_bytes) fail("property byte count");
    if (pos_ < end) {
      const std::size_t null_size = wide_ ? 25 : 13;
      while (pos_ < end - null_size) {
        Node child;
        if (!read_node(child)) fail("null record before the end offset");
        node.children.push_back(std::move(child));
      }
      for (std::size_t i = 0; i < null_size; ++i) expect_zero();
    }
    if (pos_ != end) fail("record of '" + node.name + "' does not end at its end offset");
    return true;
  }

  const std::string& bytes_;
  std::size_t pos_ = 0;
  bool wide_ = false;
};

inline std::vector<Node> read_binary(const std::string& bytes, std::uint32_t* version = nullptr) {
  return BinaryReader(bytes).read(version);
}

}  // namespace wheelpose::motion::fbx::testing
