#include "experiment/plan.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "learn/model_files.h"

namespace wheelpose::experiment {
namespace {

namespace fs = std::filesystem;

// Exact text for commands (step hashes are of commands, so this form must not change: it
// would orphan every finished step of a resumable run).
std::string number_text(double value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

// The shortest text that reads back as the same double: 0.3, not 0.29999999999999999.
std::string shortest_number_text(double value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

class Planner {
 public:
  explicit Planner(const fs::path& out_dir) : out_dir_(out_dir), steps_dir_(out_dir / "steps") {}

  // Adds the step unless an identical one exists; returns its folder. `make` fills the
  // commands given the folder the step writes to.
  template <typename Make>
  fs::path add(const std::string& kind, const std::string& name, const std::string& label,
               bool resumable, Make make) {
    // The hash sees the commands with a placeholder folder, so it names what the step does,
    // not where the run lives.
    const fs::path placeholder = "@STEP";
    std::string key = kind + "\n" + serialize(make(placeholder));
    // Nor where the run lives: other steps' folders enter relative to it.
    const std::string root = out_dir_.string();
    for (std::size_t at = key.find(root); !root.empty() && at != std::string::npos;
         at = key.find(root, at)) {
      key.replace(at, root.size(), "@OUT");
    }
    key += input_contents(make(placeholder));
    const std::string id = kind + "-" + name + "-" + stable_hash(key).substr(0, 10);
    const fs::path dir = steps_dir_ / id;
    if (std::none_of(plan_.steps.begin(), plan_.steps.end(),
                     [&](const Step& s) { return s.id == id; })) {
      plan_.steps.push_back({id, kind, label, make(dir), dir, resumable, {}});
    }
    return dir;
  }

  DatasetFiles dataset(const ExperimentSpec& spec, const std::string& name) {
    const DatasetSpec& d = spec.dataset(name);
    switch (d.kind) {
      case DatasetSpec::Kind::kCoco:
        return {d.coco, d.images};
      case DatasetSpec::Kind::kGenerate: {
        const fs::path dir =
            add("generate", d.name, "generate " + d.name, true, [&](const fs::path& at) {
              std::vector<std::string> c = {"generate",
                                            "--out",
                                            at.string(),
                                            "--frames",
                                            std::to_string(d.frames),
                                            "--seed",
                                            std::to_string(d.seed)};
              if (d.generate_config) c.insert(c.end(), {"--config", d.generate_config->string()});
              if (d.clips_from) c.insert(c.end(), {"--clips-from", d.clips_from->string()});
              return std::vector<std::vector<std::string>>{c};
            });
        return {dir / "annotations.json", dir / "images"};
      }
      case DatasetSpec::Kind::kSplit: {
        const DatasetFiles parent = dataset(spec, d.split_of);
        std::string ratios, names;
        for (std::size_t i = 0; i < d.ratios.size(); ++i) {
          ratios += (i ? "," : "") + number_text(d.ratios[i]);
          names += (i ? "," : "") + std::string("part") + std::to_string(i);
        }
        const fs::path dir =
            add("split", d.split_of, "split " + d.split_of, false, [&](const fs::path& at) {
              return std::vector<std::vector<std::string>>{
                  {"coco", "split", parent.coco.string(), "--ratios", ratios, "--names", names,
                   "--group-by", "image", "--seed", std::to_string(d.seed), "--out", at.string()}};
            });
        split_images_[dir] = parent.images;
        return {dir / ("part" + std::to_string(d.part) + ".json"), parent.images};
      }
    }
    throw Error("unknown dataset kind");
  }

  fs::path train(const std::string& variant, const ExperimentSpec& spec) {
    const TrainingSpec& t = *spec.training;
    std::vector<std::string> c = {"train"};
    for (const TrainSetRef& ref : t.sets) {
      const std::string file = dataset(spec, ref.set).coco.string();
      c.insert(c.end(), {"--train", ref.weight == 1 ? file : file + ":" + number_text(ref.weight)});
    }
    if (!t.val.empty()) c.insert(c.end(), {"--val", dataset(spec, t.val).coco.string()});
    for (const auto& [key, value] : t.options) {
      c.push_back("--" + key);
      if (value != "true") c.push_back(value);
    }
    const fs::path dir = add("train", variant, "train " + variant, true, [&](const fs::path& at) {
      std::vector<std::string> command = c;
      command.insert(command.end(), {"--out", at.string()});
      return std::vector<std::vector<std::string>>{command};
    });
    trained_weights_[variant] = dir / (t.keep + ".pt");
    plan_.train_runs[variant] = dir;
    return dir;
  }

  std::string member_model(const std::string& variant, const ExperimentSpec& spec,
                           const ModelSpec& model, const std::string& member) {
    if (member != "trained") return member;
    const std::string weights = trained_or_blended(variant, spec, model);
    if (!model.exported) return weights;
    const std::string what = model.blend && *model.blend != 1
                                 ? "blend " + variant + " " + shortest_number_text(*model.blend)
                                 : "train " + variant;
    const fs::path dir = add("export", variant, "export " + what, false, [&](const fs::path& at) {
      return std::vector<std::vector<std::string>>{
          {"model", "export", weights, "--out", (at / "model").string()}};
    });
    return (dir / "model" / "model.json").string();
  }

  // The trained weights, or their blend with the start model when the model asks for one.
  std::string trained_or_blended(const std::string& variant, const ExperimentSpec& spec,
                                 const ModelSpec& model) {
    const fs::path weights = trained_weights_.at(variant);
    if (!model.blend || *model.blend == 1) return weights.string();
    std::string start = "movenet-multipose";
    for (const auto& [key, value] : spec.training->options) {
      if (key == "model") start = value;
    }
    const std::string alpha = number_text(*model.blend);
    const std::string label = "blend " + variant + " " + shortest_number_text(*model.blend);
    const fs::path dir = add("blend", variant, label, false, [&](const fs::path& at) {
      return std::vector<std::vector<std::string>>{{"model", "blend", "--start", start,
                                                    "--finetuned", weights.string(), "--alpha",
                                                    alpha, "--out", (at / "blend.pt").string()}};
    });
    return (dir / "blend.pt").string();
  }

  void score(const std::string& variant, const ExperimentSpec& spec, const ModelSpec& model,
             const ScoreSpec& s) {
    const DatasetFiles files = dataset(spec, s.set);
    std::vector<std::string> predict = {"predict"};
    for (const std::string& member : model.members) {
      predict.insert(predict.end(), {"--model", member_model(variant, spec, model, member)});
    }
    if (model.flip) predict.push_back("--flip");
    predict.insert(predict.end(),
                   {"--coco", files.coco.string(), "--images", files.images.string()});
    if (s.size) predict.insert(predict.end(), {"--size", std::to_string(s.size)});
    const std::string label = "score " + model.name + " on " + s.set + " (" + variant + ")";
    const fs::path dir =
        add("score", s.set + "-" + model.name, label, false, [&](const fs::path& at) {
          std::vector<std::string> p = predict;
          p.insert(p.end(), {"--out", (at / "results.json").string()});
          return std::vector<std::vector<std::string>>{
              p,
              {"eval", "--gt", files.coco.string(), "--dt", (at / "results.json").string(),
               "--type", s.type, "--out", at.string()}};
        });
    ScoreRef ref{variant, model.name, s.set, s.type, s.size, dir / "metrics.json"};
    ref.gt = files.coco;
    ref.results = dir / "results.json";
    plan_.scores.push_back(ref);
  }

  // Points the scores added since `first` at the `intervals:` baseline scored among them.
  void link_baseline(std::size_t first, const IntervalSpec& intervals) {
    const auto end = plan_.scores.end();
    const auto base = std::find_if(plan_.scores.begin() + first, end,
                                   [&](const ScoreRef& r) { return r.model == intervals.against; });
    if (base == end) return;  // the baseline is not scored on this set: no intervals here
    for (auto it = plan_.scores.begin() + first; it != end; ++it) {
      if (it == base) continue;
      it->baseline_results = base->results;
      it->baseline_model = base->model;
      it->resamples = intervals.resamples;
      it->resample_seed = intervals.seed;
    }
  }

  std::size_t score_count() const { return plan_.scores.size(); }

  Plan finish() {
    for (Step& step : plan_.steps) {
      auto images = split_images_.find(step.dir);
      if (images != split_images_.end()) step.link_images = images->second;
    }
    return std::move(plan_);
  }

 private:
  std::string serialize(const std::vector<std::vector<std::string>>& commands) const {
    std::string text;
    for (const auto& command : commands) {
      for (const std::string& arg : command) text += arg + '\x1f';
      text += '\n';
    }
    return text;
  }

  // The contents of the files the commands read from outside the run (scenario, clip list,
  // annotations, weights; a shipped model by name is its folder's files), so a step whose input
  // file was edited since the last run is a new step, not a stale reuse. Image folders are not
  // read: they are too large, and an image set is named by its annotations.
  std::string input_contents(const std::vector<std::vector<std::string>>& commands) {
    std::string text;
    for (const auto& command : commands) {
      for (std::size_t i = 0; i < command.size(); ++i) {
        const bool model_name = i > 0 && command[i - 1] == "--model";
        for (const fs::path& file : input_files(command[i], model_name)) {
          text += '\x1e' + content_hash(file);
        }
      }
    }
    return text;
  }

  std::vector<fs::path> input_files(const std::string& arg, bool model_name) const {
    std::error_code ec;
    const fs::path path = arg;
    const auto inside =
        std::mismatch(out_dir_.begin(), out_dir_.end(), path.begin(), path.end()).first;
    if (inside == out_dir_.end()) return {};  // another step's output: its id says what it holds
    if (fs::is_regular_file(path, ec)) return {path};
    const auto& shipped = learn::shipped_model_names();
    if (!model_name || std::find(shipped.begin(), shipped.end(), arg) == shipped.end()) return {};
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(learn::shipped_models_dir() / arg, ec)) {
      if (entry.is_regular_file(ec)) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    return files;
  }

  const std::string& content_hash(const fs::path& file) {
    auto [at, added] = content_hashes_.try_emplace(file);
    if (added) {
      std::ifstream in(file, std::ios::binary);
      std::ostringstream bytes;
      bytes << in.rdbuf();
      at->second = stable_hash(bytes.str());
    }
    return at->second;
  }

  fs::path out_dir_, steps_dir_;
  std::map<fs::path, std::string> content_hashes_;
  Plan plan_;
  std::map<std::string, fs::path> trained_weights_;
  std::map<fs::path, fs::path> split_images_;
};

}  // namespace

std::string stable_hash(const std::string& text) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

Plan make_plan(const std::vector<Variant>& variants, const fs::path& out_dir) {
  Planner planner(out_dir);
  for (const Variant& v : variants) {
    for (const DatasetSpec& d : v.spec.datasets) planner.dataset(v.spec, d.name);
    if (v.spec.uses_training()) planner.train(v.name, v.spec);
    for (const ScoreSpec& s : v.spec.scores) {
      const std::size_t first = planner.score_count();
      for (const ModelSpec& m : v.spec.models) {
        if (!s.models.empty() &&
            std::find(s.models.begin(), s.models.end(), m.name) == s.models.end()) {
          continue;
        }
        planner.score(v.name, v.spec, m, s);
      }
      if (v.spec.intervals) planner.link_baseline(first, *v.spec.intervals);
    }
  }
  return planner.finish();
}

}  // namespace wheelpose::experiment
