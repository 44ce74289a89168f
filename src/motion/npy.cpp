#include "motion/npy.h"

#include <bit>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose::motion {

namespace {

constexpr std::string_view kMagic = "\x93NUMPY";

// Minimal reader for the header: a Python dict literal whose values are strings, booleans or
// tuples of integers — the only forms NumPy writes for 'descr', 'fortran_order' and 'shape'.
class HeaderParser {
 public:
  HeaderParser(std::string_view text, const std::string& where) : text_(text), where_(where) {}

  struct Value {
    enum Kind { kString, kBool, kTuple } kind;
    std::string text;
    bool flag = false;
    std::vector<std::size_t> numbers;
  };

  // Calls `on_entry(key, value)` for each dict entry.
  template <typename F>
  void parse(F on_entry) {
    expect('{');
    while (true) {
      skip_space();
      if (peek() == '}') break;
      std::string key = parse_string();
      expect(':');
      Value value = parse_value();
      on_entry(key, value);
      skip_space();
      if (peek() == ',') {
        ++pos_;
        continue;
      }
      if (peek() != '}') fail("expected ',' or '}' in the header dict");
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(where_ + ": bad .npy header: " + what + " (header: " + std::string(text_) + ")");
  }
  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  char peek() const { return pos_ < text_.size() ? text_[pos_] : '\0'; }
  void expect(char c) {
    skip_space();
    if (peek() != c) fail(std::string("expected '") + c + "'");
    ++pos_;
  }
  std::string parse_string() {
    skip_space();
    char quote = peek();
    if (quote != '\'' && quote != '"') fail("expected a quoted string");
    ++pos_;
    std::size_t end = text_.find(quote, pos_);
    if (end == std::string_view::npos) fail("unterminated string");
    std::string result(text_.substr(pos_, end - pos_));
    pos_ = end + 1;
    return result;
  }
  Value parse_value() {
    skip_space();
    Value value{};
    char c = peek();
    if (c == '\'' || c == '"') {
      value.kind = Value::kString;
      value.text = parse_string();
    } else if (text_.substr(pos_, 4) == "True") {
      value.kind = Value::kBool;
      value.flag = true;
      pos_ += 4;
    } else if (text_.substr(pos_, 5) == "False") {
      value.kind = Value::kBool;
      pos_ += 5;
    } else if (c == '(') {
      value.kind = Value::kTuple;
      ++pos_;
      while (true) {
        skip_space();
        if (peek() == ')') break;
        if (!std::isdigit(static_cast<unsigned char>(peek()))) fail("shape must hold integers");
        std::size_t n = 0;
        while (std::isdigit(static_cast<unsigned char>(peek()))) {
          if (n > std::numeric_limits<std::size_t>::max() / 10) fail("shape value too large");
          n = n * 10 + static_cast<std::size_t>(peek() - '0');
          ++pos_;
        }
        // Python 2 era writers may append 'L' to integers.
        if (peek() == 'L') ++pos_;
        value.numbers.push_back(n);
        skip_space();
        if (peek() == ',') ++pos_;
      }
      ++pos_;
    } else {
      fail("unsupported value");
    }
    return value;
  }

  std::string_view text_;
  const std::string& where_;
  std::size_t pos_ = 0;
};

std::uint32_t read_le(std::string_view bytes, std::size_t offset, int size) {
  std::uint32_t v = 0;
  for (int i = size - 1; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(bytes[offset + i]);
  return v;
}

template <typename Float, typename UInt>
double decode(const char* p, bool swap) {
  UInt bits;
  std::memcpy(&bits, p, sizeof bits);
  if (swap) {
    UInt r = 0;
    for (std::size_t i = 0; i < sizeof(UInt); ++i) {
      r = static_cast<UInt>((r << 8) | (bits & 0xff));
      bits = static_cast<UInt>(bits >> 8);
    }
    bits = r;
  }
  return static_cast<double>(std::bit_cast<Float>(bits));
}

}  // namespace

NpyArray parse_npy(std::string_view bytes, const std::string& where) {
  if (bytes.size() < kMagic.size() || bytes.substr(0, kMagic.size()) != kMagic) {
    throw Error(where + ": not a NumPy .npy file (missing the \\x93NUMPY magic)");
  }
  if (bytes.size() < 8) throw Error(where + ": truncated .npy file (no version)");
  int major = static_cast<unsigned char>(bytes[6]);
  int minor = static_cast<unsigned char>(bytes[7]);
  int len_size = 0;
  if (major == 1) {
    len_size = 2;
  } else if (major == 2 || major == 3) {
    len_size = 4;
  } else {
    throw Error(where + ": unsupported .npy format version " + std::to_string(major) + "." +
                std::to_string(minor) + " (supported: 1.0, 2.0, 3.0)");
  }
  std::size_t header_start = 8 + static_cast<std::size_t>(len_size);
  if (bytes.size() < header_start) throw Error(where + ": truncated .npy file (no header length)");
  std::size_t header_len = read_le(bytes, 8, len_size);
  if (bytes.size() < header_start + header_len) {
    throw Error(where + ": truncated .npy file (header says " + std::to_string(header_len) +
                " bytes, file ends before)");
  }
  std::string_view header = bytes.substr(header_start, header_len);

  NpyArray array;
  std::optional<bool> fortran;
  bool have_shape = false;
  HeaderParser(header, where).parse([&](const std::string& key, const HeaderParser::Value& v) {
    if (key == "descr" && v.kind == HeaderParser::Value::kString) {
      array.descr = v.text;
    } else if (key == "fortran_order" && v.kind == HeaderParser::Value::kBool) {
      fortran = v.flag;
    } else if (key == "shape" && v.kind == HeaderParser::Value::kTuple) {
      array.shape = v.numbers;
      have_shape = true;
    } else {
      throw Error(where + ": bad .npy header: unexpected entry '" + key + "'");
    }
  });
  if (array.descr.empty() || !fortran || !have_shape) {
    throw Error(where + ": bad .npy header: needs 'descr', 'fortran_order' and 'shape'");
  }
  if (*fortran) throw Error(where + ": fortran order arrays are not supported");

  const std::string& d = array.descr;
  if (d.size() != 3 || (d[0] != '<' && d[0] != '>' && d[0] != '|' && d[0] != '=') || d[1] != 'f' ||
      (d[2] != '4' && d[2] != '8')) {
    throw Error(where + ": unsupported dtype '" + d +
                "' (need float32 or float64: <f4, <f8, >f4, >f8)");
  }
  bool big = d[0] == '>';
  bool swap = (big != (std::endian::native == std::endian::big)) && d[0] != '|' && d[0] != '=';
  std::size_t item = d[2] == '4' ? 4 : 8;

  std::size_t count = 1;
  for (std::size_t n : array.shape) {
    if (n != 0 && count > std::numeric_limits<std::size_t>::max() / item / n) {
      throw Error(where + ": .npy shape is too large");
    }
    count *= n;
  }
  std::size_t data_start = header_start + header_len;
  std::size_t available = bytes.size() - data_start;
  if (available < count * item) {
    throw Error(where + ": truncated .npy file: shape needs " + std::to_string(count * item) +
                " data bytes, file has " + std::to_string(available));
  }
  if (available > count * item) {
    throw Error(where + ": .npy file has " + std::to_string(available - count * item) +
                " bytes after the array data");
  }
  array.values.resize(count);
  const char* p = bytes.data() + data_start;
  for (std::size_t i = 0; i < count; ++i, p += item) {
    array.values[i] =
        item == 4 ? decode<float, std::uint32_t>(p, swap) : decode<double, std::uint64_t>(p, swap);
  }
  return array;
}

NpyArray read_npy(const std::filesystem::path& path) {
  std::string bytes = read_file(path);
  return parse_npy(bytes, path.string());
}

}  // namespace wheelpose::motion
