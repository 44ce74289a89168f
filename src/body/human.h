#pragma once
// The MakeHuman parametric body: base mesh + macro morph targets. Macro sliders combine the
// corner targets as MakeHuman defines them: each variable (gender, age, muscle, weight, height,
// proportions) is split into linear parts between named corner values (macro.json); a target's
// weight is the product of its per-variable weights, times the ethnicity share for ethnic
// targets. Units: the base mesh is in decimetres; everything this layer returns is in metres,
// +Y up, facing +Z, subject's left = +X.

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <unordered_map>
#include <vector>

namespace wheelpose::body {

struct MacroParams {
  double gender = 0.5;       // 0 female .. 1 male
  double age_years = 25.0;   // 10 .. 100 (MakeHuman's scale tops out at 90)
  double muscle = 0.5;       // 0 .. 1, 0.5 average
  double weight = 0.5;       // 0 .. 1, 0.5 average
  double height = 0.5;       // 0 .. 1, 0.5 average for the other macros
  double proportions = 0.5;  // 0 uncommon .. 0.5 neutral .. 1 ideal
  double african = 1.0 / 3, asian = 1.0 / 3, caucasian = 1.0 / 3;  // normalised on use
  double skin_tone = 0.5;  // continuous: 0 darkest .. 1 lightest

  nlohmann::ordered_json to_json() const;
  // Sets one parameter by name ("gender", "age", "muscle", "weight", "height", "proportions",
  // "african", "asian", "caucasian", "skin_tone"); throws Error naming the key or bad value.
  void set(const std::string& key, const std::string& value);
};

// MakeHuman's age slider: 1 year at 0, 11 at 0.1875, 25 at 0.5, 90 at 1 (clamped).
double age_slider(double years);

// Weight of each macro target (relative path under targets/macrodetails, without .target.gz),
// only non-zero ones. `available` filters out corners the data lacks (e.g. baby proportions).
using TargetWeights = std::map<std::string, double>;
struct MacroBreakpoints {
  // Per variable: ordered corner names and the slider value at each ("" = no target).
  std::vector<std::string> names;
  std::vector<double> at;
};
std::map<std::string, MacroBreakpoints> parse_macro_json(const nlohmann::json& macro,
                                                         const std::string& where);
TargetWeights macro_target_weights(const MacroParams& params,
                                   const std::map<std::string, MacroBreakpoints>& breakpoints);

struct SparseTarget {
  std::vector<int> index;
  std::vector<Eigen::Vector3f> delta;  // decimetres
};
SparseTarget parse_target(const std::string& text, int vertex_count, const std::string& where);

struct BaseMesh {
  std::vector<Eigen::Vector3f> vertices;       // decimetres, as in base.obj
  std::vector<std::array<int, 4>> body_quads;  // faces of group "body" (triangles repeat v0)
  std::map<std::string, std::vector<int>> group_vertices;  // joint-*/helper-* vertex sets
};
BaseMesh parse_obj(const std::string& text, const std::string& where);

// Shared, read-only data of the body model. Targets load lazily (thread-safe) and stay cached.
class HumanModel {
 public:
  explicit HumanModel(const std::filesystem::path& assets_root);

  const BaseMesh& base() const { return base_; }
  const std::map<std::string, MacroBreakpoints>& breakpoints() const { return breakpoints_; }
  const std::filesystem::path& root() const { return root_; }

  // Target weights for `params`, restricted to targets present on disk.
  TargetWeights weights(const MacroParams& params) const;
  // Morphed vertex positions in metres.
  std::vector<Eigen::Vector3f> morph(const MacroParams& params) const;
  // Loads every macro target now (for benchmarks and servers).
  void preload_all() const;
  std::size_t loaded_target_count() const;

 private:
  const SparseTarget& target(const std::string& name) const;

  std::filesystem::path root_;  // .../makehuman
  BaseMesh base_;
  std::map<std::string, MacroBreakpoints> breakpoints_;
  std::vector<std::string> available_;  // sorted target names on disk
  mutable std::mutex mutex_;
  mutable std::unordered_map<std::string, std::unique_ptr<SparseTarget>> cache_;
};

// Diffuse reflectance (linear RGB) of skin at `tone` 0 (very dark) … 1 (very light).
Eigen::Vector3f skin_colour(double tone);

}  // namespace wheelpose::body
