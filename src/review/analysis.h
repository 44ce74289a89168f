#pragma once
// Reading a review study back out: progress, raw export, per-clip scores, the ranking the
// generator filters on, and the HTML/PNG report (paper Figure "HumanEvalStat" a–h).

#include <filesystem>
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

// Writes report.html and the PNG figures into `out_dir`; returns the files written.
std::vector<std::filesystem::path> write_report(const ReviewStore& store,
                                                const std::filesystem::path& out_dir);

}  // namespace wheelpose::review
