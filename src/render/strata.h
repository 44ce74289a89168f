#pragma once
// Screen-space stratification of light samples. The pixels of each aligned 8×8 block are
// ordered along a quadtree and take consecutive points of the 2-D Sobol (0,2)-sequence, so every
// aligned 2^k × 2^k square of pixels covers the unit square with one point in each of 4^k
// strata, and the lighting smoothing averages stratified samples instead of independent ones:
// less noise for the same rays. Randomised so that no pattern repeats (after Ahmed & Wonka
// 2020, "Screen-space blue-noise diffusion of Monte Carlo sampling error via hierarchical
// ordering of pixels"):
// - each quadtree node orders its four children at random (random digit flips of the index);
// - each dimension pair XORs the index with its own random number (another valid order);
// - a random digital shift (XOR) per block, sample and pair makes each pixel's point uniform on
//   [0, 1)², so estimates stay unbiased, and keeps the net structure.
#include <array>
#include <cstdint>

namespace wheelpose::render {

class ScreenStrata {
 public:
  static constexpr int kBlock = 8;  // pixels per block side
  static constexpr int kPairs = 3;  // dimension pairs (one per use: sun, light choice, sky)

  // One sample's points for the pixels of one block.
  class Block {
   public:
    // The point of dimension pair `pair` for pixel (x, y), which must lie in this block.
    std::array<float, 2> point(int x, int y, int pair) const {
      const std::uint32_t i =
          index_[(y & (kBlock - 1)) * kBlock + (x & (kBlock - 1))] ^ order_[pair];
      return {unit(sequence_u_[i] ^ shift_u_[pair]), unit(sequence_v_[i] ^ shift_v_[pair])};
    }

   private:
    friend class ScreenStrata;
    std::array<std::uint8_t, kBlock * kBlock> index_{};  // pixel → place in the order
    std::array<std::uint32_t, kPairs> order_{}, shift_u_{}, shift_v_{};
    static float unit(std::uint32_t bits) {
      return static_cast<float>(bits >> 8) * (1.0f / 16777216.0f);
    }
    // The first kBlock² points of the (0,2)-sequence, as 32-bit fractions.
    static const std::array<std::uint32_t, kBlock * kBlock> sequence_u_, sequence_v_;
  };

  explicit ScreenStrata(std::uint64_t seed);
  // The block holding pixel (x, y), for sample `sample`.
  Block block(int x, int y, int sample) const;

 private:
  std::uint64_t seed_hash_;
};

}  // namespace wheelpose::render
