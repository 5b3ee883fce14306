// The DIS example of the paper, Section 3.5, in float for generating on target (the bench image, main.cpp): the
// plant A = 1 + q^-1 + 0.21 q^-2, B = 70.5 q^-1 - 35.25 q^-2, the descending border C_d of the example, and
// deterministic pseudo-noise of standard deviation 4 (variance 16, as in the paper). No libm, no heap.
// Reference: F. Giri, Y. Rochdi, A. Brouri, F. Z. Chaoui, "Identification of block-oriented systems in the presence
// of nonparametric input nonlinearities of switch and backlash types", Automatica, Section 3.5.
#pragma once

#include <cstdint>

namespace lashid::bench {

constexpr float kVMin = -3.0f;
constexpr float kVMax = 4.0f;
constexpr float kA1 = 1.0f;
constexpr float kA2 = 0.21f;
constexpr float kB1 = 70.5f;
constexpr float kB2 = -35.25f;
constexpr float kNoiseSd = 4.0f;

// C_d of the example and F^d of (3.2): C_d(V) up to V = 3, u_M = C_d(3) = 71.375 / 70.5 above.
inline float border_d(float v) {
  const float w = v <= 3.0f ? v : 3.0f;
  return (((w + 3.5f) * w + 2.75f) * w + 4.625f) / 70.5f;
}

// Deterministic pseudo-noise: a 32-bit LCG (Numerical Recipes' constants), 12 uniforms on [0, 1) summed minus 6
// (Irwin-Hall: mean 0, variance 1, a close-to-Gaussian bell on [-6, 6]). No libm needed.
class PseudoNoise {
 public:
  float next() {
    float sum = 0.0f;
    for (int i = 0; i < 12; ++i) {
      state_ = 1664525U * state_ + 1013904223U;
      sum += static_cast<float>(state_ >> 8) * (1.0f / 16777216.0f);
    }
    return sum - 6.0f;
  }

 private:
  std::uint32_t state_ = 12345U;
};

// y(t) = -a1 y(t-1) - a2 y(t-2) + b1 u(t-1) + b2 u(t-2) + xi(t), started at the equilibrium of the held output.
class Plant {
 public:
  explicit Plant(float u0) : u1_(u0), u2_(u0) {
    y1_ = (kB1 + kB2) * u0 / (1.0f + kA1 + kA2);
    y2_ = y1_;
  }
  float next(float u) {
    const float y = -kA1 * y1_ - kA2 * y2_ + kB1 * u1_ + kB2 * u2_ + kNoiseSd * noise_.next();
    y2_ = y1_;
    y1_ = y;
    u2_ = u1_;
    u1_ = u;
    return y;
  }

 private:
  float y1_ = 0.0f, y2_ = 0.0f, u1_, u2_;
  PseudoNoise noise_;
};

}  // namespace lashid::bench
