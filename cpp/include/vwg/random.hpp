// Seeded random numbers whose sequence is fixed by this code alone (std:: distributions differ
// between standard libraries, which would break "same seed, same trace" across machines).
#pragma once

#include <cmath>
#include <cstdint>

#include "vwg/hash.hpp"
#include "vwg/state.hpp"

namespace vwg {

/// xoshiro256** (Blackman & Vigna), seeded through SplitMix64.
class Rng {
 public:
  explicit Rng(std::uint64_t seed = 0) { reseed(seed); }

  void reseed(std::uint64_t seed) {
    has_spare_ = false;
    for (auto& word : s_) {
      seed += 0x9E3779B97F4A7C15ULL;
      word = mix64(seed);
    }
  }

  std::uint64_t next_u64() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n), n > 0 (Lemire's multiply-shift; the bias is below 2^-64 * n).
  std::uint64_t below(std::uint64_t n) {
    __extension__ using u128 = unsigned __int128;  // GCC and Clang; __extension__ keeps -Wpedantic quiet
    return static_cast<std::uint64_t>((static_cast<u128>(next_u64()) * n) >> 64);
  }
  /// Standard normal by Marsaglia's polar method: a pair of values from a point drawn uniformly
  /// in the unit disc, the second kept for the next call. No sine or cosine, one logarithm a pair:
  /// a crowd's lasers draw one a beam, and Box-Muller (a logarithm and a cosine a value) was a
  /// few percent of their frame.
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u, v, s;
    do {
      u = 2.0 * uniform() - 1.0;
      v = 2.0 * uniform() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double scale = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = v * scale;
    has_spare_ = true;
    return u * scale;
  }
  double normal(double mean, double stddev) { return mean + stddev * normal(); }

  /// The whole state (a saved run): the four words and normal()'s spare value.
  void save(StateWriter& out) const {
    for (const std::uint64_t word : s_) out.u64(word);
    out.f64(spare_);
    out.boolean(has_spare_);
  }
  void load(StateReader& in) {
    for (auto& word : s_) word = in.u64();
    if (s_[0] == 0 && s_[1] == 0 && s_[2] == 0 && s_[3] == 0) in.fail("a random stream of all zeros");
    spare_ = in.f64();
    has_spare_ = in.boolean();
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
  double spare_ = 0.0;  // the second value of the last pair normal() drew
  bool has_spare_ = false;
};

/// A seed for a sub-stream: the same (seed, a, b) always gives the same result.
constexpr std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t a, std::uint64_t b = 0) {
  return hash_combine(hash_combine(mix64(seed), a), b);
}

}  // namespace vwg
