#include "learn/train_logs.h"

#include <sstream>

#include "core/atomic_file.h"

namespace wheelpose::learn {
namespace fs = std::filesystem;

const char* const kTrainLogHeader =
    "step,learning_rate,loss,centre,keypoint_heatmap,keypoint_regression,keypoint_offset,"
    "box_scale,box_offset,distill,images_per_second\n";

std::string train_log_row(const StepReport& r) {
  std::ostringstream row;
  row.precision(6);
  row << r.step << ',' << r.learning_rate << ',' << r.loss << ',' << r.centre << ','
      << r.keypoint_heatmap << ',' << r.keypoint_regression << ',' << r.keypoint_offset << ','
      << r.box_scale << ',' << r.box_offset << ',' << r.distill << ',' << r.images_per_second << '\n';
  return row.str();
}

const char* const kValLogHeader = "step,keypoint_ap,keypoint_ap50,keypoint_ar,box_ap,box_ap50\n";

std::string val_log_row(const ValidationRow& r) {
  std::ostringstream row;
  row.precision(6);
  row << r.step << ',' << r.keypoint_ap << ',' << r.keypoint_ap50 << ',' << r.keypoint_ar << ','
      << r.box_ap << ',' << r.box_ap50 << '\n';
  return row.str();
}

std::vector<ValidationRow> parse_val_log(const std::string& text) {
  std::vector<ValidationRow> rows;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::istringstream fields(line);
    ValidationRow r;
    char comma = 0;
    fields >> r.step >> comma >> r.keypoint_ap >> comma >> r.keypoint_ap50 >> comma >>
        r.keypoint_ar >> comma >> r.box_ap >> comma >> r.box_ap50;
    rows.push_back(r);
  }
  return rows;
}

nlohmann::json val_json(const ValidationRow& r) {
  return {{"step", r.step},
          {"keypoint_ap", r.keypoint_ap},
          {"keypoint_ap50", r.keypoint_ap50},
          {"keypoint_ar", r.keypoint_ar},
          {"box_ap", r.box_ap},
          {"box_ap50", r.box_ap50}};
}

std::string log_prefix(const fs::path& path, int step, const std::string& header) {
  std::string kept = header;
  if (!fs::exists(path)) return kept;
  std::istringstream in(read_file(path));
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (std::stoi(line.substr(0, line.find(','))) > step) break;
    kept += line + '\n';
  }
  return kept;
}

}  // namespace wheelpose::learn
