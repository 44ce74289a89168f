#include "body/human.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <set>

#include "body/assets.h"
#include "core/error.h"
#include "core/srgb.h"

namespace wheelpose::body {

namespace fs = std::filesystem;

namespace {

double parse_double(const std::string& key, const std::string& value) {
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (value.empty() || end == nullptr || *end != '\0' || !std::isfinite(v)) {
    throw Error("--params " + key + "=" + value + ": not a number");
  }
  return v;
}

// Per-variable weights of the corner names for one slider value.
std::vector<std::pair<std::string, double>> variable_weights(const MacroBreakpoints& bp,
                                                             double value) {
  const double v = std::clamp(value, bp.at.front(), bp.at.back());
  std::vector<std::pair<std::string, double>> out;
  for (std::size_t k = 0; k + 1 < bp.at.size(); ++k) {
    if (v > bp.at[k + 1] && k + 2 < bp.at.size()) continue;
    const double t = (v - bp.at[k]) / (bp.at[k + 1] - bp.at[k]);
    if (1.0 - t > 0) out.emplace_back(bp.names[k], 1.0 - t);
    if (t > 0) out.emplace_back(bp.names[k + 1], t);
    break;
  }
  return out;
}

const MacroBreakpoints& variable(const std::map<std::string, MacroBreakpoints>& bps,
                                 const std::string& name) {
  const auto it = bps.find(name);
  if (it == bps.end()) throw Error("macro.json: variable '" + name + "' missing");
  return it->second;
}

const char* skip_space(const char* p, const char* end) {
  while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
  return p;
}

}  // namespace

nlohmann::ordered_json MacroParams::to_json() const {
  return {{"gender", gender},      {"age", age_years}, {"muscle", muscle},
          {"weight", weight},      {"height", height}, {"proportions", proportions},
          {"african", african},    {"asian", asian},   {"caucasian", caucasian},
          {"skin_tone", skin_tone}};
}

void MacroParams::set(const std::string& key, const std::string& value) {
  const double v = parse_double(key, value);
  auto unit = [&](double& field) {
    if (v < 0 || v > 1) throw Error("--params " + key + "=" + value + ": must be in [0, 1]");
    field = v;
  };
  if (key == "gender") return unit(gender);
  if (key == "muscle") return unit(muscle);
  if (key == "weight") return unit(weight);
  if (key == "height") return unit(height);
  if (key == "proportions") return unit(proportions);
  if (key == "african") return unit(african);
  if (key == "asian") return unit(asian);
  if (key == "caucasian") return unit(caucasian);
  if (key == "skin_tone") return unit(skin_tone);
  if (key == "age") {
    if (v < 10 || v > 100) throw Error("--params age=" + value + ": must be 10..100 years");
    age_years = v;
    return;
  }
  throw Error("--params " + key + ": unknown body parameter");
}

double age_slider(double years) {
  if (years <= 1) return 0.0;
  if (years <= 11) return 0.1875 * (years - 1) / 10.0;
  if (years <= 25) return 0.1875 + (0.5 - 0.1875) * (years - 11) / 14.0;
  if (years <= 90) return 0.5 + 0.5 * (years - 25) / 65.0;
  return 1.0;
}

std::map<std::string, MacroBreakpoints> parse_macro_json(const nlohmann::json& macro,
                                                         const std::string& where) {
  std::map<std::string, MacroBreakpoints> out;
  if (!macro.contains("macrotargets") || !macro["macrotargets"].is_object()) {
    throw Error(where + ": no 'macrotargets' object");
  }
  // The data's part bounds carry slop (-0.01, 0.49998, 1.01); the breakpoints MakeHuman means are
  // multiples of 1/16 (0, 0.1875, 0.5, 1), so bounds are snapped to them.
  auto snap = [](double x) { return std::clamp(std::round(x * 16.0) / 16.0, 0.0, 1.0); };
  for (const auto& [name, var] : macro["macrotargets"].items()) {
    MacroBreakpoints bp;
    try {
      for (const auto& part : var.at("parts")) {
        if (bp.names.empty()) {
          bp.names.push_back(part.at("low").get<std::string>());
          bp.at.push_back(snap(part.at("lowest").get<double>()));
        }
        bp.names.push_back(part.at("high").get<std::string>());
        bp.at.push_back(snap(part.at("highest").get<double>()));
      }
    } catch (const nlohmann::json::exception& e) {
      throw Error(where + ": macrotargets." + name + ": " + e.what());
    }
    for (std::size_t i = 1; i < bp.at.size(); ++i) {
      if (!(bp.at[i] > bp.at[i - 1]))
        throw Error(where + ": macrotargets." + name + ": parts overlap");
    }
    if (bp.at.size() < 2) throw Error(where + ": macrotargets." + name + ": no parts");
    out[name] = std::move(bp);
  }
  return out;
}

TargetWeights macro_target_weights(const MacroParams& p,
                                   const std::map<std::string, MacroBreakpoints>& bps) {
  const auto g = variable_weights(variable(bps, "gender"), p.gender);
  const auto a = variable_weights(variable(bps, "age"), age_slider(p.age_years));
  const auto m = variable_weights(variable(bps, "muscle"), p.muscle);
  const auto w = variable_weights(variable(bps, "weight"), p.weight);
  const auto h = variable_weights(variable(bps, "height"), p.height);
  const auto pr = variable_weights(variable(bps, "proportions"), p.proportions);
  TargetWeights out;
  const double share_sum = std::max(p.african + p.asian + p.caucasian, 1e-12);
  const std::pair<const char*, double> races[] = {{"african", p.african / share_sum},
                                                  {"asian", p.asian / share_sum},
                                                  {"caucasian", p.caucasian / share_sum}};
  if (p.african + p.asian + p.caucasian <= 0) {
    throw Error("--params: african + asian + caucasian must be positive");
  }
  for (const auto& [gn, gw] : g) {
    for (const auto& [an, aw] : a) {
      for (const auto& [race, share] : races) {
        if (share > 0) out[std::string(race) + "-" + gn + "-" + an] += share * gw * aw;
      }
      for (const auto& [mn, mw] : m) {
        for (const auto& [wn, ww] : w) {
          const std::string stem = gn + "-" + an + "-" + mn + "-" + wn;
          const double base = gw * aw * mw * ww;
          out["universal-" + stem] += base;
          for (const auto& [hn, hw] : h) {
            if (!hn.empty()) out["height/" + stem + "-" + hn] += base * hw;
          }
          for (const auto& [pn, pw] : pr) {
            if (!pn.empty()) out["proportions/" + stem + "-" + pn] += base * pw;
          }
        }
      }
    }
  }
  return out;
}

SparseTarget parse_target(const std::string& text, int vertex_count, const std::string& where) {
  SparseTarget t;
  const char* p = text.data();
  const char* end = p + text.size();
  int line = 0;
  while (p < end) {
    ++line;
    const char* eol = static_cast<const char*>(std::memchr(p, '\n', end - p));
    if (eol == nullptr) eol = end;
    const char* q = skip_space(p, eol);
    if (q < eol && *q != '#') {
      int index = 0;
      auto r = std::from_chars(q, eol, index);
      Eigen::Vector3f d;
      bool ok = r.ec == std::errc() && index >= 0 && index < vertex_count;
      q = r.ptr;
      for (int k = 0; ok && k < 3; ++k) {
        q = skip_space(q, eol);
        auto rf = std::from_chars(q, eol, d[k]);
        ok = rf.ec == std::errc();
        q = rf.ptr;
      }
      if (!ok) throw Error(where + ":" + std::to_string(line) + ": bad target line");
      t.index.push_back(index);
      t.delta.push_back(d);
    }
    p = eol + 1;
  }
  return t;
}

BaseMesh parse_obj(const std::string& text, const std::string& where) {
  BaseMesh mesh;
  std::string group;
  std::vector<std::array<int, 4>> faces_of_group;
  const char* p = text.data();
  const char* end = p + text.size();
  int line = 0;
  std::map<std::string, std::set<int>> groups;
  while (p < end) {
    ++line;
    const char* eol = static_cast<const char*>(std::memchr(p, '\n', end - p));
    if (eol == nullptr) eol = end;
    auto bad = [&](const char* what) {
      return Error(where + ":" + std::to_string(line) + ": " + what);
    };
    if (eol - p > 2 && p[0] == 'v' && p[1] == ' ') {
      Eigen::Vector3f v;
      const char* q = p + 2;
      for (int k = 0; k < 3; ++k) {
        q = skip_space(q, eol);
        auto r = std::from_chars(q, eol, v[k]);
        if (r.ec != std::errc()) throw bad("bad vertex");
        q = r.ptr;
      }
      mesh.vertices.push_back(v);
    } else if (eol - p > 2 && p[0] == 'g' && p[1] == ' ') {
      group.assign(skip_space(p + 2, eol), eol);
      while (!group.empty() && std::isspace(static_cast<unsigned char>(group.back())))
        group.pop_back();
    } else if (eol - p > 2 && p[0] == 'f' && p[1] == ' ') {
      std::array<int, 4> face{};
      int n = 0;
      const char* q = p + 2;
      while (true) {
        q = skip_space(q, eol);
        if (q >= eol) break;
        int index = 0;
        auto r = std::from_chars(q, eol, index);
        if (r.ec != std::errc() || index < 1 || n >= 4) throw bad("bad face");
        face[n++] = index - 1;
        q = r.ptr;
        while (q < eol && *q != ' ' && *q != '\t') ++q;
      }
      if (n < 3) throw bad("face with fewer than 3 vertices");
      if (n == 3) face[3] = face[0];
      if (group == "body") {
        mesh.body_quads.push_back(face);
      } else {
        for (int k = 0; k < n; ++k) groups[group].insert(face[k]);
      }
    }
    p = eol + 1;
  }
  const int count = static_cast<int>(mesh.vertices.size());
  for (const auto& f : mesh.body_quads) {
    for (int i : f) {
      if (i >= count)
        throw Error(where + ": face refers to vertex " + std::to_string(i + 1) + " of " +
                    std::to_string(count));
    }
  }
  for (auto& [name, set] : groups) {
    for (int i : set) {
      if (i >= count) throw Error(where + ": group " + name + " refers to a missing vertex");
    }
    mesh.group_vertices[name] = std::vector<int>(set.begin(), set.end());
  }
  if (mesh.body_quads.empty()) throw Error(where + ": no faces in group 'body'");
  return mesh;
}

HumanModel::HumanModel(const fs::path& assets_root) : root_(assets_root / "makehuman") {
  const fs::path obj = root_ / "mesh" / "base.obj";
  base_ = parse_obj(read_asset(obj), obj.string());
  const fs::path macro_path = root_ / "targets" / "macrodetails" / "macro.json";
  const std::string macro_text = read_asset(macro_path);
  const auto macro = nlohmann::json::parse(macro_text, nullptr, false);
  if (macro.is_discarded()) throw Error(macro_path.string() + ": not valid JSON");
  breakpoints_ = parse_macro_json(macro, macro_path.string());
  const fs::path dir = root_ / "targets" / "macrodetails";
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string rel = fs::relative(entry.path(), dir).generic_string();
    const std::string suffix = ".target.gz";
    if (rel.size() > suffix.size() && rel.ends_with(suffix)) {
      available_.push_back(rel.substr(0, rel.size() - suffix.size()));
    }
  }
  std::sort(available_.begin(), available_.end());
  if (available_.empty()) throw Error(dir.string() + ": no .target.gz files; run scripts/setup.sh");
}

