#include "core/cpu_isa.h"

#include <gtest/gtest.h>

#include "core/cpu_clones.h"
#include "core/error.h"

namespace wheelpose {
namespace {

TEST(CpuIsa, NamesRoundTrip) {
  for (Isa isa : {Isa::kSse42, Isa::kAvx, Isa::kAvx2, Isa::kAvx512}) {
    ASSERT_TRUE(parse_isa(isa_name(isa)).has_value()) << isa_name(isa);
    EXPECT_EQ(*parse_isa(isa_name(isa)), isa);
  }
  EXPECT_EQ(parse_isa("avx512skx"), Isa::kAvx512);
  EXPECT_FALSE(parse_isa("sse2").has_value());  // below what WheelPose supports
  EXPECT_FALSE(parse_isa("AVX2").has_value());
}

TEST(CpuIsa, ReadsTheIsaFromAnEmbreeConfig) {
  EXPECT_FALSE(isa_in_embree_config("").has_value());
  EXPECT_FALSE(isa_in_embree_config("threads=2,verbose=1").has_value());
  EXPECT_EQ(isa_in_embree_config("isa=sse4.2"), Isa::kSse42);
  EXPECT_EQ(isa_in_embree_config("threads=2, isa = avx2 ,verbose=0"), Isa::kAvx2);
  EXPECT_EQ(isa_in_embree_config("max_isa=avx"), Isa::kAvx);
}

TEST(CpuIsa, RefusesWhatEmbreeWouldIgnore) {
  for (const char* bad : {"isa=avx3", "isa=", "isaa=avx2", "threads", "thread=2"}) {
    try {
      (void)isa_in_embree_config(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("WHEELPOSE_EMBREE_CONFIG"), std::string::npos)
          << e.what();
      EXPECT_EQ(e.exit_code(), 2);
    }
  }
}

TEST(CpuIsa, TheCpuListIsOrderedAndNested) {
  const std::vector<Isa> isas = isas_on_this_cpu();
  // Every x86-64 machine this project runs on has SSE4.2; the list is a prefix of the ladder.
  ASSERT_FALSE(isas.empty());
  for (std::size_t i = 0; i < isas.size(); ++i) {
    EXPECT_EQ(static_cast<int>(isas[i]), static_cast<int>(i));
    EXPECT_TRUE(cpu_has(isas[i]));
  }
  if (isas.size() < 4) {
    EXPECT_FALSE(cpu_has(static_cast<Isa>(isas.size())));
  }
}

TEST(CpuIsa, TheActiveIsaIsTheCpusBestUnlessCapped) {
  ASSERT_TRUE(isa_problem().empty()) << isa_problem();
  const std::optional<Isa> cap = isa_in_embree_config(embree_config_text());
  const Isa best = isas_on_this_cpu().back();
  EXPECT_EQ(active_isa(), cap ? std::min(*cap, best) : best);
  EXPECT_EQ(use_avx2_loops(), active_isa() >= Isa::kAvx2);
}

}  // namespace
}  // namespace wheelpose
