#include "experiment/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/html.h"

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

std::vector<std::string> cells(const json& row) {
  const json kp = row.value("keypoints", json()), box = row.value("bbox", json());
  return {row["variant"].get<std::string>(),
          row["model"].get<std::string>(),
          points(kp, "AP"),
          points(kp, "AP50"),
          points(box, "AP"),
          points(box, "AP50")};
}

const std::vector<std::string> kColumns = {"variant",       "model",  "keypoint AP",
                                           "keypoint AP50", "box AP", "box AP50"};

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
  for (const auto& [title, rows] : by_set(results)) {
    md << "\n## " << title << "\n\n|";
    for (const std::string& c : kColumns) md << " " << c << " |";
    md << "\n|";
    for (std::size_t i = 0; i < kColumns.size(); ++i) md << "---|";
    md << "\n";
    for (const json& row : rows) {
      md << "|";
      for (const std::string& c : cells(row)) md << " " << c << " |";
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
  for (const auto& [title, rows] : by_set(results)) {
    h << "<h2>" << html_escape(title) << "</h2>\n<table><tr>";
    for (const std::string& c : kColumns) h << "<th>" << html_escape(c) << "</th>";
    h << "</tr>\n";
    for (const json& row : rows) {
      h << "<tr>";
      for (const std::string& c : cells(row)) h << "<td>" << html_escape(c) << "</td>";
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
