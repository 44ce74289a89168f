#include "motion/fbx_binary.h"

#include <bit>
#include <limits>
#include <type_traits>

#include "core/error.h"

namespace wheelpose::motion::fbx {

namespace {

// The footer's id goes with the document's CreationTime (export_fbx.cpp writes the matching
// fixed time); the closing magic is the same in every file.
constexpr unsigned char kFooterId[16] = {0xfa, 0xbc, 0xab, 0x09, 0xd0, 0xc8, 0xd4, 0x66,
                                         0xb1, 0x76, 0xfb, 0x83, 0x1c, 0xf7, 0x26, 0x7e};
constexpr unsigned char kFooterMagic[16] = {0xf8, 0x5a, 0x8c, 0x6a, 0xde, 0xf5, 0xd9, 0x7e,
                                            0xec, 0xe9, 0x0c, 0xe3, 0x75, 0x8f, 0x29, 0x0b};

class Encoder {
 public:
  explicit Encoder(std::uint32_t version) : wide_(version >= 7500) {}

  std::string& out() { return out_; }

  template <typename T>
  void put(T value) {
    static_assert(std::is_arithmetic_v<T>);
    using Bits = std::conditional_t<
        sizeof(T) == 1, std::uint8_t,
        std::conditional_t<sizeof(T) == 2, std::uint16_t,
                           std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
    const Bits bits = std::bit_cast<Bits>(value);
    for (std::size_t i = 0; i < sizeof(T); ++i) out_.push_back(static_cast<char>(bits >> (8 * i)));
  }

  // An offset or count: uint32 or uint64 by version; patched later when `at` is given.
  void put_word(std::uint64_t value) {
    if (wide_) {
      put<std::uint64_t>(value);
    } else {
      if (value > std::numeric_limits<std::uint32_t>::max()) {
        throw Error("FBX file larger than 4 GiB (FBX 7.4 offsets are 32-bit)", ErrorKind::kFailure);
      }
      put<std::uint32_t>(static_cast<std::uint32_t>(value));
    }
  }
  void patch_word(std::size_t at, std::uint64_t value) {
    Encoder patch(wide_ ? 7500 : 7400);
    patch.put_word(value);
    out_.replace(at, patch.out_.size(), patch.out_);
  }
  std::size_t word_size() const { return wide_ ? 8 : 4; }
  void null_record() { out_.append(3 * word_size() + 1, '\0'); }

  void put_length(std::size_t length) {
    if (length > std::numeric_limits<std::uint32_t>::max()) {
      throw Error("FBX property longer than 4 GiB", ErrorKind::kFailure);
    }
    put<std::uint32_t>(static_cast<std::uint32_t>(length));
  }

  template <typename T>
  void put_array(const std::vector<T>& values) {
    put_length(values.size());
    put<std::uint32_t>(0);  // encoding: uncompressed
    put_length(values.size() * sizeof(T));
    for (const T& v : values) put(v);
  }

  void put_property(const Property& property) {
    out_.push_back(type_code(property));
    std::visit(
        [this](const auto& value) {
          using T = std::decay_t<decltype(value)>;
          if constexpr (std::is_same_v<T, bool>) {
            put<std::uint8_t>(value ? 1 : 0);
          } else if constexpr (std::is_arithmetic_v<T>) {
            put(value);
          } else if constexpr (std::is_same_v<T, std::string>) {
            put_length(value.size());
            out_ += value;
          } else if constexpr (std::is_same_v<T, Bytes>) {
            put_length(value.data.size());
            out_ += value.data;
          } else if constexpr (std::is_same_v<T, std::vector<bool>>) {
            put_length(value.size());
            put<std::uint32_t>(0);
            put_length(value.size());
            for (bool b : value) put<std::uint8_t>(b ? 1 : 0);
          } else {
            put_array(value);
          }
        },
        property);
  }

  void put_node(const Node& node) {
    if (node.name.size() > 255) {
      throw Error("FBX record name longer than 255 bytes: " + node.name.substr(0, 40) + "...",
                  ErrorKind::kFailure);
    }
    const std::size_t start = out_.size();
    put_word(0);  // end offset, patched below
    put_word(node.properties.size());
    put_word(0);  // property bytes, patched below
    put<std::uint8_t>(static_cast<std::uint8_t>(node.name.size()));
    out_ += node.name;
    const std::size_t properties_start = out_.size();
    for (const Property& property : node.properties) put_property(property);
    patch_word(start + 2 * word_size(), out_.size() - properties_start);
    for (const Node& child : node.children) put_node(child);
    if (has_nested_list(node)) null_record();
    patch_word(start, out_.size());
  }

 private:
  bool wide_;
  std::string out_;
};

}  // namespace

std::string encode_binary(const std::vector<Node>& top_level, std::uint32_t version) {
  Encoder encoder(version);
  std::string& out = encoder.out();
  out.append(kBinaryMagic, sizeof(kBinaryMagic));
  encoder.put<std::uint32_t>(version);
  for (const Node& node : top_level) encoder.put_node(node);
  encoder.null_record();
  out.append(reinterpret_cast<const char*>(kFooterId), sizeof(kFooterId));
  out.append((16 - out.size() % 16) % 16, '\0');
  out.append(4, '\0');
  encoder.put<std::uint32_t>(version);
  out.append(120, '\0');
  out.append(reinterpret_cast<const char*>(kFooterMagic), sizeof(kFooterMagic));
  return out;
}

}  // namespace wheelpose::motion::fbx
