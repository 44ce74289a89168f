#include "generate/runner.h"

#include <gtest/gtest.h>

#include <string>

#include "core/error.h"

namespace wheelpose::generate {
namespace {

TEST(Runner, ShardsPartitionTheFramesInOrder) {
  for (std::int64_t frames : {1, 7, 100, 1001}) {
    for (int count : {1, 2, 3, 8}) {
      std::int64_t next = 0;
      for (int i = 0; i < count; ++i) {
        const auto [first, end] = shard_range(frames, i, count);
        EXPECT_EQ(first, next) << frames << " " << i << "/" << count;
        EXPECT_LE(end - first, frames / count + 1);
        EXPECT_GE(end - first, frames / count);
        next = end;
      }
      EXPECT_EQ(next, frames);
    }
  }
}

TEST(Runner, OptionsCheckNamesTheBadOption) {
  RunOptions ok;
  ok.out = "out";
  EXPECT_NO_THROW(ok.check());
  auto message = [](RunOptions o) {
    try {
      o.check();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  RunOptions o = ok;
  o.frames = 0;
  EXPECT_NE(message(o).find("--frames"), std::string::npos);
  o = ok;
  o.shard_index = 2;
  o.shard_count = 2;
  EXPECT_NE(message(o).find("--shard"), std::string::npos);
  o = ok;
  o.format = "bmp";
  EXPECT_NE(message(o).find("--format"), std::string::npos);
  o = ok;
  o.out.clear();
  EXPECT_NE(message(o).find("--out"), std::string::npos);
  o = ok;
  o.threads = -1;
  EXPECT_NE(message(o).find("--threads"), std::string::npos);
}

}  // namespace
}  // namespace wheelpose::generate