TargetWeights HumanModel::weights(const MacroParams& params) const {
  TargetWeights all = macro_target_weights(params, breakpoints_);
  TargetWeights out;
  for (const auto& [name, w] : all) {
    if (w <= 0) continue;
    if (std::binary_search(available_.begin(), available_.end(), name)) {
      out[name] = w;
    } else if (name.starts_with("universal-") || name.find('/') == std::string::npos) {
      // Universal and ethnic corners must all exist; only height/proportion ones may be absent.
      require_asset(root_ / "targets" / "macrodetails" / (name + ".target.gz"));
    }
  }
  return out;
}

const SparseTarget& HumanModel::target(const std::string& name) const {
  {
    std::lock_guard lock(mutex_);
    if (auto it = cache_.find(name); it != cache_.end()) return *it->second;
  }
  const fs::path path = root_ / "targets" / "macrodetails" / (name + ".target.gz");
  auto parsed = std::make_unique<SparseTarget>(
      parse_target(read_asset(path), static_cast<int>(base_.vertices.size()), path.string()));
  std::lock_guard lock(mutex_);
  auto [it, inserted] = cache_.emplace(name, std::move(parsed));
  return *it->second;
}

void HumanModel::preload_all() const {
  for (const std::string& name : available_) target(name);
}

std::size_t HumanModel::loaded_target_count() const {
  std::lock_guard lock(mutex_);
  return cache_.size();
}

