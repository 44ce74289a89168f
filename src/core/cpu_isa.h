#pragma once
// Which x86-64 instruction sets the renderer may use. WheelPose needs SSE4.2 at least; Embree's
// kernels and our AVX2 loops use AVX, AVX2 and AVX-512 when the CPU has them. The environment
// variable WHEELPOSE_EMBREE_CONFIG (Embree's device config, e.g. "isa=avx2,threads=4") can cap
// the ISA with isa=..., which is how the tests run every ISA of a machine on that machine.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace wheelpose {

// In increasing order; the names are Embree's.
enum class Isa { kSse42 = 0, kAvx = 1, kAvx2 = 2, kAvx512 = 3 };

const char* isa_name(Isa isa);
std::optional<Isa> parse_isa(std::string_view name);

// True when this CPU has every feature Embree's kernels for `isa` use (AVX2: also FMA, BMI1/2;
// AVX-512: the Skylake-server set F, CD, DQ, BW, VL).
bool cpu_has(Isa isa);

// The ISAs this CPU runs, lowest first (empty when it lacks SSE4.2).
std::vector<Isa> isas_on_this_cpu();

// WHEELPOSE_EMBREE_CONFIG's text ("" when unset).
std::string embree_config_text();

// The ISA an Embree config string caps Embree at (isa= or max_isa=), if any. Throws Error
// naming the variable for an ISA name or a setting Embree does not know (Embree itself ignores
// both silently).
std::optional<Isa> isa_in_embree_config(std::string_view config);

// The highest ISA this process may use: the CPU's best, capped by isa= in
// WHEELPOSE_EMBREE_CONFIG. Throws Error when the CPU lacks SSE4.2 or the config asks for an ISA
// this CPU does not have. Read once and cached.
Isa active_isa();

// Empty when the process can render on this CPU with this environment, else why not (one line).
std::string isa_problem();

}  // namespace wheelpose
