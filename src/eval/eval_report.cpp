#include "eval/eval_report.h"

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <string>

namespace wheelpose::eval {
namespace {

using nlohmann::json;

json number_or_null(std::optional<double> v) { return v ? json(*v) : json(nullptr); }

// The per-keypoint metrics every report shows, in column order: a new metric is a field of
// KeypointStats (computed in keypoint_metrics.cpp) and a row here.
struct MetricColumn {
  const char* key;     // in metrics.json
  const char* header;  // in Markdown tables; (+) higher is better, (-) lower is better
  const char* format;
  std::optional<double> KeypointStats::*value;
};
constexpr MetricColumn kMetricColumns[] = {
    {"pdj5", "PDJ@5 (+)", "%.3f", &KeypointStats::pdj5},
    {"pjpe", "PJPE (-)", "%.2f", &KeypointStats::pjpe},
    {"oks50", "OKS50 (+)", "%.3f", &KeypointStats::oks50},
    {"oks75", "OKS75 (+)", "%.3f", &KeypointStats::oks75},
};

// "| Keypoint | <metric headers> | <extra>... |" and its separator row.
std::string table_header(std::initializer_list<const char*> extra) {
  std::string head = "| Keypoint |", rule = "|---|";
  for (const MetricColumn& c : kMetricColumns) {
    head += std::string(" ") + c.header + " |";
    rule += "---|";
  }
  for (const char* e : extra) {
    head += std::string(" ") + e + " |";
    rule += "---|";
  }
  return head + "\n" + rule + "\n";
}

std::optional<double> stat_value(const std::optional<EvalSummary>& s, const std::string& key) {
  return s ? s->stat(key) : std::nullopt;
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
  json out{{"count", k.count}, {"missed", k.missed}};
  for (const MetricColumn& c : kMetricColumns) out[c.key] = number_or_null(k.*c.value);
  return out;
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
  json out = json::object();
  for (const MetricColumn& c : kMetricColumns) {
    out[c.key] = number_or_null(percent_change(ours.*c.value, base.*c.value));
  }
  return out;
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
  std::string out = table_header({"Keypoints", "Missed"});
  for (const KeypointStats* k : rows(m)) {
    out += "| " + k->name + " |";
    for (const MetricColumn& c : kMetricColumns) out += " " + fmt(k->*c.value, c.format) + " |";
    out += " " + std::to_string(k->count) + " | " + std::to_string(k->missed) + " |\n";
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
    out += "\n## Keypoint breakdown (ours, percent change vs baseline)\n\n" + table_header({});
    const auto ra = rows(a), rb = rows(b);
    for (std::size_t i = 0; i < ra.size() && i < rb.size(); ++i) {
      out += "| " + ra[i]->name + " |";
      for (const MetricColumn& c : kMetricColumns) {
        out += " " + with_change(ra[i]->*c.value, rb[i]->*c.value, c.format) + " |";
      }
      out += "\n";
    }
    out += "\n## Keypoint breakdown (baseline)\n\n" + keypoint_table_markdown(b);
    out += "\n## Keypoint breakdown (ours)\n\n" + keypoint_table_markdown(a);
  }
  return out;
}

}  // namespace wheelpose::eval
