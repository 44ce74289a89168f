// `wheelpose coco`: validate, merge, sample, split, export and visualise COCO person-keypoint
// files. Every file written is in the canonical form described in dataset/coco_file.h.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/keypoint_template.h"
#include "dataset/coco_file.h"
#include "dataset/coco_tools.h"
#include "dataset/coco_viz.h"
#include "dataset/exporters.h"
#include "dataset/yolo_import.h"

namespace wheelpose::app {
namespace {

namespace fs = std::filesystem;
using dataset::json;

struct CocoOptions {
  std::string file;
  std::vector<std::string> inputs;
  std::string images;
  std::string out;
  bool replace_by_filename = false;
  std::int64_t n = 0;
  std::uint64_t seed = 0;
  bool even = false;
  bool plain = false;  // viz: no overlays
  std::string ratios = "0.8,0.1,0.1";
  std::string names;
  std::string group_by = "motion";
  std::string format = "yolo-pose";
  std::string keypoint_template = "coco17";
  std::string labels;
  std::string classes;
  std::string description;
};

void run_validate(const CocoOptions& o) {
  const json root = dataset::load_json(o.file);
  dataset::ValidateOptions options;
  if (!o.images.empty()) {
    if (!fs::is_directory(o.images)) throw Error(o.images + ": not a directory (--images)");
    options.images_dir = o.images;
  }
  const auto problems = dataset::validate_coco(root, options);
  std::string text;
  for (const auto& p : problems) text += o.file + ": " + p.path + ": " + p.message + "\n";
  std::fputs(text.c_str(), stdout);
  std::fflush(stdout);
  auto count = [&](const char* key) {
    return root.is_object() && root.contains(key) && root[key].is_array() ? root[key].size() : 0;
  };
  const std::string totals = std::to_string(count("images")) + " images, " +
                             std::to_string(count("annotations")) + " annotations, " +
                             std::to_string(count("categories")) + " categories";
  if (!problems.empty()) {
    throw Error(o.file + ": " + std::to_string(problems.size()) + " problem(s) in " + totals);
  }
  std::printf("%s: valid (%s)\n", o.file.c_str(), totals.c_str());
}

void run_merge(const CocoOptions& o) {
  std::vector<dataset::NamedCoco> inputs;
  for (const auto& path : o.inputs) inputs.push_back({path, dataset::load_json(path)});
  const json merged = dataset::merge_coco(inputs, o.replace_by_filename);
  dataset::write_coco(o.out, merged);
  spdlog::info("{}: {} images, {} annotations from {} file(s)", o.out, merged["images"].size(),
               merged["annotations"].size(), inputs.size());
}

void run_sample(const CocoOptions& o, bool seed_given) {
  if (o.even && seed_given) throw Error("coco sample: --seed and --even exclude each other");
  const json root = dataset::load_json(o.file);
  const json out = dataset::sample_coco(root, o.file, o.n, o.even, o.seed);
  dataset::write_coco(o.out, out);
  spdlog::info("{}: {} images, {} annotations", o.out, out["images"].size(),
               out["annotations"].size());
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.push_back(item);
  return out;
}

void run_split(const CocoOptions& o) {
  std::vector<double> ratios;
  for (const auto& item : split_list(o.ratios)) {
    try {
      std::size_t used = 0;
      ratios.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw Error("--ratios: '" + item + "' is not a number (expected e.g. 0.8,0.1,0.1)");
    }
  }
  std::vector<std::string> names = split_list(o.names);
  if (names.empty()) {
    if (ratios.size() == 3) {
      names = {"train", "val", "test"};
    } else if (ratios.size() == 2) {
      names = {"train", "val"};
    } else {
      for (std::size_t k = 0; k < ratios.size(); ++k) names.push_back("part" + std::to_string(k));
    }
  }
  for (const auto& name : names) {
    // Names become file names in --out; keep them plain.
    if (name.empty() ||
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                               "0123456789_-") != std::string::npos) {
      throw Error("--names: '" + name + "' must be letters, digits, '_' or '-'");
    }
  }
  if (names.size() != ratios.size()) {
    throw Error("--names: " + std::to_string(names.size()) + " names for " +
                std::to_string(ratios.size()) + " ratios");
  }
  const json root = dataset::load_json(o.file);
  dataset::require_usable(root, o.file);
  const auto parts = dataset::split_coco(
      root, ratios, names,
      o.group_by == "image" ? dataset::GroupBy::kImage : dataset::GroupBy::kMotion, o.seed);
  ensure_directory(o.out);
  for (const auto& part : parts) {
    dataset::write_coco(fs::path(o.out) / (part.name + ".json"), part.root);
    spdlog::info("{}: {} images, {} annotations", part.name, part.root["images"].size(),
                 part.root["annotations"].size());
  }
}

void run_export(const CocoOptions& o) {
  const json root = dataset::load_json(o.file);
  const auto t = load_keypoint_template(o.keypoint_template);
  const std::size_t lines = dataset::dataset_exporter(o.format).write(root, o.file, t, o.out);
  spdlog::info("{}: {} label lines for {} images", o.out, lines, root["images"].size());
}

void run_viz(const CocoOptions& o) {
  const json root = dataset::load_json(o.file);
  const std::size_t drawn = dataset::visualize_coco(root, o.file, o.images, o.out, o.n, !o.plain);
  spdlog::info("{}: {} images and contact_sheet.png", o.out, drawn);
}

void run_import_yolo(const CocoOptions& o) {
  check_output_file(o.out);
  const dataset::YoloImportOptions options{.images_dir = o.images,
                                           .labels_dir = o.labels,
                                           .classes = dataset::parse_yolo_classes(o.classes),
                                           .description = o.description};
  const json root = dataset::import_yolo(options, load_keypoint_template(o.keypoint_template));
  dataset::write_coco(o.out, root);
  std::size_t people = 0;
  for (const json& a : root["annotations"]) people += a["iscrowd"] == 0;
  spdlog::info("{}: {} images, {} people, {} crowd regions", o.out, root["images"].size(), people,
               root["annotations"].size() - people);
}

}  // namespace

