#include "render/strata.h"

#include "core/random.h"

namespace wheelpose::render {
namespace {

constexpr int kLevels = 3;  // 8×8 blocks: a quadtree of 3 levels, 64 points
constexpr int kPoints = ScreenStrata::kBlock * ScreenStrata::kBlock;
static_assert(ScreenStrata::kBlock == 1 << kLevels);

constexpr std::uint32_t reverse_bits(std::uint32_t v) {
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
  v = ((v >> 8) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8);
  return (v >> 16) | (v << 16);
}

// Second Sobol dimension (generator matrix: Pascal's triangle mod 2); the first is
// reverse_bits. Together they are the (0,2)-sequence in base 2.
constexpr std::uint32_t sobol_second(std::uint32_t index) {
  std::uint32_t result = 0;
  for (std::uint32_t v = 1u << 31; index != 0; index >>= 1, v ^= v >> 1) {
    if (index & 1u) result ^= v;
  }
  return result;
}

template <std::uint32_t (*coordinate)(std::uint32_t)>
constexpr std::array<std::uint32_t, kPoints> first_points() {
  std::array<std::uint32_t, kPoints> points{};
  for (std::uint32_t i = 0; i < kPoints; ++i) points[i] = coordinate(i);
  return points;
}

}  // namespace

const std::array<std::uint32_t, kPoints> ScreenStrata::Block::sequence_u_ =
    first_points<reverse_bits>();
const std::array<std::uint32_t, kPoints> ScreenStrata::Block::sequence_v_ =
    first_points<sobol_second>();

ScreenStrata::ScreenStrata(std::uint64_t seed) : seed_hash_(StreamKey("strata").hash() ^ seed) {}

ScreenStrata::Block ScreenStrata::block(int x, int y, int sample) const {
  const auto bx = static_cast<std::uint64_t>(static_cast<std::uint32_t>(x) / kBlock);
  const auto by = static_cast<std::uint64_t>(static_cast<std::uint32_t>(y) / kBlock);
  const std::uint64_t hash =
      StreamKey::mix(seed_hash_ + bx * 0x9e3779b97f4a7c15ULL + by * 0xc2b2ae3d27d4eb4fULL +
                     static_cast<std::uint64_t>(sample) * 0x165667b19e3779f9ULL);
  Block b;
  // Two random bits per quadtree node (level l, node (nx, ny) of side 2^(l+1)) flip the
  // base-4 digit l of its children's indices: the order of the four children differs per node.
  std::array<std::array<std::uint32_t, kPoints>, kLevels> flips{};
  for (int l = 0; l < kLevels; ++l) {
    const int nodes = kBlock >> (l + 1);
    for (int n = 0; n < nodes * nodes; ++n) {
      flips[l][n] = static_cast<std::uint32_t>(
          StreamKey::mix(hash +
                         static_cast<std::uint64_t>(l * kPoints + n + 1) * 0xd6e8feb86659fd93ULL) &
          3u);
    }
  }
  for (int py = 0; py < kBlock; ++py) {
    for (int px = 0; px < kBlock; ++px) {
      std::uint32_t index = 0;
      for (int l = 0; l < kLevels; ++l) {
        const std::uint32_t child =
            static_cast<std::uint32_t>(((px >> l) & 1) | (((py >> l) & 1) << 1));
        const int nodes = kBlock >> (l + 1);
        const int node = (py >> (l + 1)) * nodes + (px >> (l + 1));
        index |= (child ^ flips[l][node]) << (2 * l);
      }
      b.index_[py * kBlock + px] = static_cast<std::uint8_t>(index);
    }
  }
  for (int pair = 0; pair < kPairs; ++pair) {
    const std::uint64_t h =
        StreamKey::mix(hash + static_cast<std::uint64_t>(pair + 1) * 0x94d049bb133111ebULL);
    b.order_[pair] = static_cast<std::uint32_t>(StreamKey::mix(h)) & (kPoints - 1);
    b.shift_u_[pair] = static_cast<std::uint32_t>(h >> 32);
    b.shift_v_[pair] = static_cast<std::uint32_t>(h);
  }
  return b;
}

}  // namespace wheelpose::render
