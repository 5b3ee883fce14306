// The plant of a plant file against outputs computed by hand, its noises against their definitions, and
// `simulate --plant`'s recording: five phases with the design's lengths, val from the device's own generator.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "lashid/firmware/validation_excitation.hpp"
#include "lashid/io/data_error.hpp"
#include "lashid/sim/file_plant.hpp"

namespace lashid::sim {
namespace {

// Switch with C_a(v) = v - 1 and C_d(v) = v + 1 on [-1, 1] (two grid points each: exactly linear),
// A = 1 - 0.5 q^-1, B = 2 q^-1, no noise.
PlantSpec hand_plant() {
  PlantSpec p;
  p.op = OperatorKind::kSwitch;
  p.border_v = {-1, 1};
  p.border_ascending = {-2, 0};
  p.border_descending = {0, 2};
  p.a = {-0.5};
  p.b = {2.0};
  return p;
}

std::vector<double> play(FilePlant plant, const std::vector<double>& v) {
  std::vector<double> y;
  for (double x : v) y.push_back(plant.step(x));
  return y;
}

const std::vector<double> kInput = {-1, 0, 1, 0.5, 0.5, -0.5};

// Started at v_start = -1: u(-1) = C_d(-1) = 0. The switch: v repeats -> hold, rises -> C_a(v), falls -> C_d(v):
//   u = 0, C_a(0) = -1, C_a(1) = 0, C_d(0.5) = 1.5, hold 1.5, C_d(-0.5) = 0.5.
// y(t) = 0.5 y(t-1) + 2 u(t-1), from rest:
//   y = 0, 0, 0.5*0 + 2*(-1) = -2, -1 + 0 = -1, -0.5 + 3 = 2.5, 1.25 + 3 = 4.25.
TEST(FilePlant, SwitchAndFirstOrderPlantEqualTheHandComputedOutput) {
  const std::vector<double> y = play(FilePlant(hand_plant(), -1.0, 7), kInput);
  const std::vector<double> expected = {0, 0, -2, -1, 2.5, 4.25};
  ASSERT_EQ(y.size(), expected.size());
  for (std::size_t t = 0; t < y.size(); ++t) EXPECT_DOUBLE_EQ(y[t], expected[t]) << "t = " << t;
}

// Backlash with the same borders: it leaves a border only when v travels far enough. From (-1, C_d(-1) = 0):
//   v = -1 hold 0; v = 0: rising, C_a^{-1}(0) = 1 > 0, still in the gap -> 0; v = 1: reaches C_a(1) = 0 -> 0;
//   v = 0.5: falling, C_d^{-1}(0) = -1 < 0.5 -> hold 0; hold 0; v = -0.5: C_d^{-1}(0) = -1 < -0.5 -> hold 0.
// u stays 0: y = 0 throughout.
TEST(FilePlant, BacklashHoldsInsideItsLoop) {
  PlantSpec p = hand_plant();
  p.op = OperatorKind::kBacklash;
  for (double y : play(FilePlant(p, -1.0, 7), kInput)) EXPECT_EQ(y, 0.0);
}

// Dead time d = 1: the operator sees v one sample late, the delay line starting full of v_start = -1:
//   operator input -1, -1, 0, 1, 0.5, 0.5 -> u = 0, 0, -1, 0, 1.5, 1.5;
//   y = 0, 0, 0, -2, -1, 2.5. Drift 0.1 per sample adds 0.1 k, k = 0, 1, 2...
TEST(FilePlant, DeadTimeAndDriftShiftTheHandComputedOutput) {
  PlantSpec p = hand_plant();
  p.dead_time = 1;
  p.sensor_drift_per_sample = 0.1;
  const std::vector<double> y = play(FilePlant(p, -1.0, 7), kInput);
  const std::vector<double> expected = {0, 0.1, 0.2, -2 + 0.3, -1 + 0.4, 2.5 + 0.5};
  for (std::size_t t = 0; t < y.size(); ++t) EXPECT_DOUBLE_EQ(y[t], expected[t]) << "t = " << t;
}

// Input lag 0.5: w(t) = 0.5 w(t-1) + 0.5 v(t), w resting at v_start = -1:
//   v = 1, 1, 1 -> w = 0, 0.5, 0.75; switch rising each time -> u = C_a(w) = -1, -0.5, -0.25;
//   y = 0, 2*(-1) = -2, -1 + 2*(-0.5) = -2.
TEST(FilePlant, InputLagFiltersTheCommandBeforeTheOperator) {
  PlantSpec p = hand_plant();
  p.input_lag = 0.5;
  const std::vector<double> y = play(FilePlant(p, -1.0, 7), {1, 1, 1});
  EXPECT_DOUBLE_EQ(y[0], 0.0);
  EXPECT_DOUBLE_EQ(y[1], -2.0);
  EXPECT_DOUBLE_EQ(y[2], -2.0);
}

// Sensor noise alone (B = 0, A = 1 + 0 q^-1): y is the AR(1) noise. Its standard deviation is the given one, its
// lag-1 correlation the pole, and already the first sample has the stationary spread (over many seeds).
TEST(FilePlant, SensorNoiseIsStationaryAr1WithTheGivenStdAndPole) {
  PlantSpec p = hand_plant();
  p.a = {0.0};
  p.b = {0.0};
  p.sensor_noise = SensorNoiseSpec{0.3, 0.8};
  FilePlant plant(p, 0.0, 11);
  const int samples = 400000;
  double sum2 = 0, lag1 = 0, previous = 0;
  for (int k = 0; k < samples; ++k) {
    const double y = plant.step(0.0);
    sum2 += y * y;
    if (k > 0) lag1 += y * previous;
    previous = y;
  }
  // AR(1) with pole 0.8: the estimates' standard errors are ~ 0.3 * sqrt((1 + c^2) / (1 - c^2) / N) ~ 1e-3 here.
  EXPECT_NEAR(std::sqrt(sum2 / samples), 0.3, 0.01);
  EXPECT_NEAR(lag1 / sum2, 0.8, 0.01);
  double first2 = 0;
  const int seeds = 4000;
  for (int s = 0; s < seeds; ++s) {
    const double y0 = FilePlant(p, 0.0, static_cast<std::uint64_t>(s)).step(0.0);
    first2 += y0 * y0;
  }
  EXPECT_NEAR(std::sqrt(first2 / seeds), 0.3, 0.015);  // relative standard error 1 / sqrt(2 x 4000) ~ 1.1 %
}

TEST(FilePlant, EquationNoiseIsWhiteWithTheGivenStdAndSeeded) {
  PlantSpec p = hand_plant();
  p.a = {0.0};
  p.b = {0.0};
  p.equation_noise_std = 0.5;
  FilePlant plant(p, 0.0, 3), same(p, 0.0, 3), other(p, 0.0, 4);
  double sum2 = 0;
  bool differs = false;
  for (int k = 0; k < 100000; ++k) {
    const double y = plant.step(0.0);
    EXPECT_EQ(y, same.step(0.0));
    differs = differs || y != other.step(0.0);
    sum2 += y * y;
  }
  EXPECT_NEAR(std::sqrt(sum2 / 100000), 0.5, 0.01);
  EXPECT_TRUE(differs);
}

ExperimentConfig config_without_lengths() {
  ExperimentConfig c{};
  c.n = 1;
  c.m = 2;
  c.v_min = -1;
  c.v_max = 1;
  c.V_d = {-1, 0};
  c.V_a = {1, 0.5};
  c.op = OperatorKind::kSwitch;
  return c;
}

// The device's design of config_without_lengths(), written out by hand: L = N_d = N_a = 2000, val 2000, seed 1.
fw::RunDesign hand_design() {
  fw::RunDesign d;
  d.op = fw::OperatorKind::kSwitch;
  d.n = 1;
  d.m = 2;
  d.v_min = -1;
  d.v_max = 1;
  d.V_d[0] = -1;
  d.V_d[1] = 0;
  d.V_a[0] = 1;
  d.V_a[1] = 0.5;
  d.step_length = d.pulse_length_d = d.pulse_length_a = d.val_length = 2000;
  d.val_seed = 1;
  return d;
}

TEST(SimulateFilePlant, FivePhasesWithTheDesignLengthsAndTheDevicesValidationInput) {
  const Recording rec = simulate_file_plant(hand_plant(), "plant.json", config_without_lengths(), hand_design(), 5);
  ASSERT_EQ(rec.order(), (std::vector<Phase>{Phase::kStepD, Phase::kDis, Phase::kStepA, Phase::kAis, Phase::kVal}));
  EXPECT_EQ(rec.phase(Phase::kStepD).size(), 2001U);
  EXPECT_EQ(rec.phase(Phase::kDis).size(), 2000U);
  EXPECT_EQ(rec.phase(Phase::kStepA).size(), 2001U);
  EXPECT_EQ(rec.phase(Phase::kAis).size(), 2000U);
  ASSERT_EQ(rec.phase(Phase::kVal).size(), 2000U);
  fw::ValidationExcitation device(hand_design());
  for (const Sample& s : rec.phase(Phase::kVal)) ASSERT_EQ(s.v, static_cast<double>(device.next()));
  // The step experiment (3.4) starts at v_m and holds v_M.
  EXPECT_EQ(rec.phase(Phase::kStepD)[0].v, -1.0);
  EXPECT_EQ(rec.phase(Phase::kStepD)[5].v, 1.0);
}

TEST(SimulateFilePlant, RefusesBordersThatDoNotCoverTheInterval) {
  ExperimentConfig wide = config_without_lengths();
  wide.v_max = 2;
  wide.V_a = {2, 0.5};
  fw::RunDesign design = hand_design();
  design.v_max = 2;
  design.V_a[0] = 2;
  try {
    (void)simulate_file_plant(hand_plant(), "plant.json", wide, design, 1);
    ADD_FAILURE() << "expected a DataError";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("plant.json: 'borders.v' covers [-1, 1]"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lashid::sim
