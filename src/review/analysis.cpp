#include "review/analysis.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/html.h"

namespace wheelpose::review {
namespace {

using nlohmann::json;
using nlohmann::ordered_json;

std::map<std::string, std::string> clip_groups(const ReviewStore& store) {
  std::map<std::string, std::string> out;
  for (const auto& c : store.clips()) out[c.id] = c.group;
  return out;
}

std::string group_of(const std::map<std::string, std::string>& groups, const std::string& clip) {
  auto it = groups.find(clip);
  if (it != groups.end()) return it->second;
  return clip.substr(0, clip.find('/'));
}

std::string csv_field(const std::string& v) {
  if (v.find_first_of(",\"\r\n") == std::string::npos) return v;
  std::string out = "\"";
  for (char c : v) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

json parse_or_null(const std::string& text) {
  return text.empty() ? json(nullptr) : json::parse(text, nullptr, false);
}

// --- figures -------------------------------------------------------------------------------

// Likert 1..7 from red (1) to green (7), BGR.
cv::Scalar likert_colour(int v) {
  static const cv::Scalar colours[7] = {{43, 57, 192},   {60, 110, 230},  {90, 170, 245},
                                        {190, 190, 190}, {150, 200, 140}, {90, 160, 60},
                                        {40, 110, 30}};
  return colours[std::clamp(v, 1, 7) - 1];
}

void put_text(cv::Mat& img, const std::string& text, cv::Point at, double scale = 0.5,
              int thickness = 1) {
  cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(20, 20, 20), thickness,
              cv::LINE_AA);
}

void write_png(const std::filesystem::path& path, const cv::Mat& img) {
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".png", img, bytes)) {
    throw Error(path.string() + ": PNG encoding failed", ErrorKind::kFailure);
  }
  write_file_atomic(path, std::span<const std::uint8_t>(bytes));
}

// One 100 % stacked bar per participant; `counts[p][k]` is the number of answers in category k.
cv::Mat stacked_bars(const std::string& title, const std::vector<std::string>& participants,
                     const std::vector<std::vector<int>>& counts,
                     const std::vector<cv::Scalar>& colours,
                     const std::vector<std::string>& legend) {
  const int bar_w = 40, gap = 16, left = 60, top = 50, plot_h = 300;
  const int width =
      std::max(480, left + static_cast<int>(participants.size()) * (bar_w + gap) + 140);
  cv::Mat img(top + plot_h + 60, width, CV_8UC3, cv::Scalar(255, 255, 255));
  put_text(img, title, {10, 25}, 0.6, 2);
  for (int pct = 0; pct <= 100; pct += 25) {
    const int y = top + plot_h - plot_h * pct / 100;
    cv::line(img, {left - 5, y}, {left + static_cast<int>(participants.size()) * (bar_w + gap), y},
             cv::Scalar(220, 220, 220));
    put_text(img, std::to_string(pct) + "%", {10, y + 5}, 0.4);
  }
  for (std::size_t p = 0; p < participants.size(); ++p) {
    const int x = left + static_cast<int>(p) * (bar_w + gap);
    int total = 0;
    for (int c : counts[p]) total += c;
    double acc = 0.0;
    for (std::size_t k = 0; k < counts[p].size() && total > 0; ++k) {
      const double frac = static_cast<double>(counts[p][k]) / total;
      const int y0 = top + plot_h - static_cast<int>(std::lround(acc * plot_h));
      acc += frac;
      const int y1 = top + plot_h - static_cast<int>(std::lround(acc * plot_h));
      if (y0 > y1) cv::rectangle(img, {x, y1}, {x + bar_w, y0}, colours[k], cv::FILLED);
    }
    put_text(img, participants[p].substr(0, 6), {x, top + plot_h + 20}, 0.4);
  }
  const int lx = width - 120;
  for (std::size_t k = 0; k < legend.size(); ++k) {
    const int y = top + static_cast<int>(k) * 22;
    cv::rectangle(img, {lx, y}, {lx + 16, y + 16}, colours[k], cv::FILLED);
    put_text(img, legend[k], {lx + 22, y + 13}, 0.45);
  }
  return img;
}

