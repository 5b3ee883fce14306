// The one firmware image with run-time designs, on the host board: a design that is not the paper's, designs the
// firmware refuses over the link with their named status, and the validation phase after the estimates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "firmware_reports.hpp"
#include "lashid/firmware/paper_run_designs.hpp"
#include "lashid/firmware/sequencer.hpp"
#include "lashid/hil/hil.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/sim/scenario.hpp"
#include "link_frames.hpp"

namespace {

using namespace lashid;
using hal::link::MessageType;
using test::command;
using test::frames_of;
using test::reports_of;
using test::Reports;

// A design that is not the paper's, through the same image: n = 3, m = 8 (T = 33), a switch, and a plant of order
// 3. The truth comes from replaying the experiments on the operator (scenario_truth), not from the estimator.
sim::Scenario order_three_scenario() {
  sim::Scenario s = sim::find_scenario("ais_paper");
  s.name = "order_three";
  const double K = std::log(52.0) - std::log(3.0);
  // Poles 0.5, 0.4, 0.3: A = (1 - 0.5 q^-1)(1 - 0.4 q^-1)(1 - 0.3 q^-1).
  s.model = {{-1.2, 0.47, -0.06}, {4.0 * K, -K, 0.5 * K}};
  s.config.n = 3;
  s.config.m = 8;
  s.config.V_d = {-2.0, -1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5};
  s.config.V_a = {2.0, 1.5, 1.0, 0.5, 0.0, -0.5, -1.0, -1.5};
  s.config.truth = sim::scenario_truth(s);
  return s;
}

TEST(FirmwareOnHostBoard, IdentifiesADesignThatIsNotThePapers) {
  const sim::Scenario s = order_three_scenario();
  const fw::RunDesign design = sim::run_design_of(s);
  EXPECT_EQ(design.period(), 33);
  sim::ScenarioBoard board = sim::make_scenario_board(s, 5);
  fw::IdentificationSequencer<sim::ScenarioBoard> firmware(board, design);
  ASSERT_EQ(firmware.run(), fw::RunStatus::kOk);
  const Reports r = reports_of(board);
  ASSERT_EQ(r.estimates.size(), 2u);
  const sim::Truth& truth = *s.config.truth;
  for (const auto& e : r.estimates) {
    ASSERT_EQ(e.n, 3);
    ASSERT_EQ(e.m, 8);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_NEAR(e.a[i], truth.a[i], 4.5f * e.se_a[i]) << "a" << i + 1;
      EXPECT_NEAR(e.b[i], truth.b[i], 4.5f * e.se_b[i]) << "b" << i + 1;
    }
    const auto& F = e.scheme == est::Scheme::kDescending ? truth.F_d : truth.F_a;
    for (std::size_t j = 0; j < 8; ++j) EXPECT_NEAR(e.F[j], F[j], 0.05) << "scheme " << int(e.scheme) << " j " << j;
  }
  EXPECT_EQ(r.cross.disagree, 0) << "max z " << r.cross.max_z;

  // The firmware's excitation is the simulator's for this design too, and its estimates are the host estimator's.
  sim::SimulationOptions options;
  options.seed = 5;
  options.validation_phase = false;
  const sim::Recording rec = sim::simulate(s, options);
  ASSERT_EQ(board.exchanges().size(), rec.size());
  std::size_t k = 0;
  for (const sim::Phase p : rec.order()) {
    for (const sim::Sample& x : rec.phase(p)) {
      ASSERT_EQ(board.exchanges()[k].v, static_cast<float>(x.v)) << "sample " << k;
      ++k;
    }
  }
  sim::IdentifyOptions f32;
  f32.precision = sim::Precision::kFloat;
  for (const auto& e : r.estimates) {
    const sim::SchemeResult cli = sim::identify_scheme(s.config, rec, e.scheme, f32, "rec");
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_NEAR(e.a[i], cli.a[i], 1e-3 * std::fabs(cli.a[i]));
      EXPECT_NEAR(e.b[i], cli.b[i], 1e-3 * std::fabs(cli.b[i]));
    }
  }
}

