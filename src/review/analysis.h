#pragma once
// Reading a review study back out: progress, raw export, per-clip scores, per-group answer
// tallies and the ranking the generator filters on. report.h draws and writes them.

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "review/store.h"

namespace wheelpose::review {

// Progress of every participant: answered (all three questions) / total clips, consent, finished.
nlohmann::json status_json(const ReviewStore& store);
std::string status_text(const ReviewStore& store);

// Every participant's questionnaire, free text and ratings.
nlohmann::json export_json(const ReviewStore& store);
// One row per rating: participant,group,clip,q1,q2,q3,updated_at (RFC 4180 quoting).
std::string export_csv(const ReviewStore& store);

struct ClipScore {
  std::string id;
  std::string group;
  std::string path;
  int ratings = 0;  // participants who answered both Q1 and Q2
  double mean_ease = 0.0;
  double mean_frequency = 0.0;
  double score = 0.0;  // mean_ease + mean_frequency
  int q3_yes = 0;
  int q3_answers = 0;
};

// Scores of every registered clip, best first (score descending, then id); clips nobody rated
// come last with ratings == 0.
std::vector<ClipScore> score_clips(const ReviewStore& store);

// Pearson correlation; nullopt when fewer than two points or a variable is constant.
std::optional<double> pearson(const std::vector<double>& x, const std::vector<double>& y);

// The ranking.json document: drops the lowest-scoring floor(n * percent / 100) rated clips
// (among `groups` only when non-empty) and lists the kept ones. Throws Error on a bad percent.
nlohmann::ordered_json filter_ranking(const ReviewStore& store, double drop_percent,
                                      const std::vector<std::string>& groups);

// One clip group's answers (paper Figure "HumanEvalStat"): per participant (store order) the
// count of each answer, and the (ease, frequency) pairs of answers with both.
struct GroupAnswers {
  std::string group;
  std::vector<std::vector<int>> ease, frequency;      // [participant][answer - 1], answers 1..7
  std::vector<std::vector<int>> seen;                 // [participant][0 = yes, 1 = no]
  std::map<std::pair<int, int>, int> pairs;           // (ease, frequency) -> answers
  std::vector<double> ease_values, frequency_values;  // the pairs, one entry per answer
};
// Every clip group, in the order their first clips were registered.
std::vector<GroupAnswers> group_answers(const ReviewStore& store);

// `v` with `digits` decimals ("0.775").
std::string format_number(double v, int digits = 3);

}  // namespace wheelpose::review
