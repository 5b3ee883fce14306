#include "lashid/plant/linear_plant.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace lashid::sim {

namespace {

double checked_standard_deviation(double variance) {
  if (!std::isfinite(variance) || variance < 0.0) {
    throw std::invalid_argument("noise variance must be finite and >= 0, got " + std::to_string(variance));
  }
  return std::sqrt(variance);
}

// 53 random bits -> uniform double in [0, 1), exactly representable, independent of the standard library.
double unit_interval(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }

LinearModel checked_model(LinearModel model) {
  if (model.a.size() != model.b.size()) {
    throw std::invalid_argument("LinearPlant: A and B must have the same order, got a.size() = " +
                                std::to_string(model.a.size()) + ", b.size() = " + std::to_string(model.b.size()));
  }
  if (model.a.empty()) throw std::invalid_argument("LinearPlant: order n must be >= 1");
  for (std::size_t i = 0; i < model.a.size(); ++i) {
    if (!std::isfinite(model.a[i]) || !std::isfinite(model.b[i])) {
      throw std::invalid_argument("LinearPlant: coefficient a" + std::to_string(i + 1) + " or b" +
                                  std::to_string(i + 1) + " is not finite");
    }
  }
  return model;
}

}  // namespace

GaussianNoise::GaussianNoise(double variance, std::uint64_t seed)
    : engine_(seed), standard_deviation_(checked_standard_deviation(variance)) {}

double GaussianNoise::next() {
  if (has_spare_) {
    has_spare_ = false;
    return standard_deviation_ * spare_;
  }
  // Box-Muller: r = sqrt(-2 ln U1) with U1 in (0, 1] so the logarithm is finite, angle 2 pi U2.
  const double u1 = 1.0 - unit_interval(engine_());
  const double u2 = unit_interval(engine_());
  const double radius = std::sqrt(-2.0 * std::log(u1));
  const double angle = 2.0 * std::numbers::pi * u2;
  spare_ = radius * std::sin(angle);
  has_spare_ = true;
  return standard_deviation_ * (radius * std::cos(angle));
}

Ar1Noise::Ar1Noise(double standard_deviation, double pole, std::uint64_t seed)
    : unit_(1.0, seed),
      standard_deviation_(standard_deviation),
      pole_(pole),
      innovation_scale_(standard_deviation * std::sqrt(1.0 - pole * pole)) {
  if (!std::isfinite(standard_deviation) || standard_deviation < 0.0) {
    throw std::invalid_argument("Ar1Noise: standard deviation must be finite and >= 0, got " +
                                std::to_string(standard_deviation));
  }
  if (!(std::fabs(pole) < 1.0)) {
    throw std::invalid_argument("Ar1Noise: pole must lie in (-1, 1), got " + std::to_string(pole));
  }
}

double Ar1Noise::next() {
  const double z = unit_.next();
  e_ = started_ ? pole_ * e_ + innovation_scale_ * z : standard_deviation_ * z;
  started_ = true;
  return e_;
}

LinearPlant::LinearPlant(LinearModel model, double noise_variance, std::uint64_t seed)
    : model_(checked_model(std::move(model))),
      noise_(noise_variance, seed),
      past_y_(model_.a.size(), 0.0),
      past_u_(model_.a.size(), 0.0) {}

double LinearPlant::step(double u) {
  double y = noise_.next();
  for (std::size_t i = 0; i < past_y_.size(); ++i) {
    y += model_.b[i] * past_u_[i] - model_.a[i] * past_y_[i];
  }
  // Shift the histories by one sample; n is small (the paper uses n = 2), so a move beats a ring buffer's index math.
  std::move_backward(past_y_.begin(), past_y_.end() - 1, past_y_.end());
  std::move_backward(past_u_.begin(), past_u_.end() - 1, past_u_.end());
  past_y_.front() = y;
  past_u_.front() = u;
  return y;
}

void LinearPlant::reset_state() {
  std::fill(past_y_.begin(), past_y_.end(), 0.0);
  std::fill(past_u_.begin(), past_u_.end(), 0.0);
}

double dc_gain(const LinearModel& model) {
  double a_at_one = 1.0;
  double b_at_one = 0.0;
  for (const double a : model.a) a_at_one += a;
  for (const double b : model.b) b_at_one += b;
  if (a_at_one == 0.0) throw std::domain_error("dc_gain: A(1) = 0, the model has no finite static gain");
  return b_at_one / a_at_one;
}

}  // namespace lashid::sim
