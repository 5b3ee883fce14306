// The sensor side of the firmware's plant port (hal/remote_plant_port.hpp) against a peer that damages, drops,
// repeats or cuts its answers: every loss is detected, counted and asked again, and a value is never taken from a
// frame that failed its checks. Expected numbers come from the faults injected, not from the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "lashid/hal/link_protocol.hpp"
#include "lashid/hal/remote_plant_port.hpp"

namespace {

using namespace lashid;
using hal::link::MessageType;

// A byte channel with a peer that answers kActuate(t, v) by kMeasurement(t, 2v + t), damaging some answers.
class FaultyPeerChannel {
 public:
  enum class Fault { kNone, kCorrupt, kDrop, kStaleThenGood, kTruncate };
  explicit FaultyPeerChannel(std::vector<Fault> faults) : faults_(std::move(faults)) {}

  hal::Status write(const std::uint8_t* data, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) {
      if (decoder_.push(data[i]) != hal::link::FrameDecoder::Result::kFrame) continue;
      auto r = decoder_.frame().reader();
      const std::uint32_t t = r.u32();
      const float v = r.f32();
      const Fault fault = requests_ < faults_.size() ? faults_[requests_] : Fault::kNone;
      ++requests_;
      if (fault == Fault::kDrop) continue;
      if (fault == Fault::kStaleThenGood) answer(t - 1, 99.0f, false);
      answer(t, 2 * v + static_cast<float>(t), fault == Fault::kCorrupt);
    }
    return hal::Status::kOk;
  }
  hal::Status read(std::uint8_t& byte) {
    ++clock_;
    if (pending_.empty()) return hal::Status::kWouldBlock;
    byte = pending_.front();
    pending_.pop_front();
    return hal::Status::kOk;
  }
  std::uint32_t cycles() const { return clock_; }

 private:
  void answer(std::uint32_t t, float y, bool corrupt) {
    hal::link::PayloadWriter w;
    w.u32(t);
    w.f32(y);
    std::uint8_t frame[hal::link::kMaxFrame];
    const std::size_t n = hal::link::encode_frame(MessageType::kMeasurement, 0, w.data(), w.size(), frame);
    if (corrupt) frame[7] ^= 0x10;  // one bit of y
    // kTruncate: the answer loses its last byte on the line.
    const std::size_t delivered = requests_ <= faults_.size() && faults_[requests_ - 1] == Fault::kTruncate ? n - 1 : n;
    pending_.insert(pending_.end(), frame, frame + delivered);
  }
  std::vector<Fault> faults_;
  std::size_t requests_ = 0;
  hal::link::FrameDecoder decoder_;
  std::deque<std::uint8_t> pending_;
  std::uint32_t clock_ = 0;
};

TEST(RemotePlantPort, DetectsCountsAndRecoversFromDamagedLostAndStaleFrames) {
  using F = FaultyPeerChannel::Fault;
  // Request 0 ok; request 1 corrupted (then resent ok); request 3 dropped (timeout, resent); request 5 preceded
  // by a stale answer for t - 1.
  FaultyPeerChannel channel({F::kNone, F::kCorrupt, F::kNone, F::kDrop, F::kNone, F::kStaleThenGood});
  static_assert(hal::ByteChannel<FaultyPeerChannel>);
  hal::RemotePlantPort<FaultyPeerChannel> port(channel, /*timeout_cycles=*/1000, /*max_retries=*/2);
  for (std::uint32_t t = 0; t < 4; ++t) {
    const float v = 0.5f * static_cast<float>(t);
    ASSERT_EQ(port.actuate(v), hal::Status::kOk);
    float y = -1;
    ASSERT_EQ(port.measure(y), hal::Status::kOk) << "t = " << t;
    EXPECT_EQ(y, 2 * v + static_cast<float>(t)) << "t = " << t;  // never the corrupted or stale value
  }
  EXPECT_EQ(port.retries(), 2u);  // the corrupted and the dropped answer
  EXPECT_EQ(port.errors(), 2u);   // one checksum failure, one stale answer
}

TEST(RemotePlantPort, GivesUpWithASensorFaultAfterTheRetries) {
  using F = FaultyPeerChannel::Fault;
  FaultyPeerChannel channel({F::kDrop, F::kDrop, F::kDrop});
  hal::RemotePlantPort<FaultyPeerChannel> port(channel, 100, 2);
  ASSERT_EQ(port.actuate(1.0f), hal::Status::kOk);
  float y = 42;
  EXPECT_EQ(port.measure(y), hal::Status::kSensorFault);
  EXPECT_EQ(y, 42);  // untouched
  EXPECT_EQ(port.retries(), 2u);
  // The channel's clock ticks once per read: the waits were 100, then doubled twice, 100 (2^3 - 1) in all.
  EXPECT_EQ(channel.cycles(), 100u * (1 + 2 + 4));
}