cv::Mat scatter(const std::string& title, const std::map<std::pair<int, int>, int>& counts) {
  const int left = 60, top = 50, size = 360;
  cv::Mat img(top + size + 60, left + size + 30, CV_8UC3, cv::Scalar(255, 255, 255));
  put_text(img, title, {10, 25}, 0.55, 2);
  auto px = [&](int ease) { return left + (ease - 1) * size / 6; };
  auto py = [&](int freq) { return top + size - (freq - 1) * size / 6; };
  for (int v = 1; v <= 7; ++v) {
    cv::line(img, {px(v), top}, {px(v), top + size}, cv::Scalar(225, 225, 225));
    cv::line(img, {left, py(v)}, {left + size, py(v)}, cv::Scalar(225, 225, 225));
    put_text(img, std::to_string(v), {px(v) - 4, top + size + 20}, 0.45);
    put_text(img, std::to_string(v), {left - 20, py(v) + 5}, 0.45);
  }
  put_text(img, "ease (Q1)", {left + size / 2 - 40, top + size + 45}, 0.5);
  put_text(img, "freq", {5, top - 10}, 0.5);
  int max_count = 1;
  for (const auto& [k, c] : counts) max_count = std::max(max_count, c);
  // Answers are integers, so points coincide: the area of each circle shows how many.
  for (const auto& [k, c] : counts) {
    const int r = 3 + static_cast<int>(std::lround(18.0 * std::sqrt(double(c) / max_count)));
    cv::circle(img, {px(k.first), py(k.second)}, r, cv::Scalar(180, 110, 30), cv::FILLED,
               cv::LINE_AA);
  }
  return img;
}

std::string format_number(double v, int digits = 3) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

ordered_json score_entry(const ClipScore& s) {
  ordered_json e;
  e["id"] = s.id;
  e["group"] = s.group;
  e["path"] = s.path;
  e["ratings"] = s.ratings;
  if (s.ratings > 0) {
    e["mean_ease"] = std::round(s.mean_ease * 1e6) / 1e6;
    e["mean_frequency"] = std::round(s.mean_frequency * 1e6) / 1e6;
    e["score"] = std::round(s.score * 1e6) / 1e6;
  } else {
    e["mean_ease"] = nullptr;
    e["mean_frequency"] = nullptr;
    e["score"] = nullptr;
  }
  e["q3_yes_fraction"] =
      s.q3_answers > 0 ? json(std::round(1e6 * s.q3_yes / s.q3_answers) / 1e6) : json(nullptr);
  return e;
}

}  // namespace

json status_json(const ReviewStore& store) {
  const auto clips = store.clips();
  json out = json::array();
  for (const auto& p : store.participants()) {
    int answered = 0, partial = 0;
    for (const auto& r : store.ratings(p.id)) {
      if (r.complete()) {
        ++answered;
      } else {
        ++partial;
      }
    }
    out.push_back({{"name", p.name},
                   {"consent", !p.consent_at.empty()},
                   {"questionnaire", !store.questionnaire(p.id).empty()},
                   {"group_order", p.group_order},
                   {"answered", answered},
                   {"partially_answered", partial},
                   {"clips", clips.size()},
                   {"finished", !p.finished_at.empty()}});
  }
  return out;
}

std::string status_text(const ReviewStore& store) {
  const json status = status_json(store);
  std::ostringstream s;
  s << "participant  consent  answered/clips  finished  group order\n";
  for (const auto& p : status) {
    std::string order;
    for (const auto& g : p["group_order"])
      order += (order.empty() ? "" : ", ") + g.get<std::string>();
    char line[512];
    std::snprintf(line, sizeof line, "%-12s %-8s %5d/%-8d %-9s %s\n",
                  p["name"].get<std::string>().c_str(), p["consent"] ? "yes" : "no",
                  p["answered"].get<int>(), p["clips"].get<int>(), p["finished"] ? "yes" : "no",
                  order.empty() ? "(not started)" : order.c_str());
    s << line;
  }
  if (status.empty()) s << "(no participants yet: `wheelpose review invite --db ... --name P1`)\n";
  return s.str();
}

json export_json(const ReviewStore& store) {
  const auto groups = clip_groups(store);
  json participants = json::array();
  for (const auto& p : store.participants()) {
    json ratings = json::array();
    for (const auto& r : store.ratings(p.id)) {
      ratings.push_back({{"clip", r.clip_id},
                         {"group", group_of(groups, r.clip_id)},
                         {"q1", r.q1 ? json(*r.q1) : json(nullptr)},
                         {"q2", r.q2 ? json(*r.q2) : json(nullptr)},
                         {"q3", r.q3 ? json(*r.q3) : json(nullptr)},
                         {"updated_at", r.updated_at}});
    }
    participants.push_back({{"name", p.name},
                            {"created_at", p.created_at},
                            {"consent_at", p.consent_at},
                            {"finished_at", p.finished_at},
                            {"group_order", p.group_order},
                            {"questionnaire", parse_or_null(store.questionnaire(p.id))},
                            {"free_text", parse_or_null(store.free_text(p.id))},
                            {"ratings", ratings}});
  }
  return {{"format", "wheelpose.review_export"}, {"version", 1}, {"participants", participants}};
}

