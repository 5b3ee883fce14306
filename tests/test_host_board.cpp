// The host board (hal/host) against the contract of hal::Board, with plant models written here, not taken from the
// simulator: status codes of each call, and the firmware identifying the paper's AIS example (Section 4.2) from a
// noise-free switch + linear plant in closed form (tests/paper_examples.hpp) through the board.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "lashid/firmware/paper_run_designs.hpp"
#include "lashid/firmware/sequencer.hpp"
#include "lashid/hal/host_board.hpp"
#include "link_frames.hpp"
#include "paper_examples.hpp"

namespace {

using namespace lashid;
using hal::Status;

// Returns a fixed output and records the commands it was stepped with.
struct RecordingPlant {
  std::vector<double>* commands;
  double output = 0.5;
  double step(double v) {
    commands->push_back(v);
    return output;
  }
};
static_assert(hal::PlantModel<RecordingPlant>);

TEST(HostBoard, ActuateStepsThePlantOnceWithTheFirmwaresFloat) {
  std::vector<double> commands;
  hal::HostBoard<RecordingPlant> board(RecordingPlant{&commands}, -1.0f, 1.0f);
  EXPECT_EQ(board.actuate(0.1f), Status::kOk);
  ASSERT_EQ(commands.size(), 1u);
  EXPECT_EQ(commands[0], static_cast<double>(0.1f));  // the float that crosses the link, not 0.1
  float y = 0;
  EXPECT_EQ(board.measure(y), Status::kOk);
  EXPECT_EQ(y, 0.5f);
}

TEST(HostBoard, CommandsOutsideTheRangeOrNotFiniteAreRefusedAndNotApplied) {
  std::vector<double> commands;
  hal::HostBoard<RecordingPlant> board(RecordingPlant{&commands}, -1.0f, 1.0f);
  EXPECT_EQ(board.actuate(1.5f), Status::kOutOfRange);
  EXPECT_EQ(board.actuate(-1.01f), Status::kOutOfRange);
  EXPECT_EQ(board.actuate(std::numeric_limits<float>::quiet_NaN()), Status::kOutOfRange);
  EXPECT_EQ(board.actuate(std::numeric_limits<float>::infinity()), Status::kOutOfRange);
  EXPECT_TRUE(commands.empty());
  EXPECT_EQ(board.actuate(1.0f), Status::kOk);  // the ends of the range are in it
  EXPECT_EQ(board.actuate(-1.0f), Status::kOk);
  EXPECT_EQ(commands.size(), 2u);
}

// No sample is a sensor fault (the run ends); a sample whose value is not a number is out of range (counted as bad,
// the run goes on), as RemotePlantPort answers a NaN from its peer: the host board and QEMU runs agree.
TEST(HostBoard, MeasureWithoutANewSampleIsASensorFaultAndANonFiniteOutputOutOfRange) {
  std::vector<double> commands;
  hal::HostBoard<RecordingPlant> board(RecordingPlant{&commands}, -1.0f, 1.0f);
  float y = 7.0f;
  EXPECT_EQ(board.measure(y), Status::kSensorFault);  // nothing actuated yet
  ASSERT_EQ(board.actuate(0.0f), Status::kOk);
  EXPECT_EQ(board.measure(y), Status::kOk);
  EXPECT_EQ(board.measure(y), Status::kSensorFault);  // the same sample twice

  hal::HostBoard<RecordingPlant> broken(RecordingPlant{&commands, std::nan("")}, -1.0f, 1.0f);
  ASSERT_EQ(broken.actuate(0.0f), Status::kOk);
  y = 7.0f;
  EXPECT_EQ(broken.measure(y), Status::kOutOfRange);
  EXPECT_EQ(y, 7.0f);  // left unchanged: the value is not used
}

TEST(HostBoard, LinkQueuesBytesBothWaysAndReadWouldBlockWhenEmpty) {
  std::vector<double> commands;
  hal::HostBoard<RecordingPlant> board(RecordingPlant{&commands}, -1.0f, 1.0f);
  std::uint8_t byte = 0;
  EXPECT_EQ(board.link_read(byte), Status::kWouldBlock);
  const std::array<std::uint8_t, 3> in{1, 2, 3};
  board.link_input(in.data(), in.size());
  for (std::uint8_t expected : in) {
    ASSERT_EQ(board.link_read(byte), Status::kOk);
    EXPECT_EQ(byte, expected);
  }
  EXPECT_EQ(board.link_read(byte), Status::kWouldBlock);
  const std::array<std::uint8_t, 2> out{9, 8};
  EXPECT_EQ(board.link_write(out.data(), out.size()), Status::kOk);
  EXPECT_EQ(board.link_output(), (std::vector<std::uint8_t>{9, 8}));
}

// The AIS example of the paper in closed form: switch (2.3) with the borders C_a, C_d, then
// y(t) = -a1 y(t-1) - a2 y(t-2) + b1 u(t-1) + b2 u(t-2), no noise. Starts in the steady state of the held input
// v_m: u = u_m = C_d(v_m), y = B(1) u_m / A(1).
struct AisExamplePlant {
  using Ex = test::AisExample;
  static double steady_output() {
    const auto a = Ex::a();
    const auto b = Ex::b();
    return (b[0] + b[1]) * Ex::u_m() / (1.0 + a[0] + a[1]);
  }
  double v_prev = Ex::v_min;
  double u_prev = Ex::u_m();
  std::array<double, 2> u_past{u_prev, u_prev};
  std::array<double, 2> y_past{steady_output(), steady_output()};
  double step(double v) {
    const double u = v > v_prev ? Ex::C_a(v) : v < v_prev ? Ex::C_d(v) : u_prev;
    const auto a = Ex::a();
    const auto b = Ex::b();
    const double y = -a[0] * y_past[0] - a[1] * y_past[1] + b[0] * u_past[0] + b[1] * u_past[1];
    y_past = {y, y_past[0]};
    u_past = {u, u_past[0]};
    v_prev = v;
    u_prev = u;
    return y;
  }
};
static_assert(hal::PlantModel<AisExamplePlant>);

TEST(HostBoard, TheFirmwareIdentifiesTheNoiseFreeAisExampleThroughTheBoard) {
  using Ex = test::AisExample;
  hal::HostBoard<AisExamplePlant> board(AisExamplePlant{}, static_cast<float>(Ex::v_min),
                                        static_cast<float>(Ex::v_max));
  fw::IdentificationSequencer<hal::HostBoard<AisExamplePlant>> firmware(board, fw::kAisPaperRun);
  ASSERT_EQ(firmware.run(), fw::RunStatus::kOk);

  fw::EstimateRecord ais;
  bool found = false;
  for (const hal::link::Frame& f : test::frames_of(board.link_output())) {
    fw::EstimateRecord e;
    if (f.type == hal::link::MessageType::kEstimate && e.decode(f.reader()) && e.scheme == est::Scheme::kAscending) {
      ais = e;
      found = true;
    }
  }
  ASSERT_TRUE(found) << "no AIS estimate frame";
  ASSERT_EQ(ais.n, 2);
  ASSERT_EQ(ais.m, 6);
  // Noise-free data, yet not exact: the step experiment starts with v going from v_M to v_m, and its mean (3.7)
  // includes the decay of y from 88 to 26.37 (poles 0.75 and 0.5), which biases ybar0 by O(1/L) (26.51 against
  // B(1) u_m / A(1) = 26.37 at L = 2000) and through the centring a, b and F. The host estimator in double shows the
  // same bias on the simulator's noise-free recording (a2 0.37671, b2 -2.8721, F offsets of 0.006 to 0.008), so the
  // bounds below are that bias with a margin, not float32 rounding.
  const auto a = Ex::a();
  const auto b = Ex::b();
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(ais.a[i], a[i], 5e-3) << "a" << i + 1;
    EXPECT_NEAR(ais.b[i], b[i], 0.02 * std::abs(b[i])) << "b" << i + 1;
  }
  for (std::size_t j = 0; j < 6; ++j) EXPECT_NEAR(ais.F[j], Ex::F_a(Ex::V[j]), 0.015) << "F(V_" << j + 1 << ")";
}

}  // namespace
