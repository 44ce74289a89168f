#pragma once
// The statistics report of `wheelpose stats`: figures (PLplot, PNG and SVG), stats.json and an
// HTML page over one dataset and, optionally, a reference beside it. Computing is stats.h's.

#include <filesystem>
#include <string>
#include <vector>

#include "dataset/stats.h"

namespace wheelpose::dataset {

// Writes out_dir/stats.json, out_dir/index.html and each figure as .png and .svg (PLplot).
// datasets[0] is the dataset, datasets[1] (optional) the reference shown beside it.
// Returns the figure names.
std::vector<std::string> write_stats_report(const std::vector<DatasetStats>& datasets,
                                            const std::filesystem::path& out_dir);

}  // namespace wheelpose::dataset