TEST(RemotePlantPort, AnAnswerCutShortCostsOneRepetitionNotTwo) {
  using F = FaultyPeerChannel::Fault;
  // Answer 0 loses its last byte. Kept open in the decoder, it would take the first byte of the repeated answer as
  // its checksum (a second loss); abandoned when the answer is overdue, the repetition is read whole.
  FaultyPeerChannel channel({F::kTruncate});
  hal::RemotePlantPort<FaultyPeerChannel> port(channel, 100, 3);
  ASSERT_EQ(port.actuate(1.5f), hal::Status::kOk);
  float y = 0;
  ASSERT_EQ(port.measure(y), hal::Status::kOk);
  EXPECT_EQ(y, 3.0f);  // 2 v + t, t = 0
  EXPECT_EQ(port.retries(), 1u);
  EXPECT_EQ(port.errors(), 1u);  // the frame cut short
}

// A peer that answers every request with the same y: at once, or only once the port has idled `idles_before` times
// (an answer that arrives while the core sleeps). Reads count as the clock's ticks.
struct ConstantPeer {
  explicit ConstantPeer(float answer, int idles_before_answer = 0) : y(answer), idles_before(idles_before_answer) {}
  hal::Status write(const std::uint8_t* data, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) {
      if (decoder.push(data[i]) != hal::link::FrameDecoder::Result::kFrame) continue;
      hal::link::PayloadWriter w;
      w.u32(decoder.frame().reader().u32());
      w.f32(y);
      std::uint8_t frame[hal::link::kMaxFrame];
      answer_size = hal::link::encode_frame(MessageType::kMeasurement, 0, w.data(), w.size(), frame);
      held.assign(frame, frame + answer_size);
      if (idles_before == 0) deliver();
    }
    return hal::Status::kOk;
  }
  hal::Status read(std::uint8_t& byte) {
    ++reads;
    if (pending.empty()) return hal::Status::kWouldBlock;
    byte = pending.front();
    pending.pop_front();
    return hal::Status::kOk;
  }
  void idle() {
    if (++idles == idles_before) deliver();
  }
  std::uint32_t cycles() const { return static_cast<std::uint32_t>(reads); }
  void deliver() { pending.insert(pending.end(), held.begin(), held.end()); }
  float y;
  int idles_before;
  hal::link::FrameDecoder decoder;
  std::vector<std::uint8_t> held;
  std::size_t answer_size = 0;
  std::deque<std::uint8_t> pending;
  int reads = 0;
  int idles = 0;
};

TEST(RemotePlantPort, ANonFiniteMeasurementIsTheSensorsFaultNotTheLinks) {
  // A verified answer carrying NaN: kOutOfRange with the value, no repetition (asking again gives the same value).
  ConstantPeer peer(std::nanf(""));
  hal::RemotePlantPort<ConstantPeer> port(peer, 100, 3);
  ASSERT_EQ(port.actuate(1.0f), hal::Status::kOk);
  float y = 0;
  EXPECT_EQ(port.measure(y), hal::Status::kOutOfRange);
  EXPECT_TRUE(std::isnan(y));
  EXPECT_EQ(port.retries(), 0u);
  EXPECT_EQ(port.next_sample(), 1u);
}

TEST(RemotePlantPort, WaitsThroughTheChannelsIdleWhereItHasOne) {
  // A channel with idle() (the images sleep there until an interrupt): the answer arrives only during an idle, as a
  // byte that wakes a sleeping core. Each of the 3 silent reads before it must be followed by one idle(), and the
  // answer then read in full. Without the idle() calls no answer comes: the clock (one tick per read) reaches the
  // time limit and the port gives up with kSensorFault.
  ConstantPeer peer(0.5f, 3);
  hal::RemotePlantPort<ConstantPeer> port(peer, 100, 3);
  ASSERT_EQ(port.actuate(1.0f), hal::Status::kOk);
  float y = 0;
  ASSERT_EQ(port.measure(y), hal::Status::kOk);
  EXPECT_EQ(y, 0.5f);
  EXPECT_EQ(peer.idles, 3);
  EXPECT_EQ(peer.reads, 3 + static_cast<int>(peer.answer_size));
  EXPECT_EQ(port.retries(), 0u);
}

}  // namespace
