// Linear part of the Hammerstein-like system (2.1)-(2.2): A(q^-1) y = B(q^-1) u + xi, with white Gaussian xi.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

namespace lashid::sim {

// A = 1 + a1 q^-1 + ... + an q^-n ; B = b1 q^-1 + ... + bn q^-n (no direct feed-through); a.size() == b.size().
struct LinearModel {
  std::vector<double> a;
  std::vector<double> b;
};

// Zero-mean Gaussian samples, reproducible from the seed: std::mt19937_64 feeds a hand-written Box-Muller
// transform (std::normal_distribution is implementation-defined and differs between standard libraries).
// Bit-identity across platforms additionally relies on std::log/std::sqrt/std::cos/std::sin, which are
// correctly rounded or near it on mainstream libms.
class GaussianNoise {
 public:
  // Throws std::invalid_argument for a negative or non-finite variance. Variance 0 yields exact zeros.
  GaussianNoise(double variance, std::uint64_t seed);
  double next();
  double variance() const { return standard_deviation_ * standard_deviation_; }

 private:
  std::mt19937_64 engine_;
  double standard_deviation_;
  double spare_ = 0.0;  // Box-Muller produces pairs; the second one is served by the next call.
  bool has_spare_ = false;
};

// Coloured measurement noise: the stationary AR(1) process e(t) = c e(t-1) + w(t), w white Gaussian of variance
// s^2 (1 - c^2), whose stationary standard deviation is s. e(0) is drawn from the stationary law (variance s^2), so
// the noise is stationary from its first sample instead of growing in from zero.
class Ar1Noise {
 public:
  // Throws std::invalid_argument for a negative or non-finite s, or a pole c outside (-1, 1).
  Ar1Noise(double standard_deviation, double pole, std::uint64_t seed);
  double next();

 private:
  GaussianNoise unit_;  // z(t) ~ N(0, 1)
  double standard_deviation_;
  double pole_;
  double innovation_scale_;  // s sqrt(1 - c^2)
  double e_ = 0.0;
  bool started_ = false;
};

// y(t) = -sum_i a_i y(t-i) + sum_i b_i u(t-i) + xi(t); the past starts at zero.
class LinearPlant {
 public:
  // Throws std::invalid_argument on a size mismatch, n == 0, non-finite coefficients or a negative variance.
  LinearPlant(LinearModel model, double noise_variance, std::uint64_t seed);
  // Given u(t): returns y(t) (which uses u(t-1..t-n) only) and then stores u(t).
  double step(double u);
  // Zeroes the past inputs and outputs; the noise stream continues.
  void reset_state();
  const LinearModel& model() const { return model_; }
  std::size_t order() const { return model_.a.size(); }

 private:
  LinearModel model_;
  GaussianNoise noise_;
  std::vector<double> past_y_;  // past_y_[i] = y(t-1-i)
  std::vector<double> past_u_;  // past_u_[i] = u(t-1-i)
};

// Static gain B(1)/A(1). Throws std::domain_error when A(1) == 0 (integrator: no finite DC gain).
double dc_gain(const LinearModel& model);

}  // namespace lashid::sim
