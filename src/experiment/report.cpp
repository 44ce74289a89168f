#include "experiment/report.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <sstream>

#include "core/atomic_file.h"
#include "core/coco_data.h"
#include "core/error.h"
#include "core/html.h"
#include "core/keypoint_template.h"
#include "eval/bootstrap.h"

namespace wheelpose::experiment {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Points (AP × 100) with one decimal, "–" when eval had nothing to score.
std::string points(const json& stats, const char* key) {
  if (!stats.is_object() || !stats.contains(key)) return "–";
  const double value = stats[key].get<double>();
  if (value < 0) return "–";
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(1);
  out << std::round(value * 1000) / 10;
  return out.str();
}

std::string set_title(const json& row) {
  std::string title = row["set"].get<std::string>();
  if (row["size"].get<int>() != 0) title += " at --size " + std::to_string(row["size"].get<int>());
  return title;
}

// Rows grouped by scored set, in the order they first appear.
std::vector<std::pair<std::string, std::vector<json>>> by_set(const json& results) {
  std::vector<std::pair<std::string, std::vector<json>>> groups;
  for (const json& row : results["results"]) {
    const std::string title = set_title(row);
    auto it =
        std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == title; });
    if (it == groups.end()) {
      groups.push_back({title, {}});
      it = groups.end() - 1;
    }
    it->second.push_back(row);
  }
  return groups;
}

// A gain and its interval in points, "+1.8 [-1.1, +6.5]"; "–" where there is none.
std::string gain(const json& row, const char* kind) {
  if (!row.contains("against") || !row["against"].contains(kind)) return "–";
  const json& ap = row["against"][kind]["AP"];
  if (ap["estimate"].is_null() || ap["low"].is_null()) return "–";
  char text[64];
  std::snprintf(text, sizeof text, "%+.1f [%+.1f, %+.1f]", ap["estimate"].get<double>() * 100,
                ap["low"].get<double>() * 100, ap["high"].get<double>() * 100);
  return text;
}

// Which model the gains are over and how they were resampled (the first row that says).
std::string gains_note(const json& results) {
  for (const json& row : results["results"]) {
    if (!row.contains("against")) continue;
    const json& a = row["against"];
    return "Gains are over `" + a["model"].get<std::string>() +
           "` on the same images, with the 95 % interval of a paired bootstrap over the set's " +
           "images (" + std::to_string(a["resamples"].get<int>()) + " resamples, seed " +
           std::to_string(a["seed"].get<std::uint64_t>()) +
           "; `wheelpose eval --bootstrap`): an interval that holds 0 is a gain the set cannot "
           "tell from chance.";
  }
  return "";
}

bool has_gains(const json& results) {
  for (const json& row : results["results"]) {
    if (row.contains("against")) return true;
  }
  return false;
}

std::vector<std::string> cells(const json& row, bool gains) {
  const json kp = row.value("keypoints", json()), box = row.value("bbox", json());
  std::vector<std::string> out = {row["variant"].get<std::string>(),
                                  row["model"].get<std::string>(),
                                  points(kp, "AP"),
                                  points(kp, "AP50"),
                                  points(box, "AP"),
                                  points(box, "AP50")};
  if (gains) {
    out.push_back(gain(row, "keypoints"));
    out.push_back(gain(row, "bbox"));
  }
  return out;
}

std::vector<std::string> columns(bool gains) {
  std::vector<std::string> out = {"variant",       "model",  "keypoint AP",
                                  "keypoint AP50", "box AP", "box AP50"};
  if (gains) out.insert(out.end(), {"keypoint AP gain [95 %]", "box AP gain [95 %]"});
  return out;
}

// What the paired bootstrap says of one score against its baseline's on the same images.
json gains_against_baseline(const ScoreRef& score,
                            std::map<std::string, coco::CocoGroundTruth>& ground_truths) {
  static const KeypointTemplate coco17 = load_keypoint_template("coco17");
  const bool keypoints = score.type != "bbox";
  const std::string key = score.gt.string() + (keypoints ? "\n+keypoints" : "");
  auto at = ground_truths.find(key);
  if (at == ground_truths.end()) {
    at = ground_truths.emplace(key, coco::load_coco_gt(score.gt, coco17.size(), keypoints)).first;
  }
  const coco::CocoGroundTruth& gt = at->second;
  const coco::CocoResults ours = coco::load_coco_results(score.results, gt, coco17.size());
  const coco::CocoResults base = coco::load_coco_results(score.baseline_results, gt, coco17.size());
  eval::BootstrapOptions options;
  options.samples = score.resamples;
  options.seed = score.resample_seed;
  json out = {{"model", score.baseline_model},
              {"resamples", score.resamples},
              {"seed", score.resample_seed}};
  for (const auto type : {coco::IouType::kKeypoints, coco::IouType::kBbox}) {
    const bool is_keypoints = type == coco::IouType::kKeypoints;
    if (is_keypoints ? !keypoints : score.type == "keypoints") continue;
    const eval::BootstrapResult r = eval::bootstrap_ap(gt, ours, &base, type, coco17, options);
    out[is_keypoints ? "keypoints" : "bbox"] = eval::bootstrap_json(r)["difference"];
  }
  return out;
}

}  // namespace

std::string project_commit() {
  const std::string command = std::string("git -C '") + WHEELPOSE_SOURCE_DIR +
                              "' describe --always --dirty --abbrev=12 --exclude '*' 2>/dev/null";
  std::string text;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[128];
    while (fgets(buffer, sizeof buffer, pipe)) text += buffer;
    pclose(pipe);
  }
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text.empty() ? "unknown" : text;
}

