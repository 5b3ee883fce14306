// Linear subsystem (2.1)-(2.2) and its noise source, against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "lashid/plant/linear_plant.hpp"

namespace lashid::sim {
namespace {

TEST(GaussianNoise, SameSeedSameSequenceDifferentSeedDifferentSequence) {
  GaussianNoise first(2.0, 42);
  GaussianNoise second(2.0, 42);
  GaussianNoise other(2.0, 43);
  bool any_difference = false;
  for (int i = 0; i < 1000; ++i) {
    const double x = first.next();
    EXPECT_EQ(x, second.next()) << "draw " << i;
    any_difference = any_difference || x != other.next();
  }
  EXPECT_TRUE(any_difference);
}

TEST(GaussianNoise, SampleMomentsWithinFiveSigma) {
  // For N iid N(0, s2) draws: the sample mean has standard deviation sqrt(s2/N); the sample variance has
  // standard deviation s2 sqrt(2/(N-1)).
  constexpr double variance = 16.0;  // the paper's DIS noise level
  constexpr int draws = 100000;
  GaussianNoise noise(variance, 2024);
  double sum = 0.0;
  double sum_squares = 0.0;
  for (int i = 0; i < draws; ++i) {
    const double x = noise.next();
    sum += x;
    sum_squares += x * x;
  }
  const double n = draws;
  const double mean = sum / n;
  const double sample_variance = (sum_squares - n * mean * mean) / (n - 1.0);
  EXPECT_LT(std::abs(mean), 5.0 * std::sqrt(variance / n));
  EXPECT_LT(std::abs(sample_variance - variance), 5.0 * variance * std::sqrt(2.0 / (n - 1.0)));
  EXPECT_DOUBLE_EQ(noise.variance(), variance);
}

TEST(GaussianNoise, ZeroVarianceIsSilentAndNegativeThrows) {
  GaussianNoise silent(0.0, 7);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(silent.next(), 0.0);
  EXPECT_THROW(GaussianNoise(-1.0, 7), std::invalid_argument);
  EXPECT_THROW(GaussianNoise(std::numeric_limits<double>::quiet_NaN(), 7), std::invalid_argument);
}

std::vector<double> impulse_response(const LinearModel& model, int length) {
  LinearPlant plant(model, 0.0, 1);
  std::vector<double> y;
  for (int t = 0; t < length; ++t) y.push_back(plant.step(t == 0 ? 1.0 : 0.0));
  return y;
}

TEST(LinearPlant, FirstOrderImpulseResponseIsGeometric) {
  // (1 - 0.5 q^-1) y = q^-1 u: h(0) = 0 (no feed-through), h(k) = 0.5^(k-1) for k >= 1.
  const auto h = impulse_response({{-0.5}, {1.0}}, 30);
  EXPECT_EQ(h[0], 0.0);
  for (int k = 1; k < 30; ++k) EXPECT_NEAR(h[static_cast<std::size_t>(k)], std::pow(0.5, k - 1), 1e-15) << k;
}

TEST(LinearPlant, SecondOrderImpulseResponseOfThePaperModel) {
  // (3.31): A = 1 + q^-1 + 0.21 q^-2 = (1 + 0.3 q^-1)(1 + 0.7 q^-1), B = 70.5 q^-1 + 35.25 q^-2.
  // By the recursion: h(1) = 70.5, h(2) = -70.5 + 35.25 = -35.25, h(3) = 35.25 - 0.21*70.5 = 20.445,
  // h(4) = -20.445 + 0.21*35.25 = -13.0425. Closed form for k >= 1 (fit on h(1), h(2)):
  // h(k) = 35.25 ((-0.3)^(k-1) + (-0.7)^(k-1)).
  const auto h = impulse_response({{1.0, 0.21}, {70.5, 35.25}}, 40);
  EXPECT_EQ(h[0], 0.0);
  EXPECT_NEAR(h[1], 70.5, 1e-12);
  EXPECT_NEAR(h[2], -35.25, 1e-12);
  EXPECT_NEAR(h[3], 20.445, 1e-12);
  EXPECT_NEAR(h[4], -13.0425, 1e-12);
  for (int k = 1; k < 40; ++k) {
    const double closed_form = 35.25 * (std::pow(-0.3, k - 1) + std::pow(-0.7, k - 1));
    EXPECT_NEAR(h[static_cast<std::size_t>(k)], closed_form, 1e-11) << k;
  }
}

TEST(LinearPlant, OutputUsesOnlyPastInputs) {
  // y(t) = 2 u(t-1): the current input shows up one sample later.
  LinearPlant plant({{0.0}, {2.0}}, 0.0, 1);
  EXPECT_EQ(plant.step(3.0), 0.0);
  EXPECT_EQ(plant.step(-1.0), 6.0);
  EXPECT_EQ(plant.step(0.0), -2.0);
  plant.reset_state();
  EXPECT_EQ(plant.step(5.0), 0.0);
  EXPECT_EQ(plant.order(), 1U);
}

TEST(LinearPlant, NoiseEntersAsEquationError) {
  // With a = b = 0 the output is the noise itself, drawn from the same seeded stream.
  LinearPlant plant({{0.0, 0.0}, {0.0, 0.0}}, 16.0, 99);
  GaussianNoise reference(16.0, 99);
  for (int t = 0; t < 100; ++t) EXPECT_EQ(plant.step(1.0), reference.next()) << t;
}

TEST(LinearPlant, StepResponseSettlesAtDcGain) {
  const LinearModel first_order{{-0.5}, {1.0}};
  const LinearModel paper{{1.0, 0.21}, {70.5, 35.25}};
  EXPECT_DOUBLE_EQ(dc_gain(first_order), 2.0);             // 1 / (1 - 0.5)
  EXPECT_DOUBLE_EQ(dc_gain(paper), 105.75 / 2.21);         // (70.5 + 35.25) / (1 + 1 + 0.21)
  LinearPlant plant(paper, 0.0, 1);
  double y = 0.0;
  for (int t = 0; t < 200; ++t) y = plant.step(1.0);
  EXPECT_NEAR(y, 105.75 / 2.21, 1e-9);
  EXPECT_THROW((void)dc_gain({{-1.0}, {1.0}}), std::domain_error);
}

TEST(LinearPlant, InvalidModelsThrow) {
  EXPECT_THROW(LinearPlant({{0.5, 0.1}, {1.0}}, 0.0, 1), std::invalid_argument);
  EXPECT_THROW(LinearPlant({{}, {}}, 0.0, 1), std::invalid_argument);
  EXPECT_THROW(LinearPlant({{0.5}, {1.0}}, -1.0, 1), std::invalid_argument);
}

}  // namespace
}  // namespace lashid::sim