std::vector<Eigen::Vector3f> HumanModel::morph(const MacroParams& params) const {
  std::vector<Eigen::Vector3f> v = base_.vertices;
  for (const auto& [name, w] : weights(params)) {
    const SparseTarget& t = target(name);
    const float wf = static_cast<float>(w);
    for (std::size_t i = 0; i < t.index.size(); ++i) v[t.index[i]] += wf * t.delta[i];
  }
  for (auto& x : v) x *= 0.1f;  // decimetres -> metres
  return v;
}

Eigen::Vector3f skin_colour(double tone) {
  // Documented skin colours from very dark to very light, as sRGB under daylight: the Monk Skin
  // Tone scale's darkest and second-lightest swatches (MST-10 #292420, MST-2 #f3e7db; Google,
  // CC BY 4.0) at the ends, the Macbeth ColorChecker's "dark skin" (115, 82, 68) and "light skin"
  // (194, 150, 130) patches, made to reflect like real skin, between them. Interpolated in
  // linear light; the result is the diffuse reflectance.
  struct Anchor {
    float tone;
    unsigned rgb;
  };
  static constexpr Anchor kAnchors[] = {
      {0.0f, 0x292420}, {0.3f, 0x735244}, {0.65f, 0xc29682}, {1.0f, 0xf3e7db}};
  const auto linear = [](const Anchor& a) { return linear_from_srgb_hex(a.rgb); };
  const float t = static_cast<float>(std::clamp(tone, 0.0, 1.0));
  std::size_t i = 1;
  while (i + 1 < std::size(kAnchors) && t > kAnchors[i].tone) ++i;
  const float f = (t - kAnchors[i - 1].tone) / (kAnchors[i].tone - kAnchors[i - 1].tone);
  return linear(kAnchors[i - 1]) * (1 - f) + linear(kAnchors[i]) * f;
}

}  // namespace wheelpose::body