TEST(FirmwareOnHostBoard, RefusesAnInvalidDesignOverTheLinkWithItsNamedStatus) {
  struct Case {
    const char* what;
    fw::RunDesign design;
    fw::DesignStatus expected;
  };
  std::vector<Case> cases;
  fw::RunDesign d = fw::kAisPaperRun;
  d.n = 5;
  cases.push_back({"n beyond the capacity", d, fw::DesignStatus::kOrderOutOfRange});
  d = fw::kAisPaperRun;
  d.V_d[2] = d.V_d[1];
  cases.push_back({"V_d not increasing", d, fw::DesignStatus::kVdNotIncreasing});
  d = fw::kAisPaperRun;
  d.pulse_length_a = 35;  // 2T = 36
  cases.push_back({"AP shorter than two periods", d, fw::DesignStatus::kPulseATooShort});
  d = fw::kAisPaperRun;
  d.step_length = 2;  // L must exceed n = 2
  cases.push_back({"step too short", d, fw::DesignStatus::kStepTooShort});
  for (const Case& c : cases) {
    const sim::Scenario& s = sim::find_scenario("ais_paper");
    sim::ScenarioBoard board = sim::make_scenario_board(s, 1);
    fw::IdentificationSequencer<sim::ScenarioBoard> firmware(board);
    const auto design = test::design_frame(c.design);
    board.link_input(design.data(), design.size());
    const auto start = command(hal::link::Command::kStart);
    board.link_input(start.data(), start.size());
    EXPECT_EQ(firmware.run(), fw::RunStatus::kDesignRejected) << c.what;
    EXPECT_EQ(firmware.design_status(), c.expected) << c.what;
    EXPECT_TRUE(board.exchanges().empty()) << c.what << ": nothing may run on an invalid design";
    int answered = -1;
    for (const auto& f : frames_of(board.link_output())) {
      if (f.type == MessageType::kDesignStatus) answered = f.payload[0];
    }
    EXPECT_EQ(answered, static_cast<int>(c.expected)) << c.what;
  }
}

TEST(FirmwareOnHostBoard, RunsTheValidationPhaseAfterTheEstimates) {
  const sim::Scenario& s = sim::find_scenario("ais_paper");
  fw::RunDesign design = fw::kAisPaperRun;
  design.val_length = 700;
  design.val_seed = 9;
  sim::ScenarioBoard board = sim::make_scenario_board(s, 2);
  fw::IdentificationSequencer<sim::ScenarioBoard> firmware(board, design);
  ASSERT_EQ(firmware.run(), fw::RunStatus::kOk);
  ASSERT_EQ(board.exchanges().size(), 2u * 2001 + 16000 + 700);
  // Every validation input is one of the design's levels or a bound (the set of ValidationExcitation).
  std::vector<float> levels{-2.0f, 2.0f};
  for (int j = 0; j < 6; ++j) {
    levels.push_back(design.V_d[static_cast<std::size_t>(j)]);
    levels.push_back(design.V_a[static_cast<std::size_t>(j)]);
  }
  for (std::size_t k = 2u * 2001 + 16000; k < board.exchanges().size(); ++k) {
    EXPECT_NE(std::find(levels.begin(), levels.end(), board.exchanges()[k].v), levels.end()) << "sample " << k;
  }
  // The estimates are the same as without the validation phase (it comes after them).
  sim::ScenarioBoard plain = sim::make_scenario_board(s, 2);
  fw::IdentificationSequencer<sim::ScenarioBoard> reference(plain, fw::kAisPaperRun);
  ASSERT_EQ(reference.run(), fw::RunStatus::kOk);
  const auto with_val = reports_of(board).estimates, without_val = reports_of(plain).estimates;
  ASSERT_EQ(with_val.size(), 2U);
  ASSERT_EQ(without_val.size(), 2U);
  for (std::size_t k = 0; k < 2; ++k) {
    const fw::EstimateRecord &e = with_val[k], &r = without_val[k];
    EXPECT_EQ(e.scheme, r.scheme) << k;
    EXPECT_EQ(e.status, r.status) << k;
    EXPECT_EQ(e.ybar0, r.ybar0) << k;
    EXPECT_EQ(e.noise_variance, r.noise_variance) << k;
    EXPECT_EQ(e.a, r.a) << k;
    EXPECT_EQ(e.se_a, r.se_a) << k;
    EXPECT_EQ(e.b, r.b) << k;
    EXPECT_EQ(e.se_b, r.se_b) << k;
    EXPECT_EQ(e.F, r.F) << k;
  }
}

}  // namespace
