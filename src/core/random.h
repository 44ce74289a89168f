#pragma once
// Seeded random streams. A stream is a pure function of (seed, keys...): there is no global RNG,
// so adding a consumer never changes the numbers another consumer sees, and any frame can be
// regenerated alone. The generator and the variate transforms are written here (not <random>'s
// distributions) because libstdc++ and libc++ produce different normal/uniform variates, and our
// outputs must be byte-identical everywhere.

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>

namespace wheelpose {

// One key of a stream: a number (frame index, draw index) or a name (randomizer, clip).
class StreamKey {
 public:
  StreamKey(std::uint64_t value) : hash_(mix(value ^ 0x9e3779b97f4a7c15ULL)) {}  // NOLINT
  StreamKey(int value)
      : StreamKey(static_cast<std::uint64_t>(static_cast<std::int64_t>(value))) {}  // NOLINT
  StreamKey(std::string_view text);                                                 // NOLINT
  StreamKey(const char* text) : StreamKey(std::string_view(text)) {}                // NOLINT
  StreamKey(const std::string& text) : StreamKey(std::string_view(text)) {}         // NOLINT
  std::uint64_t hash() const { return hash_; }
  // SplitMix64 finaliser: a bijective avalanche on 64 bits. Inline: pixel sampling and
  // procedural textures call it millions of times per frame.
  static std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t hash_;
};

class RandomStream {
 public:
  RandomStream(std::uint64_t seed, std::initializer_list<StreamKey> keys);

  // A stream derived from this one's identity (not its position) and further keys.
  RandomStream child(std::initializer_list<StreamKey> keys) const;

  // Inline: the renderer draws millions per frame.
  std::uint64_t next_u64() {
    state_ += 0x9e3779b97f4a7c15ULL;
    return StreamKey::mix(state_);
  }
  // Uniform in [0, 1) with 53 random bits.
  double uniform01() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
  // Uniform in [lo, hi).
  double uniform(double lo, double hi);
  // Uniform integer in [lo, hi] (inclusive), unbiased.
  std::int64_t uniform_int(std::int64_t lo, std::int64_t hi);
  // Standard normal by the Box–Muller transform (both variates used).
  double normal(double mean, double stddev);
  bool bernoulli(double p);

  // Where the stream stands, in 8 bytes, to store per pixel and continue from later with
  // seek() on a stream of the same identity. A spare normal variate is not part of it.
  std::uint64_t position() const { return state_; }
  void seek(std::uint64_t position) {
    state_ = position;
    has_spare_normal_ = false;
  }

 private:
  explicit RandomStream(std::uint64_t identity) : identity_(identity), state_(identity) {}
  std::uint64_t identity_;
  std::uint64_t state_;
  bool has_spare_normal_ = false;
  double spare_normal_ = 0.0;
};

}  // namespace wheelpose