void attach_coco(CLI::App& parent) {
  auto* coco =
      parent.add_subcommand("coco", "Validate, merge, sample, split, export and view COCO files");
  coco->require_subcommand(1);
  auto o = std::make_shared<CocoOptions>();

  auto* validate = coco->add_subcommand(
      "validate", "Report every schema and meaning problem with its JSON path (exit 2 if any)");
  validate->add_option("file", o->file, "COCO keypoint JSON")->required();
  validate->add_option("--images", o->images, "Image directory: every file_name must exist in it");
  validate->callback([o] { run_validate(*o); });

  auto* merge = coco->add_subcommand(
      "merge", "Concatenate COCO files, renumbering images and annotations from 1 in input order");
  merge->add_option("inputs", o->inputs, "COCO files, in order")->required();
  merge->add_option("--out", o->out, "Merged COCO file")->required();
  merge->add_flag(
      "--replace-by-filename", o->replace_by_filename,
      "The first file is the base; later files relabel its images matched by file_name");
  merge->callback([o] { run_merge(*o); });

  auto* sample = coco->add_subcommand("sample", "Keep N images (seeded random or evenly spaced)");
  sample->add_option("file", o->file, "COCO file")->required();
  sample->add_option("--n", o->n, "Number of images")->required();
  auto* seed_opt = sample->add_option("--seed", o->seed, "Random seed (default 0)");
  sample->add_flag("--even", o->even, "Evenly spaced by id, first and last included");
  sample->add_option("--out", o->out, "Output COCO file")->required();
  sample->callback([o, seed_opt] { run_sample(*o, seed_opt->count() > 0); });

  auto* split = coco->add_subcommand(
      "split", "Cut into parts by ratio; frames of one motion clip stay together");
  split->add_option("file", o->file, "COCO file")->required();
  split->add_option("--ratios", o->ratios, "Comma-separated ratios (default 0.8,0.1,0.1)");
  split->add_option("--names", o->names, "Comma-separated part names (default train,val,test)");
  split->add_option("--group-by", o->group_by, "motion (images sharing motion_id) or image")
      ->check(CLI::IsMember({"motion", "image"}));
  split->add_option("--seed", o->seed, "Random seed (default 0)");
  split->add_option("--out", o->out, "Output directory (<name>.json per part)")->required();
  split->callback([o] { run_split(*o); });

  auto* exp = coco->add_subcommand("export", "Write labels for another framework");
  exp->add_option("file", o->file, "COCO file")->required();
  std::string formats;
  for (const dataset::DatasetExporter& e : dataset::dataset_exporters()) {
    formats += (formats.empty() ? "" : "; ") + std::string(e.name) + ": " + e.description;
  }
  exp->add_option("--format", o->format, "Label format (" + formats + ")")
      ->check(CLI::IsMember(dataset::dataset_exporter_names()));
  exp->add_option("--template", o->keypoint_template,
                  "Keypoint template for flip indices: coco17 or a template JSON");
  exp->add_option("--out", o->out, "Output directory")->required();
  exp->callback([o] { run_export(*o); });

  auto* viz = coco->add_subcommand("viz", "Draw boxes, skeletons and masks; and a contact sheet");
  viz->add_option("file", o->file, "COCO file")->required();
  viz->add_option("--images", o->images, "Image directory")->required();
  viz->add_option("--out", o->out, "Output directory")->required();
  o->n = 16;
  viz->add_option("--n", o->n, "Number of images (first by id; default 16)");
  viz->add_flag("--plain", o->plain, "The images without overlays (a contact sheet of the frames)");
  viz->callback([o] { run_viz(*o); });

  auto* yolo = coco->add_subcommand(
      "import-yolo", "Read YOLO box (or pose) labels into a COCO file, mapping classes to roles");
  yolo->add_option("--images", o->images, "Image directory")->required();
  yolo->add_option("--labels", o->labels, "Label directory (<image stem>.txt; default --images)");
  yolo->add_option("--classes", o->classes,
                   "Each YOLO class's role: CLASS=person|crowd|drop, comma-separated (e.g. "
                   "1=person,0=crowd); a class not listed is an error")
      ->required();
  yolo->add_option("--template", o->keypoint_template,
                   "Keypoint template of the category (and of keypoints in the labels)");
  yolo->add_option("--description", o->description, "info.description, e.g. the data's source");
  yolo->add_option("--out", o->out, "Output COCO file")->required();
  yolo->callback([o] { run_import_yolo(*o); });
}

}  // namespace wheelpose::app
