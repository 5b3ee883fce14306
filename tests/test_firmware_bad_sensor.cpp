// The firmware on the host board with a bad sensor: NaN readings, finite readings too large for the estimator, a
// sensor open during the interval check, values outside the config's sensor range, a scheme whose step experiment
// never gets a usable reading. The device leaves each out (or names the fault), and the host's identification of
// the same data must leave out the same rows (lashid hil's check of a recording).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "firmware_host_support.hpp"
#include "lashid/firmware/paper_run_designs.hpp"
#include "lashid/firmware/sequencer.hpp"
#include "lashid/hil/hil.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/io/data_error.hpp"
#include "lashid/sim/scenario.hpp"

namespace {

using namespace lashid;
using test::expect_cli_estimates;
using test::NanSensorBoard;
using test::reports_of;
using test::Reports;

// A sensor that gives nothing usable during the interval check (open: NaN; or one finite reading too large for the
// float32 sums, 1e20, among good ones at each end) is the sensor's fault, not the interval's: every NaN left the
// means at 0 / 0 and the run said "interval too narrow"; one 1e20 reading overflowed the spread to inf and said it
// too. The interval check's 288 samples are run samples 0..287 (4 periods of 2 x 36).
TEST(FirmwareOnHostBoard, TheIntervalCheckTellsABadSensorFromANarrowInterval) {
  const sim::Scenario& s = sim::find_scenario("dis_paper");
  std::vector<std::size_t> all(288);
  for (std::size_t t = 0; t < all.size(); ++t) all[t] = t;
  NanSensorBoard open(sim::make_scenario_board(s, 3), all);
  fw::IdentificationSequencer<NanSensorBoard> silent(open, fw::kDisPaperRun);
  EXPECT_EQ(silent.run(), fw::RunStatus::kSensorFault);
  EXPECT_EQ(open.exchanges().size(), 288u);  // it stopped after the check
  // Samples 100 (a v_max half, its held part) and 128 (a v_min half): one 1e20 each; the check passes on the others.
  NanSensorBoard spikes(sim::make_scenario_board(s, 3), {100, 128}, 1e20F);
  fw::IdentificationSequencer<NanSensorBoard> firmware(spikes, fw::kDisPaperRun);
  EXPECT_EQ(firmware.run(), fw::RunStatus::kOk);
}


TEST(FirmwareOnHostBoard, CountsTheSamplesTheEstimatorRejects) {
  const sim::Scenario& s = sim::find_scenario("ais_paper");
  // Sample 100 of the DIS step experiment; pulse samples 1000 and 5000 of the DP experiment (t = 0 at 2001).
  NanSensorBoard board(sim::make_scenario_board(s, 7), {100, 2001 + 1000, 2001 + 5000});
  static_assert(hal::Board<NanSensorBoard>);
  fw::IdentificationSequencer<NanSensorBoard> firmware(board, fw::kAisPaperRun);
  EXPECT_EQ(firmware.run(), fw::RunStatus::kOk);  // the least squares on the rows used
  // The step sample, and per NaN pulse sample its own row and the n = 2 rows that hold it as a lag.
  EXPECT_EQ(firmware.cost().rejected_samples, 1u + 2u * (1 + 2));
  EXPECT_EQ(reports_of(board).cost.rejected_samples, firmware.cost().rejected_samples);
  // Each NaN is also counted as a bad sensor value, once.
  EXPECT_EQ(firmware.cost().bad_sensor_values, 3u);
  EXPECT_EQ(reports_of(board).cost.bad_sensor_values, 3u);
}

// The device leaves out a bad reading and every row that holds it as a lag; `identify --float` with
// leave_out_unusable_y (hil's check of a streamed recording) must leave out the same rows and give the same
// estimates, whether the bad value falls in a row's y or only in its lags. Without the option it is an error naming
// it. Bad is NaN (a reading the firmware set aside) or finite but beyond the estimator's kMaxSampleMagnitude, which
// the firmware's sensor test lets through when the design gives no sensor range: the estimator leaves it out all
// the same, and the host's check must too (it threw before).
void expect_host_leaves_out_what_the_device_did(float bad) {
  const sim::Scenario& s = sim::find_scenario("ais_paper");  // DIS pulses are run samples 2001..10000
  const std::vector<std::size_t> nan_at{2001 + 1000, 2001 + 1002, 2001 + 5000, 12002 + 3000};
  NanSensorBoard board(sim::make_scenario_board(s, 7), nan_at, bad);
  fw::IdentificationSequencer<NanSensorBoard> firmware(board, fw::kAisPaperRun);
  ASSERT_EQ(firmware.run(), fw::RunStatus::kOk);
  sim::SimulationOptions options;
  options.seed = 7;
  options.validation_phase = false;
  const sim::Recording clean = sim::simulate(s, options);
  sim::Recording rec;
  std::size_t k = 0;
  for (const sim::Phase p : clean.order()) {
    for (const sim::Sample& x : clean.phase(p)) {
      const bool aside = std::find(nan_at.begin(), nan_at.end(), k++) != nan_at.end();
      rec.append(p, x.v, aside ? static_cast<double>(bad) : x.y);
    }
  }
  sim::IdentifyOptions f32;
  f32.precision = sim::Precision::kFloat;
  EXPECT_THROW((void)sim::identify_scheme(s.config, rec, est::Scheme::kDescending, f32, "rec"), sim::DataError);
  f32.leave_out_unusable_y = true;
  const Reports r = reports_of(board);
  expect_cli_estimates(r, s.config, rec, f32);
  // Rows left out: per bad value its own row and the n = 2 rows that lag it; those of 1000 and 1002 overlap in row
  // 1002 (rows 1000-1004): 5 + 3 + 3.
  EXPECT_EQ(r.cost.rejected_samples, 11u);
}

TEST(FirmwareOnHostBoard, TheHostLeavesOutTheSetAsideSamplesAsTheDeviceDoes) {
  expect_host_leaves_out_what_the_device_did(std::nanf(""));
}

// Every reading of the AIS step experiment bad: the AIS has no step mean, its estimate fails, and its record must
// say so with no values. Before, it carried the DIS's a, b and F (what the estimate object still held) under a
// failed status: in `lashid hil` a second estimate agreeing perfectly with the first.
TEST(FirmwareOnHostBoard, AFailedSchemeReportsItsStatusAndNoValues) {
  const sim::Scenario& s = sim::find_scenario("ais_paper");  // the AIS step experiment is run samples 10001..12001
  std::vector<std::size_t> bad;
  for (std::size_t t = 10001; t <= 12001; ++t) bad.push_back(t);
  NanSensorBoard board(sim::make_scenario_board(s, 7), bad);
  fw::IdentificationSequencer<NanSensorBoard> firmware(board, fw::kAisPaperRun);
  (void)firmware.run();
  const Reports r = reports_of(board);
  ASSERT_EQ(r.estimates.size(), 2U);
  const fw::EstimateRecord& dis = r.estimates[0];
  const fw::EstimateRecord& ais = r.estimates[1];
  ASSERT_EQ(dis.scheme, est::Scheme::kDescending);
  EXPECT_EQ(static_cast<est::Status>(dis.status), est::Status::kOk);
  EXPECT_TRUE(std::isfinite(dis.a[0]) && std::isfinite(dis.F[0]));
  ASSERT_EQ(ais.scheme, est::Scheme::kAscending);
  EXPECT_EQ(static_cast<est::Status>(ais.status), est::Status::kStepMeanMissing);
  ASSERT_EQ(ais.n, 2U);  // ais_paper's n and m: the loops below check every value
  ASSERT_EQ(ais.m, 6U);
  for (std::size_t i = 0; i < ais.n; ++i) {
    EXPECT_TRUE(std::isnan(ais.a[i]) && std::isnan(ais.b[i]) && std::isnan(ais.se_a[i]) && std::isnan(ais.se_b[i]))
        << i;
  }
  for (std::size_t j = 0; j < ais.m; ++j) EXPECT_TRUE(std::isnan(ais.F[j])) << j;
  EXPECT_TRUE(std::isnan(ais.ybar0));
  EXPECT_TRUE(std::isnan(ais.noise_variance));
  EXPECT_EQ(r.cross.max_z, -1.0F);  // no cross-check without both schemes
}

// identify applies the config's sensor_range as the device does: each y outside it is left out with its lag rows,
// which is the same estimate as that y made NaN under leave_out_unusable_y (the path checked against the firmware
// above), in both precisions; the count is the recording's own (y above the bound, counted here).
TEST(IdentifyWithASensorRange, LeavesOutTheValuesOutsideAsTheDeviceDoes) {
  const sim::Scenario& s = sim::find_scenario("ais_paper");
  sim::SimulationOptions options;
  options.seed = 7;
  options.validation_phase = false;
  const sim::Recording rec = sim::simulate(s, options);
  // A bound that the AIS phases' largest outputs pass: the top 0.2 % of their y.
  std::vector<double> ys;
  for (const sim::Phase p : {sim::Phase::kStepA, sim::Phase::kAis}) {
    for (const sim::Sample& x : rec.phase(p)) ys.push_back(x.y);
  }
  std::sort(ys.begin(), ys.end());
  const double hi = ys[ys.size() - ys.size() / 500];
  const std::int64_t count = std::count_if(ys.begin(), ys.end(), [&](double y) { return y > hi; });
  ASSERT_GT(count, 5);
  sim::ExperimentConfig ranged = s.config;
  ranged.sensor_range = std::array<double, 2>{-1e6, hi};
  sim::Recording as_nan;
  for (const sim::Phase p : rec.order()) {
    for (const sim::Sample& x : rec.phase(p)) as_nan.append(p, x.v, x.y > hi ? std::nan("") : x.y);
  }
  for (const sim::Precision precision : {sim::Precision::kFloat, sim::Precision::kDouble}) {
    sim::IdentifyOptions plain;
    plain.precision = precision;
    const sim::SchemeResult r = sim::identify_scheme(ranged, rec, est::Scheme::kAscending, plain, "rec");
    sim::IdentifyOptions nan = plain;
    nan.leave_out_unusable_y = true;
    const sim::SchemeResult e = sim::identify_scheme(s.config, as_nan, est::Scheme::kAscending, nan, "rec");
    EXPECT_EQ(r.out_of_sensor_range, count);
    EXPECT_EQ(e.out_of_sensor_range, 0);
    ASSERT_EQ(r.status, est::Status::kOk);
    EXPECT_EQ(r.rows, e.rows);
    EXPECT_EQ(r.theta, e.theta);
    EXPECT_EQ(r.F, e.F);
    // Without the range, the same recording gives another estimate (the test can fail).
    EXPECT_NE(sim::identify_scheme(s.config, rec, est::Scheme::kAscending, plain, "rec").theta, r.theta);
  }
}

TEST(FirmwareOnHostBoard, TheHostLeavesOutAFiniteReadingTooLargeForTheEstimatorAsTheDeviceDoes) {
  static_assert(1e20F > est::kMaxSampleMagnitude<float>);
  expect_host_leaves_out_what_the_device_did(1e20F);
}

}  // namespace
