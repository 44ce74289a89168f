#pragma once
// Test-only helpers for the importer tests: a scratch directory and fixture writers.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace wheelpose::motion::testing {

// A fresh directory under the system temp dir, removed at the end of the test.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("wheelpose_import_" + std::to_string(::getpid()) + "_" + info->test_suite_name() +
             "_" + info->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() { std::filesystem::remove_all(path_); }
  std::filesystem::path write(const std::string& name, const std::string& contents) const {
    std::filesystem::path p = path_ / name;
    std::ofstream(p, std::ios::binary) << contents;
    return p;
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Bytes of an .npy file. `descr` like "<f4"; values are written in the descr's byte order.
inline std::string npy_bytes(const std::string& descr, const std::vector<std::size_t>& shape,
                             const std::vector<double>& values, int major = 1,
                             bool fortran = false) {
  std::string shape_text = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    shape_text += std::to_string(shape[i]) + (shape.size() == 1 || i + 1 < shape.size() ? "," : "");
    if (i + 1 < shape.size()) shape_text += " ";
  }
  shape_text += ")";
  std::string header = "{'descr': '" + descr +
                       "', 'fortran_order': " + (fortran ? "True" : "False") +
                       ", 'shape': " + shape_text + ", }";
  const std::size_t prefix = major == 1 ? 10 : 12;
  while ((prefix + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string out = "\x93NUMPY";
  out += static_cast<char>(major);
  out += '\0';
  const std::size_t len = header.size();
  for (std::size_t i = 0; i < prefix - 8; ++i) out += static_cast<char>((len >> (8 * i)) & 0xff);
  out += header;
  const bool big = descr[0] == '>';
  const bool f4 = descr.substr(1) == "f4";
  for (double v : values) {
    char bytes[8];
    std::size_t n = f4 ? 4 : 8;
    if (f4) {
      float f = static_cast<float>(v);
      std::memcpy(bytes, &f, 4);
    } else {
      std::memcpy(bytes, &v, 8);
    }
    // The test machines are little-endian; big-endian output reverses each value.
    if (big) std::reverse(bytes, bytes + n);
    out.append(bytes, n);
  }
  return out;
}

}  // namespace wheelpose::motion::testing
