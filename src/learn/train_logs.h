#pragma once
// The CSV logs of a training run: train_log.csv (one row per step) and val_log.csv (one row
// per validation), and the prefix of each a resumed run keeps. Internal to the learn layer.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "learn/trainer.h"

namespace wheelpose::learn {

extern const char* const kTrainLogHeader;
std::string train_log_row(const StepReport& r);

extern const char* const kValLogHeader;
std::string val_log_row(const ValidationRow& r);
// The validation rows of a val_log.csv text.
std::vector<ValidationRow> parse_val_log(const std::string& text);
// A validation row as best.json holds it.
nlohmann::json val_json(const ValidationRow& r);

// A CSV log's header and its rows up to `step` (a killed run may have logged past its last
// checkpoint; those steps run again); just the header if the file does not exist.
std::string log_prefix(const std::filesystem::path& path, int step, const std::string& header);

}  // namespace wheelpose::learn
