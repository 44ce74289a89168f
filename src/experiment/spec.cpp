#include "experiment/spec.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <sstream>

#include "core/config.h"
#include "core/error.h"
#include "learn/model_files.h"
#include "learn/pose_predictor.h"

namespace wheelpose::experiment {
namespace {

namespace fs = std::filesystem;

constexpr const char* kTrainedModel = "trained";

fs::path existing_path(const ConfigNode& node, const fs::path& base_dir, bool directory) {
  const fs::path path = (base_dir / node.as_string()).lexically_normal();
  std::error_code ec;
  const bool ok = directory ? fs::is_directory(path, ec) : fs::is_regular_file(path, ec);
  if (!ok) node.fail(path.string() + (directory ? ": no such folder" : ": no such file"));
  return path;
}

DatasetSpec parse_dataset(const std::string& name, const ConfigNode& node,
                          const fs::path& base_dir) {
  DatasetSpec d;
  d.name = name;
  const int kinds = node.has("generate") + node.has("coco") + node.has("split");
  if (kinds != 1) node.fail("a dataset is one of generate:, coco: (with images:) or split:");
  if (auto g = node.optional_child("generate")) {
    d.kind = DatasetSpec::Kind::kGenerate;
    if (auto c = g->optional_child("config"))
      d.generate_config = existing_path(*c, base_dir, false);
    if (auto c = g->optional_child("clips_from")) d.clips_from = existing_path(*c, base_dir, false);
    d.frames = g->get_int("frames", 0, 1, 10'000'000);
    d.seed = static_cast<std::uint64_t>(g->get_int("seed", 1, 0, (1LL << 62)));
    g->finish();  // a misspelt key first: it is why a required one is missing
    if (d.frames == 0) g->fail("missing required key 'frames'");
  } else if (auto c = node.optional_child("coco")) {
    d.kind = DatasetSpec::Kind::kCoco;
    d.coco = existing_path(*c, base_dir, false);
    d.images = existing_path(node.child("images"), base_dir, true);
  } else {
    const ConfigNode s = node.child("split");
    d.kind = DatasetSpec::Kind::kSplit;
    d.split_of = s.child("of").as_string();
    const ConfigNode ratios = s.child("ratios");
    if (!ratios.is_sequence() || ratios.size() < 2)
      ratios.fail("expected a list of two or more ratios");
    for (std::size_t i = 0; i < ratios.size(); ++i) {
      const double r = ratios.element(i).as_double();
      if (r <= 0) ratios.element(i).fail("a ratio must be > 0");
      d.ratios.push_back(r);
    }
    d.part = static_cast<int>(s.get_int("part", 0, 0, static_cast<long long>(d.ratios.size()) - 1));
    d.seed = static_cast<std::uint64_t>(s.get_int("seed", 0, 0, (1LL << 62)));
    s.finish();
  }
  node.finish();
  return d;
}

std::string scalar_text(const ConfigNode& node) {
  if (!node.is_scalar()) node.fail("expected a number, a word or true/false");
  return node.as_string();
}

TrainingSpec parse_training(const ConfigNode& node, const ExperimentSpec& spec,
                            const CommandOptions& commands) {
  TrainingSpec t;
  const ConfigNode sets = node.child("sets");
  if (!sets.is_sequence() || sets.size() == 0) sets.fail("expected a list of training sets");
  for (std::size_t i = 0; i < sets.size(); ++i) {
    const ConfigNode item = sets.element(i);
    TrainSetRef ref;
    if (item.is_scalar()) {
      ref.set = item.as_string();
    } else {
      ref.set = item.child("set").as_string();
      ref.weight = item.get_double("weight", 1, 1e-9, 1e9);
      item.finish();
    }
    spec.dataset(ref.set);  // throws for an unknown name
    t.sets.push_back(ref);
  }
  t.val = node.get_string("val", "");
  if (!t.val.empty()) spec.dataset(t.val);
  t.keep = node.get_choice("keep", t.val.empty() ? "last" : "best", {"best", "last"});
  if (t.keep == "best" && t.val.empty()) node.child("keep").fail("best needs a val: set");
  if (auto options = node.optional_child("options")) {
    for (const std::string& key : options->keys()) {
      const ConfigNode value = options->child(key);
      if (commands.reserved.count(key)) {
        value.fail("set by the experiment itself (training.sets, training.val, --out)");
      }
      if (!commands.train.count(key)) value.fail("not an option of `wheelpose train`");
      const std::string text = scalar_text(value);
      if (text == "false") continue;
      t.options.emplace_back(key, text);
    }
  }
  node.finish();
  return t;
}

ModelSpec parse_model(const std::string& name, const ConfigNode& node, const fs::path& base_dir) {
  ModelSpec m;
  m.name = name;
  auto member = [&](const ConfigNode& item) {
    std::string text = item.as_string();
    if (text == kTrainedModel) return text;
    const bool is_path =
        text.find('/') != std::string::npos || text.ends_with(".pt") || text.ends_with(".json");
    if (is_path) text = existing_path(item, base_dir, false).string();
    try {
      learn::choose_model(text, std::nullopt);
    } catch (const Error& e) {
      item.fail(e.what());
    }
    return text;
  };
  if (node.is_scalar()) {
    m.members.push_back(member(node));
    return m;
  }
  const ConfigNode members = node.child("members");
  if (members.is_scalar()) {
    m.members.push_back(member(members));
  } else {
    if (members.size() == 0) members.fail("expected one or more models");
    for (std::size_t i = 0; i < members.size(); ++i)
      m.members.push_back(member(members.element(i)));
  }
  if (node.has("blend")) m.blend = node.get_double("blend", 1, 0, 1);
  m.flip = node.get_bool("flip", false);
  m.exported = node.get_bool("export", false);
  node.finish();
  return m;
}

bool has_model(const ExperimentSpec& spec, const std::string& name) {
  return std::any_of(spec.models.begin(), spec.models.end(),
                     [&](const ModelSpec& m) { return m.name == name; });
}

ScoreSpec parse_score(const ConfigNode& node, const ExperimentSpec& spec) {
  ScoreSpec s;
  s.set = node.child("set").as_string();
  spec.dataset(s.set);
  s.type = node.get_choice("type", "both", {"keypoints", "bbox", "both"});
  s.size = static_cast<int>(node.get_int("size", 0, 0, learn::kMaxInputSide));
  if (s.size != 0 && (s.size < 32 || s.size % 32 != 0)) {
    node.child("size").fail("an input size is 32 to 1280 in steps of 32");
  }
  if (auto models = node.optional_child("models")) {
    for (std::size_t i = 0; i < models->size(); ++i) {
      const std::string name = models->element(i).as_string();
      if (!has_model(spec, name)) {
        models->element(i).fail("no model named '" + name + "' under models:");
      }
      s.models.push_back(name);
    }
  }
  node.finish();
  return s;
}

ExperimentSpec parse_spec(const ConfigNode& root, const fs::path& base_dir,
                          const CommandOptions& commands) {
  ExperimentSpec spec;
  spec.name = root.child("name").as_string();
  spec.description = root.get_string("description", "");
  const ConfigNode datasets = root.child("datasets");
  for (const std::string& name : datasets.keys()) {
    spec.datasets.push_back(parse_dataset(name, datasets.child(name), base_dir));
  }
  for (const DatasetSpec& d : spec.datasets) {
    if (d.kind != DatasetSpec::Kind::kSplit) continue;
    const auto parent = std::find_if(spec.datasets.begin(), spec.datasets.end(),
                                     [&](const DatasetSpec& p) { return p.name == d.split_of; });
    if (parent == spec.datasets.end() || parent->kind == DatasetSpec::Kind::kSplit) {
      datasets.child(d.name).fail("split of '" + d.split_of +
                                  "': not a generate: or coco: dataset of this file");
    }
  }
  if (auto training = root.optional_child("training")) {
    spec.training = parse_training(*training, spec, commands);
  }
  const ConfigNode models = root.child("models");
  for (const std::string& name : models.keys()) {
    spec.models.push_back(parse_model(name, models.child(name), base_dir));
    const ModelSpec& m = spec.models.back();
    const bool trains = std::count(m.members.begin(), m.members.end(), kTrainedModel) > 0;
    if (trains && !spec.training) models.child(name).fail("'trained' needs a training: section");
    if (m.blend && !trains) models.child(name).fail("blend: applies to a 'trained' member");
    if (m.exported && !trains) models.child(name).fail("export: applies to a 'trained' member");
  }
  const ConfigNode scores = root.child("scores");
  if (!scores.is_sequence() || scores.size() == 0) scores.fail("expected a list of sets to score");
  for (std::size_t i = 0; i < scores.size(); ++i) {
    spec.scores.push_back(parse_score(scores.element(i), spec));
  }
  if (auto intervals = root.optional_child("intervals")) {
    IntervalSpec iv;
    const ConfigNode against = intervals->child("against");
    iv.against = against.as_string();
    if (!has_model(spec, iv.against)) {
      against.fail("no model named '" + iv.against + "' under models:");
    }
    iv.resamples = static_cast<int>(intervals->get_int("resamples", 1000, 1, 100000));
    iv.seed = static_cast<std::uint64_t>(intervals->get_int("seed", 0, 0, INT64_MAX));
    intervals->finish();
    spec.intervals = iv;
  }
  root.finish();
  return spec;
}

YAML::Node load_yaml(const std::string& text, const std::string& origin) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw Error(origin + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }
}

}  // namespace

