#pragma once
// How the JSON readers of labels and results (core's keypoint templates, eval's COCO files)
// reject input: "<file>: <where>: <what>", one line naming the file, the
// entry or field, and the problem.

#include <string>

#include "core/error.h"

namespace wheelpose {

[[noreturn]] inline void fail(const std::string& source, const std::string& where,
                              const std::string& what) {
  throw Error(source + ": " + where + ": " + what);
}

}  // namespace wheelpose
