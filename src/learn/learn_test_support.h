#pragma once
// Shared by the learn layer's tests: where the MoveNet models are, and small TF.js graphs
// written from C++ (inline Const values, no weight shards) to test single ops end to end.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "learn/train_data.h"

namespace wheelpose::learn::testing {

namespace fs = std::filesystem;

// The message of the Error that `f` throws ("" if none).
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const ::wheelpose::Error& e) {
    return e.what();
  }
  return "";
}

using nlohmann::json;

// $WHEELPOSE_MODELS, else the checkout's models/.
inline fs::path models_dir() {
  if (const char* env = std::getenv("WHEELPOSE_MODELS"); env != nullptr && *env != '\0') {
    return env;
  }
  return fs::path(WHEELPOSE_SOURCE_DIR) / "models";
}

inline fs::path model_json(const std::string& name) { return models_dir() / (name + ".json"); }

inline bool have_model(const std::string& name) {
  return fs::exists(model_json(name)) && fs::exists(models_dir() / (name + ".bin"));
}

#define WHEELPOSE_REQUIRE_MODEL(name)                       \
  if (!::wheelpose::learn::testing::have_model(name))       \
  GTEST_SKIP() << "model " << (name) << " not found in "    \
               << ::wheelpose::learn::testing::models_dir() \
               << "; run scripts/setup.sh (or set WHEELPOSE_MODELS)"

// The COCO sample's skier alone, as a training set in `dir` (gt.json and its image).
inline fs::path write_skier_set(const fs::path& dir) {
  const fs::path shared = fs::path(WHEELPOSE_SHARED_DIR) / "data" / "coco-sample";
  fs::remove_all(dir);
  fs::create_directories(dir);
  json gt = json::parse(read_file(shared / "person_keypoints_sample.json"));
  json images = json::array(), annotations = json::array();
  for (const auto& image : gt["images"]) {
    if (image["file_name"] == "000000000785.jpg") images.push_back(image);
  }
  for (const auto& a : gt["annotations"]) {
    if (a["image_id"] == images.at(0)["id"]) annotations.push_back(a);
  }
  gt["images"] = images;
  gt["annotations"] = annotations;
  write_file_atomic(dir / "gt.json", gt.dump());
  fs::copy_file(shared / "000000000785.jpg", dir / "000000000785.jpg");
  return dir / "gt.json";
}

// Augmentation switched off: the image scaled so its longer side is `longer_side`, centred on
// the chosen person, nothing else changed.
inline AugmentOptions no_augmentation(int input_size, int longer_side) {
  return {.input_size = input_size,
          .target_longer_side = longer_side,
          .scale_min = 1,
          .scale_max = 1,
          .shift_fraction = 0,
          .rotate_degrees = 0,
          .flip_probability = 0,
          .color_jitter = 0,
          .blur_probability = 0,
          .jpeg_probability = 0};
}

// A fresh empty directory under the system temp dir, removed when destroyed.
class TempDir {
 public:
  explicit TempDir(const std::string& tag) {
    path_ =
        fs::temp_directory_path() / ("wheelpose_learn_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

inline std::string base64(const std::string& in) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) |
                       (static_cast<unsigned char>(in[i + 1]) << 8) |
                       static_cast<unsigned char>(in[i + 2]);
    for (int k = 3; k >= 0; --k) out += alphabet[(v >> (6 * k)) & 63];
  }
  if (i + 1 == in.size()) {
    const unsigned v = static_cast<unsigned char>(in[i]) << 16;
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == in.size()) {
    const unsigned v =
        (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8);
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += alphabet[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

// AttrValue JSON in the form tensorflowjs_converter writes.
inline json attr_i(long long v) { return {{"i", std::to_string(v)}}; }
inline json attr_b(bool v) { return {{"b", v}}; }
inline json attr_f(double v) { return {{"f", v}}; }
inline json attr_s(const std::string& v) { return {{"s", base64(v)}}; }
inline json attr_type(const std::string& t) { return {{"type", t}}; }
inline json attr_ints(const std::vector<long long>& v) {
  json list = json::array();
  for (long long x : v) list.push_back(std::to_string(x));
  return {{"list", {{"i", list}}}};
}
inline json attr_strings(const std::vector<std::string>& v) {
  json list = json::array();
  for (const std::string& x : v) list.push_back(base64(x));
  return {{"list", {{"s", list}}}};
}
inline json tensor_shape(const std::vector<long long>& shape) {
  json dims = json::array();
  for (long long d : shape) dims.push_back({{"size", std::to_string(d)}});
  return {{"dim", dims}};
}

// Builds a model.json with inline constants.
class GraphBuilder {
 public:
  GraphBuilder& placeholder(const std::string& name, const std::string& dtype,
                            const std::vector<long long>& shape) {
    nodes_.push_back(
        {{"name", name},
         {"op", "Placeholder"},
         {"attr", {{"dtype", attr_type(dtype)}, {"shape", {{"shape", tensor_shape(shape)}}}}}});
    return *this;
  }
  GraphBuilder& const_float(const std::string& name, const std::vector<long long>& shape,
                            const std::vector<float>& values) {
    json v = json::array();
    for (float x : values) v.push_back(x);
    return constant(name, "DT_FLOAT", shape, "floatVal", v);
  }
  GraphBuilder& const_int(const std::string& name, const std::vector<long long>& shape,
                          const std::vector<int>& values) {
    json v = json::array();
    for (int x : values) v.push_back(x);
    return constant(name, "DT_INT32", shape, "intVal", v);
  }
  GraphBuilder& node(const std::string& name, const std::string& op,
                     const std::vector<std::string>& inputs, json attrs = json::object()) {
    nodes_.push_back({{"name", name}, {"op", op}, {"input", inputs}, {"attr", attrs}});
    return *this;
  }
  GraphBuilder& output(const std::string& tensor) {
    outputs_["output_" + std::to_string(outputs_.size())] = {{"name", tensor}};
    return *this;
  }
  json document() const {
    json doc = {{"format", "graph-model"},
                {"modelTopology", {{"node", nodes_}}},
                {"weightsManifest", json::array()}};
    if (!outputs_.empty()) doc["signature"] = {{"outputs", outputs_}};
    return doc;
  }
  fs::path write(const fs::path& file) const {
    std::ofstream(file) << document().dump(1);
    return file;
  }

 private:
  GraphBuilder& constant(const std::string& name, const std::string& dtype,
                         const std::vector<long long>& shape, const char* field, const json& v) {
    json tensor = {{"dtype", dtype}, {"tensorShape", tensor_shape(shape)}};
    tensor[field] = v;
    json attr = {{"dtype", attr_type(dtype)}};
    attr["value"] = {{"tensor", tensor}};
    nodes_.push_back({{"name", name}, {"op", "Const"}, {"attr", attr}});
    return *this;
  }
  json nodes_ = json::array();
  json outputs_ = json::object();
};

}  // namespace wheelpose::learn::testing
