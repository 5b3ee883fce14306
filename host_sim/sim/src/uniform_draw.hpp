// Draws that are the same on every standard library: std::uniform_real_distribution and friends are
// implementation-defined, so generated recordings would differ between platforms; these use only the raw bits.
#pragma once

#include <cstdint>
#include <random>

namespace lashid::sim {

class Draw {
 public:
  explicit Draw(std::uint64_t seed) : rng_(seed) {}
  /// Uniform in [lo, hi) from the top 53 bits of one draw.
  double uniform(double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng_() >> 11) * 0x1.0p-53); }
  /// Uniform integer in [lo, hi] (modulo bias below 2^-58 for the small ranges used here).
  int integer(int lo, int hi) { return lo + static_cast<int>(rng_() % static_cast<std::uint64_t>(hi - lo + 1)); }
  bool coin(double p) { return uniform(0.0, 1.0) < p; }
  std::uint64_t raw() { return rng_(); }

 private:
  std::mt19937_64 rng_;
};

}  // namespace lashid::sim
