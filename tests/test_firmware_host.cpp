// The identification firmware on the host board: same code as on Cortex-M, plant in-process.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string_view>
#include <utility>
#include <vector>

#include "lashid/firmware/paper_run_designs.hpp"
#include "lashid/firmware/sequencer.hpp"
#include "lashid/hil/hil.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/io/data_error.hpp"
#include "lashid/sim/scenario.hpp"
#include "firmware_host_support.hpp"
#include "firmware_reports.hpp"
#include "link_frames.hpp"

namespace {

using namespace lashid;
using hal::link::MessageType;

using test::command;
using test::frames_of;
using test::reports_of;
using test::Reports;
using test::expect_cli_estimates;
using test::NanSensorBoard;

TEST(FirmwareOnHostBoard, EqualsTheCliEstimatorOnTheSameRecording) {
  // AIS example (switch: no interval check), so the firmware's samples are exactly simulate()'s phases.
  const sim::Scenario& s = sim::find_scenario("ais_paper");
  sim::ScenarioBoard board = sim::make_scenario_board(s, 7);
  fw::IdentificationSequencer<sim::ScenarioBoard> firmware(board, fw::kAisPaperRun);
  ASSERT_EQ(firmware.run(), fw::RunStatus::kOk);

  sim::SimulationOptions options;
  options.seed = 7;
  options.validation_phase = false;
  const sim::Recording rec = sim::simulate(s, options);
  // Same excitation, sample for sample: the firmware's generator and the simulator's.
  ASSERT_EQ(board.exchanges().size(), rec.size());
  std::size_t k = 0;
  for (const sim::Phase p : rec.order()) {
    for (const sim::Sample& x : rec.phase(p)) {
      ASSERT_EQ(board.exchanges()[k].v, static_cast<float>(x.v)) << "sample " << k;
      ASSERT_EQ(board.exchanges()[k].y, static_cast<float>(x.y)) << "sample " << k;
      ++k;
    }
  }
  sim::IdentifyOptions f32;
  f32.precision = sim::Precision::kFloat;
  const Reports r = reports_of(board);
  EXPECT_EQ(r.done, static_cast<int>(fw::RunStatus::kOk));
  expect_cli_estimates(r, s.config, rec, f32);
  // Remark 3b on a plant that is what the model says: the DIS and AIS linear estimates agree.
  EXPECT_EQ(r.cross.disagree, 0) << "max z " << r.cross.max_z;
  EXPECT_GT(r.cross.max_z, 0.0f);
  // Cost: one update per pulse sample, one solve per pulse period (and at the end); every sample used, every
  // report sent.
  EXPECT_EQ(r.cost.rejected_samples, 0u);
  EXPECT_EQ(r.cost.send_failures, 0u);
  EXPECT_EQ(r.cost.updates, 16000u);
  EXPECT_EQ(r.cost.solves, 2u * ((8000 + 17) / 18));
  EXPECT_EQ(r.cost.samples, 2u * 2001 + 16000);
}

TEST(FirmwareOnHostBoard, DisExampleWithIntervalCheckIdentifiesTheBacklash) {
  const sim::Scenario& s = sim::find_scenario("dis_paper");
  sim::ScenarioBoard board = sim::make_scenario_board(s, 3);
  fw::IdentificationSequencer<sim::ScenarioBoard> firmware(board, fw::kDisPaperRun);
  ASSERT_EQ(firmware.run(), fw::RunStatus::kOk);
  const Reports r = reports_of(board);
  ASSERT_EQ(r.estimates.size(), 2u);
  const auto& truth = *s.config.truth;
  for (const auto& e : r.estimates) {
    EXPECT_NEAR(e.a[0], truth.a[0], 4 * e.se_a[0]);
    EXPECT_NEAR(e.b[0], truth.b[0], 4 * e.se_b[0]);
    const auto& F = e.scheme == est::Scheme::kDescending ? truth.F_d : truth.F_a;
    for (std::size_t j = 0; j < 6; ++j) EXPECT_NEAR(e.F[j], F[j], 0.1) << "scheme " << int(e.scheme) << " j " << j;
  }
  EXPECT_EQ(r.cross.disagree, 0) << "max z " << r.cross.max_z;
  // The interval check (4 periods of 2 x 36 samples) ran before the DIS step experiment.
  EXPECT_EQ(r.cost.samples, 4u * 72 + 2 * 2001 + 2 * 2000);
}

// Fig. 5: a backlash whose play is wider than the interval freezes after one cycle; the firmware must refuse.
fw::RunDesign narrow_interval_design() {
  fw::RunDesign d = fw::kDisPaperRun;
  d.v_min = -0.5f;
  d.v_max = 0.5f;
  d.V_d = {-0.5f, -0.3f, -0.1f, 0.1f, 0.2f, 0.3f};
  d.V_a = {0.5f, 0.3f, 0.1f, -0.1f, -0.2f, -0.3f};
  return d;
}

TEST(FirmwareOnHostBoard, RefusesAnIntervalTooNarrowForTheBacklash) {
  sim::Scenario s = sim::find_scenario("dis_paper");
  s.config.v_min = -0.5;
  s.config.v_max = 0.5;
  s.initial_output = -1.5;  // start on the ascendent border C_a(v) = v - 1 at v_min
  s.make_operator = [] {
    return std::make_unique<sim::BacklashOperator>(sim::Border::from_table({{-0.5, -1.5}, {0.5, -0.5}}),
                                                   sim::Border::from_table({{-0.5, 0.5}, {0.5, 1.5}}));
  };
  s.noise_variance = 1.0;
  sim::ScenarioBoard board = sim::make_scenario_board(s, 1);
  fw::IdentificationSequencer<sim::ScenarioBoard> firmware(board, narrow_interval_design());
  EXPECT_EQ(firmware.run(), fw::RunStatus::kIntervalTooNarrow);
  EXPECT_EQ(reports_of(board).done, static_cast<int>(fw::RunStatus::kIntervalTooNarrow));
  EXPECT_EQ(board.exchanges().size(), 4u * 72);  // it stopped after the check
}


TEST(FirmwareOnHostBoard, CrossCheckFlagsAPlantThatIsNotSwitchOrBacklash) {
  // Remark 3b: with first-order dynamics before the switch (lambda = 0.6), the operator seen by the experiments
  // is no longer a switch, and the two schemes estimate different linear parts.
  sim::Scenario s = sim::find_scenario("ais_paper");
  const auto inner = s.make_operator;
  s.make_operator = [inner] { return std::make_unique<sim::InputLagOperator>(inner(), 0.6); };
  sim::ScenarioBoard board = sim::make_scenario_board(s, 1);
  fw::IdentificationSequencer<sim::ScenarioBoard> firmware(board, fw::kAisPaperRun);
  (void)firmware.run();
  const Reports r = reports_of(board);
  EXPECT_EQ(r.cross.disagree, 1) << "max z " << r.cross.max_z;
}

// A board whose actuator reaches only [low, high] (a DAC's range): the firmware must refuse a design beyond it
// before actuating anything, and run one within it.
class RangedActuatorBoard : public sim::ScenarioBoard {
 public:
  RangedActuatorBoard(sim::ScenarioBoard board, float low, float high)
      : sim::ScenarioBoard(std::move(board)), low_(low), high_(high) {}
  float actuator_low() const { return low_; }
  float actuator_high() const { return high_; }