json collect_results(const ReportInputs& inputs, const Plan& plan,
                     const std::vector<StepRecord>& steps) {
  json rows = json::array();
  std::map<std::string, coco::CocoGroundTruth> ground_truths;
  for (const ScoreRef& score : plan.scores) {
    std::error_code ec;
    if (!fs::exists(score.metrics, ec)) continue;
    const json metrics = json::parse(read_file(score.metrics), nullptr, false);
    if (!metrics.is_object() || !metrics.contains("results")) {
      throw Error(score.metrics.string() + ": not an eval metrics file", ErrorKind::kFailure);
    }
    json row = {{"variant", score.variant},
                {"model", score.model},
                {"set", score.set},
                {"type", score.type},
                {"size", score.size}};
    for (const char* kind : {"keypoints", "bbox"}) {
      if (metrics["results"].contains(kind)) row[kind] = metrics["results"][kind]["stats"];
    }
    if (!score.baseline_results.empty() && fs::exists(score.results, ec) &&
        fs::exists(score.baseline_results, ec)) {
      row["against"] = gains_against_baseline(score, ground_truths);
    }
    rows.push_back(row);
  }
  json step_rows = json::array();
  double total = 0;
  for (const StepRecord& s : steps) {
    step_rows.push_back(
        {{"id", s.id}, {"kind", s.kind}, {"label", s.label}, {"seconds", s.seconds}});
    total += s.seconds;
  }
  json curves = json::object();
  for (const auto& [variant, dir] : plan.train_runs) {
    curves[variant] = (fs::path("steps") / dir.filename() / "curves.svg").string();
  }
  return {{"experiment", inputs.name},
          {"description", inputs.description},
          {"file", inputs.config_file.string()},
          {"commit", inputs.commit},
          {"variants", inputs.variants},
          {"results", rows},
          {"steps", step_rows},
          {"wall_seconds", total},
          {"training_curves", curves},
          {"config", inputs.config_text}};
}

std::string report_markdown(const json& results) {
  std::ostringstream md;
  md << "# Experiment: " << results["experiment"].get<std::string>() << "\n\n";
  if (!results["description"].get<std::string>().empty()) {
    md << results["description"].get<std::string>() << "\n\n";
  }
  md << "From `" << results["file"].get<std::string>() << "` at commit "
     << results["commit"].get<std::string>() << "; every number is in results.json. Points are "
     << "COCO AP × 100 (`wheelpose eval`).\n";
  const bool gains = has_gains(results);
  if (gains) md << "\n" << gains_note(results) << "\n";
  for (const auto& [title, rows] : by_set(results)) {
    md << "\n## " << title << "\n\n|";
    for (const std::string& c : columns(gains)) md << " " << c << " |";
    md << "\n|";
    for (std::size_t i = 0; i < columns(gains).size(); ++i) md << "---|";
    md << "\n";
    for (const json& row : rows) {
      md << "|";
      for (const std::string& c : cells(row, gains)) md << " " << c << " |";
      md << "\n";
    }
  }
  md << "\n## Steps\n\n| step | seconds |\n|---|---|\n";
  for (const json& s : results["steps"]) {
    md << "| " << s["label"].get<std::string>() << " | " << std::lround(s["seconds"].get<double>())
       << " |\n";
  }
  md << "\nTotal wall time: " << std::lround(results["wall_seconds"].get<double>()) << " s.\n";
  if (!results["training_curves"].empty()) {
    md << "\n## Training curves\n\n";
    for (const auto& [variant, path] : results["training_curves"].items()) {
      md << "- " << variant << ": `" << path.get<std::string>() << "`\n";
    }
  }
  return md.str();
}

std::string report_html(const json& results) {
  std::ostringstream h;
  const std::string name = html_escape(results["experiment"].get<std::string>());
  h << "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Experiment: "
    << name
    << "</title>\n<style>body{font-family:sans-serif;max-width:60em;margin:2em auto}"
       "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:.2em .6em}"
       "td{text-align:right}td:first-child,td:nth-child(2){text-align:left}img{max-width:100%}"
       "</style></head><body>\n<h1>Experiment: "
    << name << "</h1>\n<p>" << html_escape(results["description"].get<std::string>())
    << "</p>\n<p>From <code>" << html_escape(results["file"].get<std::string>())
    << "</code> at commit <code>" << html_escape(results["commit"].get<std::string>())
    << "</code>. Points are COCO AP &times; 100.</p>\n";
  const bool gains = has_gains(results);
  if (gains) h << "<p>" << html_escape(gains_note(results)) << "</p>\n";
  for (const auto& [title, rows] : by_set(results)) {
    h << "<h2>" << html_escape(title) << "</h2>\n<table><tr>";
    for (const std::string& c : columns(gains)) h << "<th>" << html_escape(c) << "</th>";
    h << "</tr>\n";
    for (const json& row : rows) {
      h << "<tr>";
      for (const std::string& c : cells(row, gains)) h << "<td>" << html_escape(c) << "</td>";
      h << "</tr>\n";
    }
    h << "</table>\n";
  }
  for (const auto& [variant, path] : results["training_curves"].items()) {
    h << "<h2>Training: " << html_escape(variant) << "</h2>\n<img src=\""
      << html_escape(path.get<std::string>()) << "\" alt=\"training curves of "
      << html_escape(variant) << "\">\n";
  }
  h << "<p>Total wall time " << std::lround(results["wall_seconds"].get<double>())
    << " s.</p>\n</body></html>\n";
  return h.str();
}

void write_reports(const json& results, const fs::path& out_dir) {
  write_file_atomic(out_dir / "results.json", results.dump(1) + "\n");
  write_file_atomic(out_dir / "report.md", report_markdown(results));
  write_file_atomic(out_dir / "report.html", report_html(results));
}

}  // namespace wheelpose::experiment