std::string export_csv(const ReviewStore& store) {
  const auto groups = clip_groups(store);
  std::string out = "participant,group,clip,q1,q2,q3,updated_at\r\n";
  for (const auto& p : store.participants()) {
    for (const auto& r : store.ratings(p.id)) {
      out += csv_field(p.name) + "," + csv_field(group_of(groups, r.clip_id)) + "," +
             csv_field(r.clip_id) + "," + (r.q1 ? std::to_string(*r.q1) : "") + "," +
             (r.q2 ? std::to_string(*r.q2) : "") + "," + (r.q3 ? (*r.q3 ? "yes" : "no") : "") +
             "," + r.updated_at + "\r\n";
    }
  }
  return out;
}

std::vector<ClipScore> score_clips(const ReviewStore& store) {
  std::map<std::string, ClipScore> by_id;
  for (const auto& c : store.clips()) by_id[c.id] = {c.id, c.group, c.path};
  for (const auto& r : store.ratings()) {
    auto it = by_id.find(r.clip_id);
    if (it == by_id.end()) continue;  // a clip no longer in the study
    ClipScore& s = it->second;
    if (r.q1 && r.q2) {
      ++s.ratings;
      s.mean_ease += *r.q1;
      s.mean_frequency += *r.q2;
    }
    if (r.q3) {
      ++s.q3_answers;
      s.q3_yes += *r.q3;
    }
  }
  std::vector<ClipScore> out;
  for (auto& [id, s] : by_id) {
    if (s.ratings > 0) {
      s.mean_ease /= s.ratings;
      s.mean_frequency /= s.ratings;
      s.score = s.mean_ease + s.mean_frequency;
    }
    out.push_back(s);
  }
  std::stable_sort(out.begin(), out.end(), [](const ClipScore& a, const ClipScore& b) {
    if ((a.ratings > 0) != (b.ratings > 0)) return a.ratings > 0;
    return a.score > b.score;
  });
  return out;
}

std::optional<double> pearson(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size() || x.size() < 2) return std::nullopt;
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= n;
  my /= n;
  double sxy = 0, sxx = 0, syy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  if (sxx <= 0 || syy <= 0) return std::nullopt;
  return sxy / std::sqrt(sxx * syy);
}

ordered_json filter_ranking(const ReviewStore& store, double drop_percent,
                            const std::vector<std::string>& groups) {
  if (!(drop_percent >= 0.0 && drop_percent < 100.0)) {
    throw Error("--drop-bottom: the percentage must be at least 0 and below 100, got " +
                format_number(drop_percent, 2));
  }
  const auto scores = score_clips(store);
  std::set<std::string> known_groups;
  for (const auto& s : scores) known_groups.insert(s.group);
  for (const auto& g : groups) {
    if (!known_groups.count(g))
      throw Error("--group: no clip group named '" + g + "' in the study");
  }
  std::vector<const ClipScore*> candidates;
  for (const auto& s : scores) {
    const bool in_groups =
        groups.empty() || std::find(groups.begin(), groups.end(), s.group) != groups.end();
    if (s.ratings > 0 && in_groups) candidates.push_back(&s);
  }
  // Lowest score first; equal scores drop the later id first so the choice is reproducible.
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const ClipScore* a, const ClipScore* b) {
                     if (a->score != b->score) return a->score < b->score;
                     return a->id > b->id;
                   });
  const auto drop_count = static_cast<std::size_t>(
      std::floor(static_cast<double>(candidates.size()) * drop_percent / 100.0 + 1e-9));
  std::set<std::string> dropped_ids;
  for (std::size_t i = 0; i < drop_count; ++i) dropped_ids.insert(candidates[i]->id);

  ordered_json kept = ordered_json::array(), dropped = ordered_json::array();
  for (const auto& s : scores) {
    (dropped_ids.count(s.id) ? dropped : kept).push_back(score_entry(s));
  }
  ordered_json doc;
  doc["format"] = "wheelpose.review_ranking";
  doc["version"] = 1;
  doc["score"] = "mean_ease + mean_frequency";
  doc["drop_bottom_percent"] = drop_percent;
  doc["filtered_groups"] = groups;
  doc["participants"] = store.participants().size();
  doc["rated_clips"] = candidates.size();
  doc["kept"] = std::move(kept);
  doc["dropped"] = std::move(dropped);
  return doc;
}

