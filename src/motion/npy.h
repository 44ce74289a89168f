#pragma once
// A reader for NumPy .npy files (format versions 1.0, 2.0 and 3.0) holding float32 or float64
// arrays in C order. Values are converted to double in the machine's byte order.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace wheelpose::motion {

struct NpyArray {
  std::vector<std::size_t> shape;
  std::vector<double> values;  // C (row-major) order, product(shape) entries
  std::string descr;           // dtype as written in the header, e.g. "<f4"
};

// Parses the bytes of an .npy file; `where` names the source in error messages.
// Throws wheelpose::Error for anything that is not a float32/float64 C-order array or whose
// size does not match the header.
NpyArray parse_npy(std::string_view bytes, const std::string& where);

// Reads and parses an .npy file.
NpyArray read_npy(const std::filesystem::path& path);

}  // namespace wheelpose::motion
