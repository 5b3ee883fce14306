// The output dynamics after the operator under sensor noise: three files through a 5 Hz resonance, orders 2 to 4
// cross-validated. About 7 s in Release and 20 to 50 s under the sanitizers, hence its own executable, labelled
// `slow` (built in Release only; tests/CMakeLists.txt); the noise-free cases are in test_output_dynamics.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "lashid/operator_fit/output_dynamics.hpp"
#include "output_dynamics_support.hpp"

namespace {

using namespace lashid::sim;
using lashid::test::kRate;
using lashid::test::switch_output;
using lashid::test::through_resonance;

// Sensor noise biases the equation error (the regressors hold noisy outputs); the simulated error does not see it.
TEST(OutputDynamics, NoisyMeasurementStillGivesTheResonanceAndTheOrder) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<FilterData> files;
  double best_fit = 0;  // mean over the files of 100 (1 - 0.05 / std(noise-free y)): the truth's own fit
  for (const double hz : {0.5, 0.9, 1.3}) {
    const std::vector<double> w = switch_output(hz, 6.0);
    std::vector<double> y = through_resonance(w, 5.0, 0.1);
    double mean = 0, var = 0;
    for (const double x : y) mean += x / static_cast<double>(y.size());
    for (const double x : y) var += (x - mean) * (x - mean) / static_cast<double>(y.size());
    best_fit += 100 * (1 - 0.05 / std::sqrt(var)) / 3;
    for (double& x : y) x += noise(rng);
    files.push_back({w, y});
  }
  const OutputDynamicsFit fit = fit_output_dynamics(files);  // orders 2..4, one file held out at a time
  ASSERT_EQ(fit.scores.size(), 3U);

  EXPECT_EQ(fit.filter.order(), 2) << "a higher order must not earn its parameters on a 2nd-order truth";
  FilterPole p;
  ASSERT_TRUE(dominant_pole(filter_poles(fit.filter, kRate), &p));
  EXPECT_NEAR(p.natural_hz, 5.0, 0.05);
  EXPECT_NEAR(p.zeta, 0.1, 0.01);
  // Only the noise is left: the fit is the truth's own, within what 9 parameters can take out of the noise.
  EXPECT_NEAR(fit.fit_train, best_fit, 0.2);
}

}  // namespace