std::vector<std::filesystem::path> write_report(const ReviewStore& store,
                                                const std::filesystem::path& out_dir) {
  ensure_directory(out_dir);
  const auto groups_of = clip_groups(store);
  const auto participants = store.participants();
  const auto ratings = store.ratings();
  std::vector<std::string> groups;
  for (const auto& c : store.clips()) {
    if (std::find(groups.begin(), groups.end(), c.group) == groups.end()) groups.push_back(c.group);
  }
  std::vector<std::string> names;
  std::map<std::int64_t, std::size_t> index;
  for (const auto& p : participants) {
    index[p.id] = names.size();
    names.push_back(p.name);
  }
  std::vector<cv::Scalar> likert_colours;
  std::vector<std::string> likert_legend;
  for (int v = 1; v <= 7; ++v) {
    likert_colours.push_back(likert_colour(v));
    likert_legend.push_back(std::to_string(v));
  }
  likert_legend.front() += " (low)";
  likert_legend.back() += " (high)";

  std::vector<std::filesystem::path> written;
  std::ostringstream html;
  html << "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>WheelPose "
          "review report</title><style>body{font-family:sans-serif;max-width:70em;margin:auto;"
          "padding:1em}table{border-collapse:collapse}td,th{border:1px solid #999;padding:"
          "0.2em 0.5em}img{max-width:100%}</style></head><body>\n<h1>WheelPose review report</h1>\n"
       << "<p>" << participants.size() << " participants, " << ratings.size()
       << " rated clips (rows).</p>\n";
  for (std::size_t gi = 0; gi < groups.size(); ++gi) {
    const std::string& g = groups[gi];
    const std::string tag = "group" + std::to_string(gi + 1);
    std::vector<std::vector<int>> ease(names.size(), std::vector<int>(7, 0));
    std::vector<std::vector<int>> freq(names.size(), std::vector<int>(7, 0));
    std::vector<std::vector<int>> seen(names.size(), std::vector<int>(2, 0));
    std::map<std::pair<int, int>, int> pairs;
    std::vector<double> xs, ys;
    for (const auto& r : ratings) {
      if (group_of(groups_of, r.clip_id) != g) continue;
      const std::size_t p = index.at(r.participant_id);
      if (r.q1) ++ease[p][*r.q1 - 1];
      if (r.q2) ++freq[p][*r.q2 - 1];
      if (r.q3) ++seen[p][*r.q3 ? 0 : 1];
      if (r.q1 && r.q2) {
        ++pairs[{*r.q1, *r.q2}];
        xs.push_back(*r.q1);
        ys.push_back(*r.q2);
      }
    }
    const auto r = pearson(xs, ys);
    const std::string r_text = r ? "r = " + format_number(*r) : "r undefined";
    const std::vector<std::pair<std::string, cv::Mat>> figures = {
        {tag + "_ease.png",
         stacked_bars("Ease (Q1), " + g, names, ease, likert_colours, likert_legend)},
        {tag + "_frequency.png",
         stacked_bars("Frequency (Q2), " + g, names, freq, likert_colours, likert_legend)},
        {tag + "_scatter.png", scatter("Ease vs frequency, " + g + ": " + r_text +
                                           " (n=" + std::to_string(xs.size()) + ")",
                                       pairs)},
        {tag + "_seen.png",
         stacked_bars("Seen others do it (Q3), " + g, names, seen,
                      {cv::Scalar(90, 160, 60), cv::Scalar(60, 110, 230)}, {"yes", "no"})},
    };
    html << "<h2>Group " << html_escape(g) << "</h2>\n<p>Pearson correlation of ease and "
         << "frequency over " << xs.size() << " answers: " << html_escape(r_text) << "</p>\n";
    for (const auto& [file, img] : figures) {
      write_png(out_dir / file, img);
      written.push_back(out_dir / file);
      html << "<img src=\"" << file << "\" alt=\"" << html_escape(file) << "\">\n";
    }
  }
  html << "<h2>Ranking (mean ease + mean frequency)</h2>\n<table><tr><th>#</th><th>clip</th>"
          "<th>group</th><th>ratings</th><th>mean ease</th><th>mean frequency</th><th>score</th>"
          "<th>seen (yes)</th></tr>\n";
  int rank = 0;
  for (const auto& s : score_clips(store)) {
    html << "<tr><td>" << ++rank << "</td><td>" << html_escape(s.id) << "</td><td>"
         << html_escape(s.group) << "</td><td>" << s.ratings << "</td>";
    if (s.ratings > 0) {
      html << "<td>" << format_number(s.mean_ease, 2) << "</td><td>"
           << format_number(s.mean_frequency, 2) << "</td><td>" << format_number(s.score, 2)
           << "</td>";
    } else {
      html << "<td></td><td></td><td></td>";
    }
    html << "<td>" << s.q3_yes << "/" << s.q3_answers << "</td></tr>\n";
  }
  html << "</table>\n</body></html>\n";
  write_file_atomic(out_dir / "report.html", html.str());
  written.push_back(out_dir / "report.html");
  return written;
}

}  // namespace wheelpose::review
