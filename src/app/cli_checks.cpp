#include "app/cli_checks.h"

#include <charconv>
#include <cmath>
#include <string>

#include "core/text_escape.h"
#include "learn/pose_predictor.h"

namespace wheelpose::app {
namespace {

template <typename T>
bool parse_whole(const std::string& text, T& value) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return !text.empty() && ec == std::errc() && end == text.data() + text.size();
}

std::string number_text(double v) {
  std::string text = std::to_string(v);
  text.erase(text.find_last_not_of('0') + 1);
  if (text.back() == '.') text.pop_back();
  return text;
}

}  // namespace

std::optional<double> parse_number(std::string_view text) {
  double value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() ||
      !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

CLI::Validator number_from(double low, double high) {
  return CLI::Validator(
      [low, high](std::string& text) -> std::string {
        const std::optional<double> value = parse_number(text);
        if (!value) return "'" + escape_bytes(text) + "' is not a number";
        if (*value < low || *value > high) {
          return text + " is outside [" + number_text(low) + ", " + number_text(high) + "]";
        }
        return "";
      },
      "[" + number_text(low) + ", " + number_text(high) + "]");
}

CLI::Validator input_side(int low) {
  return CLI::Validator(
      [low](std::string& text) -> std::string {
        int value = 0;
        const std::string range =
            " from " + std::to_string(low) + " to " + std::to_string(learn::kMaxInputSide);
        if (!parse_whole(text, value)) {
          return "'" + escape_bytes(text) + "' is not a whole number (a multiple of 32" + range +
                 ")";
        }
        if (value < low || value > learn::kMaxInputSide || value % 32 != 0) {
          return text + " is not a multiple of 32" + range;
        }
        return "";
      },
      "x32");
}

}  // namespace wheelpose::app
