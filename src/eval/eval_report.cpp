#include "eval/eval_report.h"

#include <cmath>
#include <cstdio>

namespace wheelpose::eval {
namespace {

using nlohmann::json;

json number_or_null(std::optional<double> v) { return v ? json(*v) : json(nullptr); }

std::optional<double> stat_value(const std::optional<EvalSummary>& s, const std::string& key) {
  if (!s) return std::nullopt;
  for (const auto& line : s->stats) {
    if (line.key == key) return line.value < 0 ? std::nullopt : std::optional<double>(line.value);
  }
  return std::nullopt;
}

json summary_json(const EvalSummary& s) {
  json stats = json::object();
  json list = json::array();
  for (const auto& line : s.stats) {
    stats[line.key] = line.value;
    list.push_back(line.value);
  }
  return json{{"stats", stats}, {"stats_list", list}, {"summary", s.text}};
}

json stats_json(const KeypointStats& k) {
  return json{{"count", k.count},
              {"missed", k.missed},
              {"pdj5", number_or_null(k.pdj5)},
              {"pjpe", number_or_null(k.pjpe)},
              {"oks50", number_or_null(k.oks50)},
              {"oks75", number_or_null(k.oks75)}};
}

json metrics_json_of(const KeypointMetrics& m) {
  json per = json::object(), groups = json::object();
  for (const auto& k : m.keypoints) per[k.name] = stats_json(k);
  for (const auto& g : m.groups) groups[g.name] = stats_json(g);
  return json{
      {"gt_people", m.gt_people},         {"pairs", m.pairs}, {"missed_people", m.missed_people},
      {"overall", stats_json(m.overall)}, {"keypoints", per}, {"groups", groups}};
}

json stats_change(const KeypointStats& ours, const KeypointStats& base) {
  return json{{"pdj5", number_or_null(percent_change(ours.pdj5, base.pdj5))},
              {"pjpe", number_or_null(percent_change(ours.pjpe, base.pjpe))},
              {"oks50", number_or_null(percent_change(ours.oks50, base.oks50))},
              {"oks75", number_or_null(percent_change(ours.oks75, base.oks75))}};
}

json summary_change(const EvalSummary& ours, const std::optional<EvalSummary>& base) {
  json out = json::object();
  for (const auto& line : ours.stats) {
    out[line.key] =
        number_or_null(percent_change(stat_value(ours, line.key), stat_value(base, line.key)));
  }
  return out;
}

std::string fmt(std::optional<double> v, const char* format) {
  if (!v) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, *v);
  return buf;
}

std::string with_change(std::optional<double> v, std::optional<double> base, const char* format) {
  const std::optional<double> change = percent_change(v, base);
  return fmt(v, format) + (change ? " (" + fmt(change, "%+.2f") + "%)" : "");
}

// The rows of Table 6: the template's groups, then everything pooled.
std::vector<const KeypointStats*> rows(const KeypointMetrics& m) {
  std::vector<const KeypointStats*> out;
  for (const auto& g : m.groups) out.push_back(&g);
  out.push_back(&m.overall);
  return out;
}

}  // namespace

std::optional<double> percent_change(std::optional<double> ours, std::optional<double> baseline) {
  if (!ours || !baseline || *baseline == 0.0) return std::nullopt;
  return (*ours - *baseline) / std::fabs(*baseline) * 100.0;
}

json report_to_json(const ResultReport& r) {
  json out{{"path", r.results_path}};
  if (r.keypoints) out["keypoints"] = summary_json(*r.keypoints);
  if (r.bbox) out["bbox"] = summary_json(*r.bbox);
  if (r.keypoint_metrics) out["keypoint_metrics"] = metrics_json_of(*r.keypoint_metrics);
  return out;
}

