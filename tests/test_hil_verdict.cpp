// The host-in-the-loop rules without QEMU: judge() on hand-made results (lost frames, empty estimates, differences
// from the host build, fault injection), the scenario -> firmware configuration table, the QEMU command line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "lashid/hil/hil.hpp"
#include "lashid/hil/verdict.hpp"
#include "lashid/sim/scenario.hpp"

namespace {

using namespace lashid;
using sim::HilFailure;

fw::EstimateRecord estimate(est::Scheme scheme, float a1) {
  fw::EstimateRecord e;
  e.scheme = scheme;
  e.n = 2;
  e.m = 6;
  e.a = {a1, 0.21f};
  e.b = {70.5f, -35.25f};
  e.F = {-1, -0.9f, -0.7f, -0.2f, 0.3f, 0.8f};
  return e;
}

// What a good run of the firmware in QEMU delivers.
sim::HilResult good_run() {
  sim::HilResult r;
  r.estimates = {estimate(est::Scheme::kDescending, 1.0f), estimate(est::Scheme::kAscending, 1.0f)};
  r.cross_check = fw::CrossCheckRecord{};
  r.cost = fw::CostRecord{};
  r.cost->samples = 8290;  // the firmware's count: every sample the host played
  r.done = static_cast<int>(fw::RunStatus::kOk);
  r.qemu_exit = 0;
  r.samples = 8290;
  return r;
}

TEST(HilVerdict, AGoodRunPasses) {
  const sim::HilResult r = good_run();
  const sim::HilVerdict v = sim::judge(r, &r, {});
  EXPECT_TRUE(v.ok());
  ASSERT_TRUE(v.dis && v.ais);
  EXPECT_EQ(*v.dis, 0u);
  EXPECT_EQ(*v.ais, 1u);
  ASSERT_TRUE(v.host);
  EXPECT_TRUE(v.host->equal);
  EXPECT_EQ(v.host->max_relative_difference, 0.0);
  EXPECT_FALSE(v.fault_injection);
}

TEST(HilVerdict, LostEstimatesWithACrossCheckAreANamedFailure) {
  sim::HilResult r = good_run();
  r.estimates.clear();  // both kEstimate frames lost, the kCrossCheck arrived
  const sim::HilVerdict v = sim::judge(r, nullptr, {});
  EXPECT_FALSE(v.ok());
  EXPECT_TRUE(v.has(HilFailure::kEstimateMissing));
  EXPECT_FALSE(v.dis || v.ais);
  EXPECT_EQ(sim::cross_check_parameter(r.cross_check->worst, 0), "parameter 0");  // no n to name it by
}

TEST(HilVerdict, AnEmptyEstimateIsANamedFailure) {
  sim::HilResult r = good_run();
  r.estimates[0].n = 0;
  const sim::HilVerdict v = sim::judge(r, nullptr, {});
  EXPECT_TRUE(v.has(HilFailure::kEstimateEmpty));
  EXPECT_FALSE(v.has(HilFailure::kEstimateMissing));  // it arrived, it is unusable
  EXPECT_FALSE(v.dis);
  ASSERT_TRUE(v.ais);
}

TEST(HilVerdict, RunStatusAndQemuExit) {
  sim::HilResult r = good_run();
  r.done = -1;
  EXPECT_TRUE(sim::judge(r, nullptr, {}).has(HilFailure::kNoDoneReport));
  r.done = static_cast<int>(fw::RunStatus::kSensorFault);
  EXPECT_TRUE(sim::judge(r, nullptr, {}).has(HilFailure::kRunFailed));
  r = good_run();
  r.qemu_exit = -1;  // unknown: a failure when QEMU is ours, fine when attached to the user's
  EXPECT_TRUE(sim::judge(r, nullptr, {}).has(HilFailure::kQemuExit));
  sim::JudgeOptions attached;
  attached.attached = true;
  EXPECT_TRUE(sim::judge(r, nullptr, attached).ok());
}

TEST(HilVerdict, DifferentFromTheHostBuild) {
  const sim::HilResult r = good_run();
  sim::HilResult host = good_run();
  host.estimates[1].a[0] = 1.5f;
  sim::HilVerdict v = sim::judge(r, &host, {});
  EXPECT_TRUE(v.has(HilFailure::kDifferentFromHost));
  EXPECT_GT(v.host->max_relative_difference, 1e-3);
  host = good_run();
  host.samples = 8289;
  EXPECT_TRUE(sim::judge(r, &host, {}).has(HilFailure::kDifferentFromHost));
  host = good_run();
  host.estimates[0].a[0] = std::nanf("");  // a NaN is a difference, not skipped
  EXPECT_TRUE(sim::judge(r, &host, {}).has(HilFailure::kDifferentFromHost));
  // Asked for and not made: a failure, so that the CTests of --compare-host cannot pass without the comparison.
  sim::JudgeOptions asked;
  asked.compare_host = true;
  EXPECT_TRUE(sim::judge(r, nullptr, asked).has(HilFailure::kDifferentFromHost));
  EXPECT_TRUE(sim::judge(r, &r, asked).ok());
}

TEST(HilVerdict, EveryDamagedFrameMustBeReRequested) {
  sim::HilResult r = good_run();
  r.corrupted_by_host = 10;
  r.cost->retries = 9;
  r.cost->link_errors = 10;
  sim::HilVerdict v = sim::judge(r, nullptr, {});
  EXPECT_TRUE(v.has(HilFailure::kDamagedFramesMissed));
  r.cost->retries = 10;
  v = sim::judge(r, nullptr, {});
  EXPECT_TRUE(v.ok());
  ASSERT_TRUE(v.fault_injection);
  EXPECT_TRUE(v.fault_injection->all_detected);
}

// A board with its own sensor attached as if it played the host's plant: the firmware measured 9034 samples, the
// host played none, and the estimates are not the plant's. A count off by one either way fails too.
TEST(HilVerdict, SamplesTheHostNeverPlayedAreANamedFailure) {
  sim::HilResult r = good_run();
  r.samples = 0;
  r.cost->samples = 9034;
  EXPECT_TRUE(sim::judge(r, nullptr, {}).has(HilFailure::kPlantNotPlayed));
  r.samples = 9035;
  EXPECT_TRUE(sim::judge(r, nullptr, {}).has(HilFailure::kPlantNotPlayed));
  // A physical plant: the host plays nothing, and that is no failure.
  sim::JudgeOptions physical;
  physical.plant_played = false;
  r.samples = 0;
  EXPECT_TRUE(sim::judge(r, nullptr, physical).ok());
}

// A physical plant recorded from the firmware's stream: a sample block lost on the link is never sent again, so a
// stream shorter than the firmware's count is an incomplete recording, not a pass.
TEST(HilVerdict, AStreamShorterThanTheRunIsANamedFailure) {
  sim::HilResult r = good_run();
  sim::JudgeOptions streamed;
  streamed.plant_played = false;
  streamed.streamed = true;
  r.cost->samples = 9034;
  r.samples = 9034 - 14;  // one full block lost
  EXPECT_TRUE(sim::judge(r, nullptr, streamed).has(HilFailure::kRecordingIncomplete));
  r.samples = 9034;
  EXPECT_TRUE(sim::judge(r, nullptr, streamed).ok());
}

TEST(HilVerdict, CrossCheckParameterNames) {
  EXPECT_EQ(sim::cross_check_parameter(0, 2), "a1");
  EXPECT_EQ(sim::cross_check_parameter(1, 2), "a2");
  EXPECT_EQ(sim::cross_check_parameter(3, 2), "b2");
}

TEST(RunDesignOf, TheScenariosDesignAsTheFirmwareHoldsIt) {
  // dis_paper: Section 3.5's design, a backlash (interval check), no validation phase.
  const fw::RunDesign d = sim::run_design_of(sim::find_scenario("dis_paper"));
  EXPECT_EQ(d.op, fw::OperatorKind::kBacklash);
  EXPECT_EQ(d.n, 2);
  EXPECT_EQ(d.m, 6);
  EXPECT_EQ(d.v_min, -3.0f);
  EXPECT_EQ(d.v_max, 4.0f);
  EXPECT_EQ(d.V_d[3], 1.0f);
  EXPECT_EQ(d.V_a[5], -2.0f);
  EXPECT_EQ(d.step_length, 2000u);
  EXPECT_EQ(d.pulse_length_d, 2000u);
  EXPECT_EQ(d.val_length, 0u);
  EXPECT_EQ(sim::run_design_of(sim::find_scenario("ais_paper")).pulse_length_a, 8000u);
  // A design the firmware would refuse is refused here, naming the rule.
  sim::Scenario s = sim::find_scenario("ais_paper");
  s.pulse_length_d = 20;  // < 2T = 36
  try {
    (void)sim::run_design_of(s);
    FAIL() << "a design the firmware refuses must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pulse_length_d"), std::string::npos) << e.what();
  }
  s = sim::find_scenario("ais_paper");
  s.step_length_a = 1000;  // the firmware has one L for both step experiments
  EXPECT_THROW((void)sim::run_design_of(s), std::invalid_argument);
}

TEST(QemuCommandLine, HasTheCommonFlagsOnceAndIcountOnRequest) {
  sim::QemuCommand c;
  c.machine = "mps2-an500";
  c.serials = {"null", "unix:/tmp/x.sock"};
  c.kernel = "image.elf";
  std::vector<std::string> args = sim::qemu_command_line(c);
  const std::vector<std::string> expected{"qemu-system-arm", "-machine", "mps2-an500", "-nographic", "-monitor",
                                          "none", "-semihosting-config", "enable=on,target=native", "-serial",
                                          "null", "-serial", "unix:/tmp/x.sock", "-kernel", "image.elf"};
  EXPECT_EQ(args, expected);
  c.icount = true;
  args = sim::qemu_command_line(c);
  const auto icount = std::find(args.begin(), args.end(), "-icount");
  ASSERT_NE(icount, args.end());
  EXPECT_EQ(*(icount + 1), "shift=0");
}

}  // namespace
