#include "core/random.h"

#include <cmath>
#include <numbers>

namespace wheelpose {

StreamKey::StreamKey(std::string_view text) {
  // FNV-1a then an avalanche, so names and numbers land in unrelated places.
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  hash_ = mix(h ^ 0x5bd1e9955bd1e995ULL);
}

namespace {
std::uint64_t combine(std::uint64_t identity, std::initializer_list<StreamKey> keys) {
  for (const StreamKey& key : keys) identity = StreamKey::mix(identity * 31 + key.hash());
  return identity;
}
}  // namespace

RandomStream::RandomStream(std::uint64_t seed, std::initializer_list<StreamKey> keys)
    : RandomStream(combine(StreamKey::mix(seed + 0x632be59bd9b4e019ULL), keys)) {}

RandomStream RandomStream::child(std::initializer_list<StreamKey> keys) const {
  return RandomStream(combine(identity_, keys));
}

double RandomStream::uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }

std::int64_t RandomStream::uniform_int(std::int64_t lo, std::int64_t hi) {
  const std::uint64_t span = static_cast<std::uint64_t>(hi - lo) + 1;
  if (span == 0) return static_cast<std::int64_t>(next_u64());  // full 64-bit range
  const std::uint64_t limit = UINT64_MAX - UINT64_MAX % span;
  std::uint64_t draw = next_u64();
  while (draw >= limit) draw = next_u64();
  return lo + static_cast<std::int64_t>(draw % span);
}

double RandomStream::normal(double mean, double stddev) {
  if (has_spare_normal_) {
    has_spare_normal_ = false;
    return mean + stddev * spare_normal_;
  }
  const double u1 = 1.0 - uniform01();  // (0, 1], so the log is finite
  const double u2 = uniform01();
  const double radius = std::sqrt(-2.0 * std::log(u1));
  const double angle = 2.0 * std::numbers::pi * u2;
  spare_normal_ = radius * std::sin(angle);
  has_spare_normal_ = true;
  return mean + stddev * radius * std::cos(angle);
}

bool RandomStream::bernoulli(double p) { return uniform01() < p; }

}  // namespace wheelpose
