#include "core/cpu_isa.h"

#include <algorithm>
#include <cstdlib>

#include "core/cpu_clones.h"
#include "core/error.h"

namespace wheelpose {
namespace {

constexpr const char* kConfigVariable = "WHEELPOSE_EMBREE_CONFIG";

// The ISA Embree names by each config value (Embree 3 also accepts these aliases).
struct IsaName {
  std::string_view name;
  Isa isa;
};
constexpr IsaName kIsaNames[] = {
    {"sse4.2", Isa::kSse42},  {"avx", Isa::kAvx},          {"avx2", Isa::kAvx2},
    {"avx512", Isa::kAvx512}, {"avx512skx", Isa::kAvx512},
};

// The settings Embree 3's rtcNewDevice reads (its documentation, "rtcNewDevice").
constexpr std::string_view kEmbreeKeys[] = {"threads",
                                            "user_threads",
                                            "set_affinity",
                                            "start_threads",
                                            "isa",
                                            "max_isa",
                                            "hugepages",
                                            "enable_selockmemoryprivilege",
                                            "verbose",
                                            "frequency_level",
                                            "tessellation_cache_size"};
constexpr const char* kEmbreeKeyList =
    "threads, user_threads, set_affinity, start_threads, isa, max_isa, hugepages, "
    "enable_selockmemoryprivilege, verbose, frequency_level, tessellation_cache_size";

bool is_embree_key(std::string_view key) {
  for (std::string_view k : kEmbreeKeys) {
    if (k == key) return true;
  }
  return false;
}

std::string trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t");
  return std::string(s.substr(first, last - first + 1));
}

}  // namespace

const char* isa_name(Isa isa) {
  switch (isa) {
    case Isa::kSse42:
      return "sse4.2";
    case Isa::kAvx:
      return "avx";
    case Isa::kAvx2:
      return "avx2";
    case Isa::kAvx512:
      return "avx512";
  }
  return "?";
}

std::optional<Isa> parse_isa(std::string_view name) {
  for (const IsaName& entry : kIsaNames) {
    if (entry.name == name) return entry.isa;
  }
  return std::nullopt;
}

bool cpu_has(Isa isa) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();
  const bool sse42 = __builtin_cpu_supports("sse4.2") && __builtin_cpu_supports("ssse3");
  const bool avx = sse42 && __builtin_cpu_supports("avx");
  const bool avx2 = avx && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                    __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2");
  const bool avx512 = avx2 && __builtin_cpu_supports("avx512f") &&
                      __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512dq") &&
                      __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl");
  switch (isa) {
    case Isa::kSse42:
      return sse42;
    case Isa::kAvx:
      return avx;
    case Isa::kAvx2:
      return avx2;
    case Isa::kAvx512:
      return avx512;
  }
  return false;
#else
  (void)isa;
  return false;
#endif
}

std::vector<Isa> isas_on_this_cpu() {
  std::vector<Isa> out;
  for (Isa isa : {Isa::kSse42, Isa::kAvx, Isa::kAvx2, Isa::kAvx512}) {
    if (cpu_has(isa)) out.push_back(isa);
  }
  return out;
}

std::string embree_config_text() {
  const char* text = std::getenv(kConfigVariable);
  return text ? std::string(text) : std::string();
}

std::optional<Isa> isa_in_embree_config(std::string_view config) {
  std::optional<Isa> found;
  std::size_t start = 0;
  while (start <= config.size()) {
    const std::size_t comma = std::min(config.find(',', start), config.size());
    const std::string_view item = config.substr(start, comma - start);
    start = comma + 1;
    if (trim(item).empty()) continue;
    const std::size_t eq = item.find('=');
    const std::string key = trim(item.substr(0, eq));
    if (eq == std::string_view::npos || !is_embree_key(key)) {
      // Embree ignores what it does not know: a typo would silently do nothing.
      throw Error(std::string(kConfigVariable) + ": '" + trim(item) +
                  "' is not an Embree setting (key=value with key one of " + kEmbreeKeyList + ")");
    }
    if (key != "isa" && key != "max_isa") continue;
    const std::string value = trim(item.substr(eq + 1));
    found = parse_isa(value);
    if (!found) {
      throw Error(std::string(kConfigVariable) + ": unknown isa '" + value +
                  "' (use sse4.2, avx, avx2 or avx512)");
    }
  }
  return found;
}

std::string isa_problem() {
  if (!cpu_has(Isa::kSse42)) {
    return "this CPU lacks SSE4.2; WheelPose renders on x86-64 CPUs with SSE4.2 at least";
  }
  const std::optional<Isa> cap = isa_in_embree_config(embree_config_text());
  if (cap && !cpu_has(*cap)) {
    return std::string(kConfigVariable) + ": isa=" + isa_name(*cap) +
           " but this CPU does not have it (it has up to " + isa_name(isas_on_this_cpu().back()) +
           ")";
  }
  return {};
}

Isa active_isa() {
  static const Isa active = [] {
    if (std::string problem = isa_problem(); !problem.empty()) throw Error(problem);
    const Isa best = isas_on_this_cpu().back();
    const std::optional<Isa> cap = isa_in_embree_config(embree_config_text());
    return cap && *cap < best ? *cap : best;
  }();
  return active;
}

bool use_avx2_loops() noexcept {
  static const bool avx2 = [] {
    try {
      return active_isa() >= Isa::kAvx2;
    } catch (const Error&) {
      return false;
    }
  }();
  return avx2;
}

}  // namespace wheelpose
