#include "review/analysis.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"

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

std::string format_number(double v, int digits) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

std::vector<GroupAnswers> group_answers(const ReviewStore& store) {
  const auto groups_of = clip_groups(store);
  const auto participants = store.participants();
  std::map<std::int64_t, std::size_t> index;
  for (const auto& p : participants) index.emplace(p.id, index.size());
  std::vector<GroupAnswers> out;
  for (const auto& c : store.clips()) {
    if (std::none_of(out.begin(), out.end(),
                     [&](const GroupAnswers& g) { return g.group == c.group; })) {
      GroupAnswers& g = out.emplace_back();
      g.group = c.group;
      g.ease.assign(participants.size(), std::vector<int>(7, 0));
      g.frequency.assign(participants.size(), std::vector<int>(7, 0));
      g.seen.assign(participants.size(), std::vector<int>(2, 0));
    }
  }
  for (const auto& r : store.ratings()) {
    const std::string group = group_of(groups_of, r.clip_id);
    auto g = std::find_if(out.begin(), out.end(),
                          [&](const GroupAnswers& a) { return a.group == group; });
    if (g == out.end()) continue;
    const std::size_t p = index.at(r.participant_id);
    if (r.q1) ++g->ease[p][*r.q1 - 1];
    if (r.q2) ++g->frequency[p][*r.q2 - 1];
    if (r.q3) ++g->seen[p][*r.q3 ? 0 : 1];
    if (r.q1 && r.q2) {
      ++g->pairs[{*r.q1, *r.q2}];
      g->ease_values.push_back(*r.q1);
      g->frequency_values.push_back(*r.q2);
    }
  }
  return out;
}

}  // namespace wheelpose::review
