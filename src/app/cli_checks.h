#pragma once
// CLI11 validators whose messages say what was given and what is wanted, in our words: CLI11's
// own Range calls "abc" "not in range 0.000000 to 1.000000" and reads "" as 0.

#include <CLI/CLI.hpp>
#include <optional>
#include <string_view>

namespace wheelpose::app {

// The whole of `text` as a finite number (from_chars: no leading space, sign '+' or trailing
// bytes), or nothing.
std::optional<double> parse_number(std::string_view text);

// A number from `low` to `high`: "'abc' is not a number", "1.5 is outside [0, 1]".
CLI::Validator number_from(double low, double high);

// A model input side (predict --size, train --input-size and --val-size): a whole multiple of
// 32 from `low` to learn::kMaxInputSide.
CLI::Validator input_side(int low = 32);

}  // namespace wheelpose::app
