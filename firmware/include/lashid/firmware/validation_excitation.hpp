// The validation phase's input (phase `val` of a recording), generated on the device from the run's design and a
// seed, so that a recording made through the firmware can be diagnosed (`lashid diagnose`) like a simulated one.
//
// It visits the design's levels L = {v_m, v_M, V^d, V^a} (sorted, duplicates merged) in segments of two holds:
//   - a step from an extreme: to v_m or v_M (either, at random), then to a random other level;
//   - a small reversal: from the current level to a neighbouring one and back.
// Each segment is one of the two with probability 1/2; every hold lasts a random kMinHold..kMaxHold samples. The
// reversals are what tell a switch from a backlash: after a small step up and back, a switch's output returns to
// the descending border while a backlash's stays on the horizontal inside the loop (Section 2, (2.3)-(2.4)).
// The generator is xorshift32 (Marsaglia 2003): a fixed, documented sequence on every target, no library state.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "lashid/firmware/run_design.hpp"

namespace lashid::fw {

class ValidationExcitation {
 public:
  static constexpr int kMinHold = 10;
  static constexpr int kMaxHold = 50;
  static constexpr int kMaxLevels = 2 * kMaxPoints + 2;

  ValidationExcitation() = default;
  /// The design must have passed check_design().
  explicit ValidationExcitation(const RunDesign& d) { restart(d); }

  void restart(const RunDesign& d) {
    count_ = 0;
    insert(d.v_min);
    insert(d.v_max);
    for (int j = 0; j < d.m && j < kMaxPoints; ++j) {
      insert(d.V_d[static_cast<std::size_t>(j)]);
      insert(d.V_a[static_cast<std::size_t>(j)]);
    }
    // xorshift32 must not start at 0; the mix spreads nearby seeds (1, 2, 3 ...) apart.
    state_ = (d.val_seed ^ 0x9E3779B9U) == 0U ? 1U : d.val_seed ^ 0x9E3779B9U;
    current_ = 0;
    second_ = -1;
    remaining_ = 0;
  }

  /// v of the next validation sample.
  float next() {
    if (remaining_ == 0) advance();
    --remaining_;
    return levels_[static_cast<std::size_t>(current_)];
  }

  int level_count() const { return count_; }
  float level(int i) const { return levels_[static_cast<std::size_t>(i)]; }

 private:
  std::uint32_t random() {
    std::uint32_t x = state_;
    x ^= x << 13U;
    x ^= x >> 17U;
    x ^= x << 5U;
    state_ = x;
    return x;
  }
  /// Uniform in [lo, hi] (the modulo bias, below 1e-8 for these ranges, does not matter for an excitation).
  int uniform(int lo, int hi) { return lo + static_cast<int>(random() % static_cast<std::uint32_t>(hi - lo + 1)); }

  void insert(float v) {
    int i = 0;
    while (i < count_ && levels_[static_cast<std::size_t>(i)] < v) ++i;
    if (i < count_ && levels_[static_cast<std::size_t>(i)] == v) return;
    for (int k = count_; k > i; --k) levels_[static_cast<std::size_t>(k)] = levels_[static_cast<std::size_t>(k - 1)];
    levels_[static_cast<std::size_t>(i)] = v;
    ++count_;
  }

  void advance() {
    remaining_ = uniform(kMinHold, kMaxHold);
    if (second_ >= 0) {  // the second hold of the current segment
      current_ = second_;
      second_ = -1;
      return;
    }
    const int last = count_ - 1;
    if ((random() & 1U) == 0U) {  // step from an extreme to another level
      const int extreme = (random() & 1U) == 0U ? 0 : last;
      int other = uniform(0, last - 1);
      if (other >= extreme) ++other;
      current_ = extreme;
      second_ = other;
    } else {  // small reversal around the current level
      int neighbour = (random() & 1U) == 0U ? current_ - 1 : current_ + 1;
      if (neighbour < 0) neighbour = 1;
      if (neighbour > last) neighbour = last - 1;
      second_ = current_;
      current_ = neighbour;
    }
  }

  std::array<float, kMaxLevels> levels_{};
  int count_ = 0;
  std::uint32_t state_ = 1;
  int current_ = 0;
  int second_ = -1;
  int remaining_ = 0;
};

}  // namespace lashid::fw