const DatasetSpec& ExperimentSpec::dataset(const std::string& wanted) const {
  for (const DatasetSpec& d : datasets) {
    if (d.name == wanted) return d;
  }
  throw Error("no dataset named '" + wanted + "' under datasets:");
}

bool ExperimentSpec::uses_training() const {
  return std::any_of(models.begin(), models.end(), [](const ModelSpec& m) {
    return std::count(m.members.begin(), m.members.end(), kTrainedModel) > 0;
  });
}

std::vector<Variant> parse_experiment(const std::string& text, const std::string& origin,
                                      const fs::path& base_dir, const CommandOptions& commands) {
  // The base is parsed from its own copy of the document; each variant from a fresh copy with
  // its keys written over it, so every error still points at a line of the file.
  const auto parse_copy = [&](const YAML::Node& variant_keys) {
    YAML::Node root = load_yaml(text, origin);
    if (!root.IsMap()) throw Error(origin + ": the document must be a map of keys");
    if (variant_keys) {
      for (const auto& item : variant_keys) {
        set_dotted_key(root, item.first.as<std::string>(), item.second);
      }
    }
    root.remove("variants");
    root.remove("run_base");
    try {
      return parse_spec(ConfigNode::from_yaml(root, origin), base_dir, commands);
    } catch (const Error& e) {
      const std::string message = e.what();
      // Lookups of unknown names carry no line: say where they came from.
      if (message.rfind(origin, 0) == 0) throw;
      throw Error(origin + ": " + message);
    }
  };

  const ConfigNode top = ConfigNode::load_string(text, origin);
  std::vector<Variant> variants;
  if (top.get_bool("run_base", true)) variants.push_back({"base", parse_copy(YAML::Node())});
  if (auto listed = top.optional_child("variants")) {
    YAML::Node root = load_yaml(text, origin);
    for (const std::string& name : listed->keys()) {
      const ConfigNode keys = listed->child(name);
      if (!keys.is_map()) keys.fail("a variant is a map of keys to override (a.b.c: value)");
      if (name == "base") keys.fail("'base' names the file as written; choose another name");
      variants.push_back({name, parse_copy(root["variants"][name])});
    }
  }
  if (variants.empty()) throw Error(origin + ": run_base is false and there are no variants");
  return variants;
}

std::vector<Variant> load_experiment(const fs::path& file, const CommandOptions& commands) {
  std::ifstream in(file);
  std::error_code ec;
  if (!in || fs::is_directory(file, ec))
    throw Error(file.string() + ": cannot open experiment file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_experiment(buffer.str(), file.string(), fs::absolute(file).parent_path(), commands);
}

}  // namespace wheelpose::experiment
