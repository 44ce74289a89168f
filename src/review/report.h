#pragma once
// The review study's report: per clip group the answer figures (paper Figure "HumanEvalStat"
// a–h, PNG) and report.html with the Pearson correlations and the clip ranking.

#include <filesystem>
#include <vector>

#include "review/store.h"

namespace wheelpose::review {

// Writes report.html and the PNG figures into `out_dir`; returns the files written.
std::vector<std::filesystem::path> write_report(const ReviewStore& store,
                                                const std::filesystem::path& out_dir);

}  // namespace wheelpose::review