json metrics_json(const std::string& gt_path, const std::string& template_name,
                  const ResultReport& ours, const ResultReport* baseline) {
  json out{{"gt", gt_path}, {"template", template_name}, {"results", report_to_json(ours)}};
  if (!baseline) return out;
  out["baseline"] = report_to_json(*baseline);
  json change = json::object();
  if (ours.keypoints) change["keypoints"] = summary_change(*ours.keypoints, baseline->keypoints);
  if (ours.bbox) change["bbox"] = summary_change(*ours.bbox, baseline->bbox);
  if (ours.keypoint_metrics && baseline->keypoint_metrics) {
    const KeypointMetrics& a = *ours.keypoint_metrics;
    const KeypointMetrics& b = *baseline->keypoint_metrics;
    json per = json::object(), groups = json::object();
    for (std::size_t i = 0; i < a.keypoints.size() && i < b.keypoints.size(); ++i) {
      per[a.keypoints[i].name] = stats_change(a.keypoints[i], b.keypoints[i]);
    }
    for (std::size_t i = 0; i < a.groups.size() && i < b.groups.size(); ++i) {
      groups[a.groups[i].name] = stats_change(a.groups[i], b.groups[i]);
    }
    change["keypoint_metrics"] = {
        {"overall", stats_change(a.overall, b.overall)}, {"keypoints", per}, {"groups", groups}};
  }
  out["change_percent"] = change;
  return out;
}

std::string keypoint_table_markdown(const KeypointMetrics& m) {
  std::string out =
      "| Keypoint | PDJ@5 (+) | PJPE (-) | OKS50 (+) | OKS75 (+) | Keypoints | Missed |\n"
      "|---|---|---|---|---|---|---|\n";
  for (const KeypointStats* k : rows(m)) {
    out += "| " + k->name + " | " + fmt(k->pdj5, "%.3f") + " | " + fmt(k->pjpe, "%.2f") + " | " +
           fmt(k->oks50, "%.3f") + " | " + fmt(k->oks75, "%.3f") + " | " +
           std::to_string(k->count) + " | " + std::to_string(k->missed) + " |\n";
  }
  out += "\nMatched people: " + std::to_string(m.pairs) + " of " + std::to_string(m.gt_people) +
         " (missed " + std::to_string(m.missed_people) + ").\n";
  return out;
}

std::string comparison_markdown(const ResultReport& ours, const ResultReport& base) {
  std::string out = "## COCO metrics\n\n| Metric | Baseline | Ours | Change |\n|---|---|---|---|\n";
  const auto add_stats = [&](const char* prefix, const std::optional<EvalSummary>& a,
                             const std::optional<EvalSummary>& b) {
    if (!a) return;
    for (const auto& line : a->stats) {
      const auto va = stat_value(a, line.key), vb = stat_value(b, line.key);
      const auto change = percent_change(va, vb);
      out += std::string("| ") + prefix + " " + line.key + " | " + fmt(vb, "%.3f") + " | " +
             fmt(va, "%.3f") + " | " + (change ? fmt(change, "%+.2f") + "%" : "n/a") + " |\n";
    }
  };
  add_stats("KP", ours.keypoints, base.keypoints);
  add_stats("BB", ours.bbox, base.bbox);
  if (ours.keypoint_metrics && base.keypoint_metrics) {
    const KeypointMetrics& a = *ours.keypoint_metrics;
    const KeypointMetrics& b = *base.keypoint_metrics;
    out +=
        "\n## Keypoint breakdown (ours, percent change vs baseline)\n\n"
        "| Keypoint | PDJ@5 (+) | PJPE (-) | OKS50 (+) | OKS75 (+) |\n|---|---|---|---|---|\n";
    const auto ra = rows(a), rb = rows(b);
    for (std::size_t i = 0; i < ra.size() && i < rb.size(); ++i) {
      out += "| " + ra[i]->name + " | " + with_change(ra[i]->pdj5, rb[i]->pdj5, "%.3f") + " | " +
             with_change(ra[i]->pjpe, rb[i]->pjpe, "%.2f") + " | " +
             with_change(ra[i]->oks50, rb[i]->oks50, "%.3f") + " | " +
             with_change(ra[i]->oks75, rb[i]->oks75, "%.3f") + " |\n";
    }
    out += "\n## Keypoint breakdown (baseline)\n\n" + keypoint_table_markdown(b);
    out += "\n## Keypoint breakdown (ours)\n\n" + keypoint_table_markdown(a);
  }
  return out;
}

}  // namespace wheelpose::eval
