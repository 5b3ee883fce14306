// What keeps a run right on a link that loses bytes (issue 14): the firmware holds its reports after the run and
// sends them again on request until the host has them all; bad sensor values are counted and never estimated from;
// a command link that keeps failing or overruns costs link errors and the cut frame only; the frame decoder loses
// no more than the frame that was damaged; the host's fault injection draws what it says it draws. Expected numbers come from the protocol's definitions and
// the board's own exchange log, not from the code under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "lashid/firmware/paper_run_designs.hpp"
#include "lashid/firmware/sequencer.hpp"
#include "lashid/hil/hil.hpp"
#include "lashid/hil/link_faults.hpp"
#include "lashid/sim/scenario.hpp"
#include "firmware_reports.hpp"
#include "link_frames.hpp"

namespace {

using namespace lashid;
using hal::link::Command;
using hal::link::MessageType;
using test::command;
using test::frames_of;

// A board whose clock ticks once per cycles() call, at 1000 cycles per second: the hold time is then a step count.
class CountingClockBoard : public sim::ScenarioBoard {
 public:
  static constexpr std::uint32_t kCyclesPerSecond = 1000;
  explicit CountingClockBoard(sim::ScenarioBoard board) : sim::ScenarioBoard(std::move(board)) {}
  std::uint32_t cycles() const { return ++clock_; }