 private:
  float low_, high_;
};

TEST(FirmwareOnHostBoard, RefusesADesignBeyondTheBoardsActuatorRange) {
  static_assert(hal::Board<RangedActuatorBoard> && hal::LimitsActuatorRange<RangedActuatorBoard>);
  const sim::Scenario& s = sim::find_scenario("ais_paper");  // [v_m, v_M] = [-2, 2]
  for (const auto& [low, high] : {std::pair{-2.0F, 1.99F}, std::pair{-1.99F, 2.0F}}) {
    RangedActuatorBoard board(sim::make_scenario_board(s, 1), low, high);
    fw::IdentificationSequencer<RangedActuatorBoard> firmware(board, fw::kAisPaperRun);
    EXPECT_EQ(firmware.run(), fw::RunStatus::kDesignRejected) << low << " " << high;
    EXPECT_EQ(firmware.design_status(), fw::DesignStatus::kOutsideActuatorRange);
    EXPECT_TRUE(board.exchanges().empty());
  }
  RangedActuatorBoard board(sim::make_scenario_board(s, 1), -2.0F, 2.0F);  // the interval itself: accepted
  fw::IdentificationSequencer<RangedActuatorBoard> firmware(board, fw::kAisPaperRun);
  EXPECT_EQ(firmware.run(), fw::RunStatus::kOk);
  EXPECT_EQ(firmware.design_status(), fw::DesignStatus::kOk);
}

TEST(FirmwareMessages, RecordSizesAndNames) {
  // The size the sequencer's static_assert checks is the size encode() writes.
  fw::EstimateRecord e;
  e.n = 2;
  e.m = 6;
  hal::link::PayloadWriter w;
  e.encode(w);
  EXPECT_TRUE(w.ok());
  EXPECT_EQ(w.size(), fw::EstimateRecord::encoded_size(2, 6));
  // The largest design the image accepts (n = 4, m = 10) fits one frame: 4 bytes + 4 (2 + 4 n + m) = 116 <= 128.
  e.n = fw::kMaxRecordOrder;
  e.m = fw::kMaxRecordPoints;
  hal::link::PayloadWriter big;
  e.encode(big);
  EXPECT_TRUE(big.ok());
  EXPECT_EQ(big.size(), 116u);
  hal::link::PayloadWriter c;
  fw::CostRecord{}.encode(c);
  EXPECT_EQ(c.size(), fw::CostRecord::kEncodedSize);
  // The cycle totals are 64-bit on the wire: 2^28 samples at ~300 cycles each (8.1e10) do not fit 32 bits.
  fw::CostRecord long_run;
  long_run.update_cycles = (std::uint64_t{1} << 28) * 300U;
  long_run.solve_cycles = std::uint64_t{0xFFFF'FFFF} + 2U;
  long_run.updates = 1U << 28;
  long_run.bad_sensor_values = 9;
  hal::link::PayloadWriter lw;
  long_run.encode(lw);
  ASSERT_TRUE(lw.ok());
  fw::CostRecord decoded;
  ASSERT_TRUE(decoded.decode(hal::link::PayloadReader(lw.data(), lw.size())));
  EXPECT_EQ(decoded.update_cycles, 80'530'636'800U);
  EXPECT_EQ(decoded.solve_cycles, 4'294'967'297U);
  EXPECT_EQ(decoded.updates, 1U << 28);
  EXPECT_EQ(decoded.bad_sensor_values, 9U);
  hal::link::PayloadWriter x;
  fw::CrossCheckRecord{}.encode(x);
  EXPECT_EQ(x.size(), fw::CrossCheckRecord::kEncodedSize);

  // The scheme byte is est::Scheme on the wire, as before (0 = DIS, 1 = AIS); anything else is refused.
  e.n = 2;
  e.m = 6;
  e.scheme = est::Scheme::kAscending;
  hal::link::PayloadWriter ws;
  e.encode(ws);
  EXPECT_EQ(ws.data()[0], 1);
  fw::EstimateRecord back;
  ASSERT_TRUE(back.decode(hal::link::PayloadReader(ws.data(), ws.size())));
  EXPECT_EQ(back.scheme, est::Scheme::kAscending);
  std::vector<std::uint8_t> bad(ws.data(), ws.data() + ws.size());
  bad[0] = 2;
  EXPECT_FALSE(back.decode(hal::link::PayloadReader(bad.data(), bad.size())));

  static_assert(std::string_view(fw::to_string(fw::RunStatus::kOk)) == "ok");
  EXPECT_STREQ(fw::to_string(fw::RunStatus::kIntervalTooNarrow), "interval too narrow");
  EXPECT_STREQ(fw::to_string(fw::Stage::kPulseA), "AP pulse experiment");
}

TEST(FirmwareOnHostBoard, StartQueryAndStopCommands) {
  const sim::Scenario& s = sim::find_scenario("ais_paper");
  sim::ScenarioBoard board = sim::make_scenario_board(s, 1);
  fw::IdentificationSequencer<sim::ScenarioBoard> firmware(board);  // waits for a design and a start
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(firmware.step());
  EXPECT_EQ(firmware.stage(), fw::Stage::kIdle);
  EXPECT_TRUE(board.exchanges().empty());
  const auto query = command(hal::link::Command::kQuery);
  board.link_input(query.data(), query.size());
  ASSERT_TRUE(firmware.step());
  auto frames = frames_of(board.link_output());
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, MessageType::kStatus);
  EXPECT_EQ(frames[0].payload[0], static_cast<std::uint8_t>(fw::Stage::kIdle));

  const auto design = test::design_frame(fw::kAisPaperRun);
  board.link_input(design.data(), design.size());
  const auto start = command(hal::link::Command::kStart);
  board.link_input(start.data(), start.size());
  for (int i = 0; i < 500; ++i) ASSERT_TRUE(firmware.step());
  EXPECT_EQ(firmware.stage(), fw::Stage::kStepD);
  const auto stop = command(hal::link::Command::kStop);
  board.link_input(stop.data(), stop.size());
  EXPECT_EQ(firmware.run(), fw::RunStatus::kStopped);
  EXPECT_LT(board.exchanges().size(), 600u);
  EXPECT_EQ(reports_of(board).done, static_cast<int>(fw::RunStatus::kStopped));
}

// kStartStreamSamples on a board whose link writes do not wait: every sample goes out as measured, in blocks that
// never span a stage change, and the blocks are exactly the board's exchanges, with the samples the firmware set aside
// (here NaN readings at two chosen samples) flagged. Without the flag nothing is streamed.
TEST(FirmwareOnHostBoard, StreamsEverySampleAsMeasuredWhenAskedTo) {
  static_assert(hal::BuffersLinkWrites<NanSensorBoard>);
  const sim::Scenario& s = sim::find_scenario("dis_paper");  // a backlash: the interval check is streamed too
  const std::vector<std::size_t> nan_at{100, 2500};
  for (const bool stream : {true, false}) {
    NanSensorBoard board(sim::make_scenario_board(s, 3), nan_at);
    fw::IdentificationSequencer<NanSensorBoard> firmware(board);
    const auto design = test::design_frame(fw::kDisPaperRun);
    board.link_input(design.data(), design.size());
    const std::uint8_t flags = stream ? hal::link::kStartStreamSamples : 0;
    const auto start = command(hal::link::Command::kStart, {flags});
    board.link_input(start.data(), start.size());
    EXPECT_EQ(firmware.run(), fw::RunStatus::kOk);
    std::vector<std::pair<float, float>> streamed;
    std::vector<std::size_t> set_aside;
    std::vector<std::uint32_t> stages_at;  // the sample count at each kStatus
    for (const hal::link::Frame& f : frames_of(board.link_output())) {
      if (f.type == MessageType::kStatus) {
        auto r = f.reader();
        (void)r.u8();
        stages_at.push_back(r.u32());
      }
      if (f.type != MessageType::kSamples) continue;
      fw::SampleBlock block;
      ASSERT_TRUE(block.decode(f.reader()));
      ASSERT_EQ(block.first, streamed.size());  // in order, none missing
      for (std::size_t k = 0; k < block.count; ++k) {
        if ((block.set_aside & (1U << k)) != 0U) set_aside.push_back(streamed.size());
        streamed.emplace_back(block.v[k], block.y[k]);
      }
      // Within one stage: no status count falls strictly inside the block.
      for (const std::uint32_t at : stages_at) EXPECT_FALSE(at > block.first && at < block.first + block.count);
    }
    if (!stream) {
      EXPECT_TRUE(streamed.empty());
      continue;
    }
    ASSERT_EQ(streamed.size(), board.exchanges().size());
    EXPECT_EQ(set_aside, nan_at);
    for (std::size_t k = 0; k < streamed.size(); ++k) {
      EXPECT_EQ(streamed[k].first, board.exchanges()[k].v) << k;
      if (k == nan_at[0] || k == nan_at[1]) {
        EXPECT_TRUE(std::isnan(streamed[k].second)) << k;  // the reading the sensor gave
      } else {
        EXPECT_EQ(streamed[k].second, board.exchanges()[k].y) << k;
      }
    }
  }
}

}  // namespace
