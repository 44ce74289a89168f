#pragma once
// How eval's JSON readers reject input: "<file>: <where>: <what>", one line naming the file, the
// entry or field, and the problem.

#include <string>

#include "core/error.h"

namespace wheelpose::eval {

[[noreturn]] inline void fail(const std::string& source, const std::string& where,
                              const std::string& what) {
  throw Error(source + ": " + where + ": " + what);
}

}  // namespace wheelpose::eval