 private:
  mutable std::uint32_t clock_ = 0;
};
static_assert(hal::Board<CountingClockBoard> && hal::KnowsCycleRate<CountingClockBoard>);

std::size_t count(const std::vector<hal::link::Frame>& frames, MessageType type) {
  return static_cast<std::size_t>(
      std::count_if(frames.begin(), frames.end(), [&](const hal::link::Frame& f) { return f.type == type; }));
}

template <class Board>
void send(Board& board, const std::vector<std::uint8_t>& bytes) {
  board.link_input(bytes.data(), bytes.size());
}

template <class Board>
void run_to_done(fw::IdentificationSequencer<Board>& firmware) {
  while (firmware.stage() != fw::Stage::kDone) ASSERT_TRUE(firmware.step());
}

// On the counting clock (the hold is 2,000 of its ticks, and each step below takes a few): with the host board's
// wall clock the steps below had to come within the 2 s hold, which a stall under load could break.
TEST(ReportHold, TheReportsAreSentAgainOnRequestUntilTheHostFinishes) {
  CountingClockBoard board(sim::make_scenario_board(sim::find_scenario("ais_paper"), 1));
  fw::IdentificationSequencer<CountingClockBoard> firmware(board);
  send(board, test::design_frame(fw::kAisPaperRun));
  send(board, command(Command::kStart, {hal::link::kStartHoldReports}));
  run_to_done(firmware);
  const auto first = frames_of(board.link_output());
  // Once: two estimates, the cross-check, the cost, kDone.
  EXPECT_EQ(count(first, MessageType::kEstimate), 2u);
  EXPECT_EQ(count(first, MessageType::kDone), 1u);
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(firmware.step()) << "the run must hold its reports";

  send(board, command(Command::kReport));
  ASSERT_TRUE(firmware.step());
  const auto again = frames_of(board.link_output());
  EXPECT_EQ(count(again, MessageType::kEstimate), 4u);
  EXPECT_EQ(count(again, MessageType::kCrossCheck), 2u);
  EXPECT_EQ(count(again, MessageType::kCost), 2u);
  EXPECT_EQ(count(again, MessageType::kDone), 2u);
  // The second copy is the first, byte for byte (the same records, not recomputed).
  const std::size_t reports = 5;
  for (std::size_t k = 0; k < reports; ++k) {
    const auto& a = again[again.size() - 2 * reports + k];
    const auto& b = again[again.size() - reports + k];
    EXPECT_EQ(a.type, b.type);
    EXPECT_TRUE(std::equal(a.payload.begin(), a.payload.begin() + a.size, b.payload.begin()));
  }
  send(board, command(Command::kFinish));
  EXPECT_FALSE(firmware.step());
  EXPECT_EQ(firmware.result(), fw::RunStatus::kOk);
}

TEST(ReportHold, WithoutTheFlagTheRunEndsWithItsReports) {
  sim::ScenarioBoard board = sim::make_scenario_board(sim::find_scenario("ais_paper"), 1);
  fw::IdentificationSequencer<sim::ScenarioBoard> firmware(board);
  send(board, test::design_frame(fw::kAisPaperRun));
  send(board, command(Command::kStart));
  EXPECT_EQ(firmware.run(), fw::RunStatus::kOk);
  EXPECT_FALSE(firmware.step());
  // A report request after the end is not answered with reports.
  send(board, command(Command::kReport));
  const std::size_t before = count(frames_of(board.link_output()), MessageType::kEstimate);
  (void)firmware.step();
  EXPECT_EQ(count(frames_of(board.link_output()), MessageType::kEstimate), before);
}

TEST(ReportHold, EndsAfterTheHoldTimeWhenTheHostIsGone) {
  CountingClockBoard board(sim::make_scenario_board(sim::find_scenario("ais_paper"), 1));
  fw::IdentificationSequencer<CountingClockBoard> firmware(board);
  send(board, test::design_frame(fw::kAisPaperRun));
  send(board, command(Command::kStart, {hal::link::kStartHoldReports}));
  run_to_done(firmware);
  int steps = 0;
  while (firmware.step()) ++steps;
  // One clock tick per step while holding: the hold lasts kReportHoldSeconds * kCyclesPerSecond ticks.
  const int hold = static_cast<int>(fw::IdentificationSequencer<CountingClockBoard>::kReportHoldSeconds) * 1000;
  EXPECT_GE(steps, hold - 5);
  EXPECT_LE(steps, hold);
}

TEST(SensorRange, ValuesOutsideTheDesignsRangeAreCountedAndNotEstimatedFrom) {
  const sim::Scenario& s = sim::find_scenario("ais_paper");
  fw::RunDesign design = fw::kAisPaperRun;
  // A range that the plant's output leaves now and then: its upper bound below the largest outputs of a clean run.
  std::vector<float> ys;
  {
    sim::ScenarioBoard clean = sim::make_scenario_board(s, 3);
    fw::IdentificationSequencer<sim::ScenarioBoard> firmware(clean, design);
    ASSERT_EQ(firmware.run(), fw::RunStatus::kOk);
    for (const auto& e : clean.exchanges()) ys.push_back(e.y);
  }
  std::sort(ys.begin(), ys.end());
  design.sensor_min = ys.front() - 1.0f;
  design.sensor_max = ys[ys.size() * 995 / 1000];
  ASSERT_EQ(fw::check_design(design), fw::DesignStatus::kOk);

  sim::ScenarioBoard board = sim::make_scenario_board(s, 3);
  fw::IdentificationSequencer<sim::ScenarioBoard> firmware(board, design);
  EXPECT_EQ(firmware.run(), fw::RunStatus::kOk);
  // The same plant and inputs: the board's own log says which values were out of range.
  const auto out_of_range = std::count_if(board.exchanges().begin(), board.exchanges().end(), [&](const auto& e) {
    return e.y < design.sensor_min || e.y > design.sensor_max;
  });
  EXPECT_GT(out_of_range, 0);
  EXPECT_EQ(firmware.cost().bad_sensor_values, static_cast<std::uint32_t>(out_of_range));
  EXPECT_GE(firmware.cost().rejected_samples, firmware.cost().bad_sensor_values);

  design.sensor_min = design.sensor_max;
  EXPECT_EQ(fw::check_design(design), fw::DesignStatus::kSensorRangeInvalid);
  design.sensor_min = std::nanf("");
  EXPECT_EQ(fw::check_design(design), fw::DesignStatus::kSensorRangeInvalid);
}

TEST(ByteFaults, NoFaultsAtRateZeroAndOnlyFaultsAtRateOne) {
  std::vector<std::uint8_t> data(1000);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(i * 7);
  sim::ByteFaults clean(0.0, 1, 0);
  std::vector<std::uint8_t> out;
  clean.pass(data.data(), data.size(), out);
  EXPECT_EQ(out, data);
  EXPECT_EQ(clean.counts().injected(), 0u);

  sim::ByteFaults all(1.0, 1, 0);
  out.clear();
  all.pass(data.data(), data.size(), out);
  const sim::FaultCounts& c = all.counts();
  EXPECT_EQ(c.injected(), data.size());
  // Every byte: dropped (0 out), garbled (1 out, one bit differs) or duplicated (2 out).
  EXPECT_EQ(out.size(), data.size() - c.dropped + c.duplicated);
}

TEST(ByteFaults, TheRateAndTheKindsAreThoseAsked) {
  constexpr double kRate = 0.01;
  constexpr std::size_t kBytes = 1'000'000;
  std::vector<std::uint8_t> data(kBytes, 0x5A);
  sim::ByteFaults faults(kRate, 42, 1);
  std::vector<std::uint8_t> out;
  faults.pass(data.data(), data.size(), out);
  const sim::FaultCounts& c = faults.counts();
  // Binomial(n, p): mean n p = 10,000, standard deviation sqrt(n p (1 - p)) = 99.5; 5 sigma either way.
  const double mean = kBytes * kRate, sd = std::sqrt(kBytes * kRate * (1 - kRate));
  EXPECT_NEAR(static_cast<double>(c.injected()), mean, 5 * sd);
  // Each kind a third of the faults: Binomial(k, 1/3), sd = sqrt(k 2/9) = 47 at k = 10,000.
  const double k = static_cast<double>(c.injected()), sd_kind = std::sqrt(k * 2.0 / 9.0);
  for (const std::uint64_t kind : {c.dropped, c.flipped, c.duplicated}) {
    EXPECT_NEAR(static_cast<double>(kind), k / 3, 5 * sd_kind);
  }
  // A garbled byte differs from 0x5A in exactly one bit.
  std::size_t one_bit = 0;
  for (const std::uint8_t b : out) one_bit += b != 0x5A && std::popcount(static_cast<unsigned>(b ^ 0x5A)) == 1;
  EXPECT_EQ(one_bit, c.flipped);
}

TEST(ByteFaults, TheSameSeedGivesTheSameFaultsAndTheDirectionsDiffer) {
  std::vector<std::uint8_t> data(100'000, 0x11);
  const auto faulty = [&](std::uint64_t seed, std::uint64_t stream) {
    sim::ByteFaults f(0.01, seed, stream);
    std::vector<std::uint8_t> out;
    f.pass(data.data(), data.size(), out);
    return out;
  };
  EXPECT_EQ(faulty(5, 2), faulty(5, 2));
  EXPECT_NE(faulty(5, 2), faulty(5, 3));
  EXPECT_NE(faulty(5, 2), faulty(6, 2));
  EXPECT_THROW(sim::ByteFaults(-0.1, 1, 0), std::invalid_argument);
  EXPECT_THROW(sim::ByteFaults(std::nan(""), 1, 0), std::invalid_argument);
}

// A link whose driver keeps reporting an error (a sticky overrun flag that is never cleared): the firmware counts
// the errors and still runs every sample (it used to loop in its poll of the link forever).
class StuckLinkBoard : public sim::ScenarioBoard {
 public:
  explicit StuckLinkBoard(sim::ScenarioBoard board) : sim::ScenarioBoard(std::move(board)) {}
  hal::Status link_read(std::uint8_t&) { return hal::Status::kLinkError; }
};

TEST(FirmwareOnHostBoard, ALinkThatKeepsFailingCostsLinkErrorsNotTheRun) {
  const sim::Scenario& s = sim::find_scenario("ais_paper");
  StuckLinkBoard board(sim::make_scenario_board(s, 7));
  static_assert(hal::Board<StuckLinkBoard>);
  fw::IdentificationSequencer<StuckLinkBoard> firmware(board, fw::kAisPaperRun);
  EXPECT_EQ(firmware.run(), fw::RunStatus::kOk);
  // Every sample of the run on a working link.
  sim::ScenarioBoard working = sim::make_scenario_board(s, 7);
  fw::IdentificationSequencer<sim::ScenarioBoard> reference(working, fw::kAisPaperRun);
  ASSERT_EQ(reference.run(), fw::RunStatus::kOk);
  EXPECT_EQ(board.exchanges().size(), working.exchanges().size());
  // One budget of errors per poll, at least one poll per sample.
  EXPECT_GE(firmware.cost().link_errors,
            static_cast<std::uint32_t>(board.exchanges().size()) *
                static_cast<std::uint32_t>(fw::IdentificationSequencer<StuckLinkBoard>::kPollBudget));
}

// A command link whose UART loses bytes in an overrun and says so (kLinkError) where they went missing: the bytes
// read are given in order, std::nullopt is the overrun.
class OverrunLinkBoard : public sim::ScenarioBoard {
 public:
  explicit OverrunLinkBoard(sim::ScenarioBoard board) : sim::ScenarioBoard(std::move(board)) {}
  std::deque<std::optional<std::uint8_t>> script;
  hal::Status link_read(std::uint8_t& byte) {
    if (script.empty()) return hal::Status::kWouldBlock;
    const std::optional<std::uint8_t> next = script.front();
    script.pop_front();
    if (!next) return hal::Status::kLinkError;
    byte = *next;
    return hal::Status::kOk;
  }
};

TEST(FirmwareOnHostBoard, AnOverrunCostsTheFrameItCutNotTheNext) {
  // A query cut by an overrun after its length byte, then a whole query: the firmware must answer the second. Read
  // on after the overrun, the cut frame would take the second's first bytes as its payload and checksum.
  const sim::Scenario& s = sim::find_scenario("ais_paper");
  OverrunLinkBoard board(sim::make_scenario_board(s, 1));
  static_assert(hal::Board<OverrunLinkBoard>);
  fw::IdentificationSequencer<OverrunLinkBoard> firmware(board);
  const auto query = command(hal::link::Command::kQuery);
  ASSERT_GT(query.size(), 6u);  // sync, sync, type, seq, length, payload..., checksum
  for (std::size_t i = 0; i < 5; ++i) board.script.emplace_back(query[i]);
  board.script.emplace_back(std::nullopt);
  for (std::uint8_t b : query) board.script.emplace_back(b);
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(firmware.step());
  const auto frames = frames_of(board.link_output());
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, MessageType::kStatus);
  EXPECT_EQ(firmware.cost().link_errors, 1u);
}

TEST(FrameDecoder, AFrameCutShortIsAbandonedSoTheNextIsRead) {
  hal::link::PayloadWriter w;
  w.u32(7);
  std::vector<std::uint8_t> a(hal::link::kMaxFrame), b(hal::link::kMaxFrame);
  a.resize(hal::link::encode_frame(MessageType::kMeasurement, 0, w.data(), w.size(), a.data()));
  b.resize(hal::link::encode_frame(MessageType::kStatus, 0, w.data(), w.size(), b.data()));
  a.pop_back();  // the last checksum byte is lost on the line
  const auto frames_after = [&](bool abandon) {
    hal::link::FrameDecoder d;
    int frames = 0;
    for (std::uint8_t x : a) frames += d.push(x) == hal::link::FrameDecoder::Result::kFrame;
    if (abandon) {
      EXPECT_TRUE(d.abandon_partial());
    }
    for (std::uint8_t x : b) frames += d.push(x) == hal::link::FrameDecoder::Result::kFrame;
    return frames;
  };
  EXPECT_EQ(frames_after(false), 0);  // b's first byte completed a's checksum: both lost
  EXPECT_EQ(frames_after(true), 1);
  hal::link::FrameDecoder idle;
  EXPECT_FALSE(idle.abandon_partial());  // nothing under way: nothing counted
  EXPECT_EQ(idle.truncated(), 0u);
}

TEST(FrameDecoder, AGarbledLengthBeyondTheLinksLargestPayloadCostsOneFrame) {
  // The plant port carries 8-byte payloads. A length byte garbled to 120 would make a decoder for any frame read the
  // next 120 bytes (eight requests) as its payload; the plant port's decoder drops it at once.
  hal::link::PayloadWriter w;
  w.u32(3);
  w.f32(1.5f);
  std::vector<std::uint8_t> good(hal::link::kMaxFrame);
  good.resize(hal::link::encode_frame(MessageType::kActuate, 0, w.data(), w.size(), good.data()));
  std::vector<std::uint8_t> stream = good;
  stream[4] = 120;  // the first frame's length byte
  for (int k = 0; k < 8; ++k) stream.insert(stream.end(), good.begin(), good.end());
  const auto frames_with = [&](hal::link::FrameDecoder d) {
    int frames = 0;
    for (std::uint8_t x : stream) frames += d.push(x) == hal::link::FrameDecoder::Result::kFrame;
    return frames;
  };
  EXPECT_EQ(frames_with(hal::link::FrameDecoder{hal::link::kExchangePayload}), 8);
  EXPECT_LT(frames_with(hal::link::FrameDecoder{}), 8);
}

TEST(FrameDecoder, AFrameCutAfterItsHeaderLosesOnlyItself) {
  // A frame cut after its sequence byte: the next frame's first sync byte (0xA5 = 165, more than any payload the
  // link carries) arrives where the length is expected. It is the start of that frame, which must still be read.
  hal::link::PayloadWriter w;
  w.u32(7);
  std::vector<std::uint8_t> frame(hal::link::kMaxFrame);
  frame.resize(hal::link::encode_frame(MessageType::kStatus, 3, w.data(), w.size(), frame.data()));
  std::vector<std::uint8_t> stream(frame.begin(), frame.begin() + 4);  // sync, sync, type, seq
  stream.insert(stream.end(), frame.begin(), frame.end());
  hal::link::FrameDecoder d;
  int frames = 0;
  for (std::uint8_t x : stream) frames += d.push(x) == hal::link::FrameDecoder::Result::kFrame;
  EXPECT_EQ(frames, 1);
  EXPECT_EQ(d.length_errors(), 1u);
  EXPECT_EQ(d.frame().seq, 3);
}

}  // namespace
