// The receive queue between a UART's interrupt handler and the firmware's link_read (hal::IsrByteQueue): order, a
// loss reported once and where it happened in the stream, many wraps of its slots, and a producer and a consumer on
// two threads (the interrupt and the main loop of the boards).
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "lashid/hal/isr_byte_queue.hpp"

namespace {

using lashid::hal::IsrByteQueue;

template <std::size_t N>
using Take = typename IsrByteQueue<N>::Take;

TEST(IsrByteQueue, GivesTheBytesBackInTheOrderTheyCame) {
  IsrByteQueue<8> q;
  std::uint8_t b = 0;
  EXPECT_EQ(q.take(b), Take<8>::kEmpty);
  EXPECT_EQ(q.room(), 8U);
  for (std::uint8_t i = 1; i <= 5; ++i) EXPECT_TRUE(q.push(i));
  EXPECT_EQ(q.size(), 5U);
  EXPECT_EQ(q.room(), 3U);  // the producer's view: what it may push without a loss
  for (std::uint8_t i = 1; i <= 5; ++i) {
    ASSERT_EQ(q.take(b), Take<8>::kByte);
    EXPECT_EQ(b, i);
    EXPECT_EQ(q.room(), 3U + i);
  }
  EXPECT_EQ(q.take(b), Take<8>::kEmpty);
  EXPECT_EQ(q.size(), 0U);
  EXPECT_EQ(q.lost(), 0U);
}

TEST(IsrByteQueue, ALossIsReportedOnceWhereItHappenedNotBeforeTheBytesQueuedEarlier) {
  IsrByteQueue<4> q;
  for (std::uint8_t i = 0; i < 4; ++i) EXPECT_TRUE(q.push(i));
  EXPECT_FALSE(q.push(4));  // full: dropped
  EXPECT_FALSE(q.push(5));
  EXPECT_EQ(q.lost(), 2U);
  std::uint8_t b = 0;
  for (std::uint8_t i = 0; i < 4; ++i) {  // what was queued before the loss comes first, intact
    ASSERT_EQ(q.take(b), Take<4>::kByte);
    EXPECT_EQ(b, i);
  }
  EXPECT_EQ(q.take(b), Take<4>::kEmpty);  // the loss shows with the next byte that arrives, not before
  EXPECT_TRUE(q.push(6));
  EXPECT_EQ(q.take(b), Take<4>::kLost);
  ASSERT_EQ(q.take(b), Take<4>::kByte);
  EXPECT_EQ(b, 6);
  EXPECT_EQ(q.take(b), Take<4>::kEmpty);
  // The UART's own loss (an overrun) between two queued bytes.
  EXPECT_TRUE(q.push(7));
  q.note_lost();
  EXPECT_TRUE(q.push(8));
  ASSERT_EQ(q.take(b), Take<4>::kByte);
  EXPECT_EQ(b, 7);
  EXPECT_EQ(q.take(b), Take<4>::kLost);
  ASSERT_EQ(q.take(b), Take<4>::kByte);
  EXPECT_EQ(b, 8);
  EXPECT_EQ(q.lost(), 3U);
}

TEST(IsrByteQueue, KeepsTheOrderOverManyWrapsOfItsSlots) {
  IsrByteQueue<8> q;
  std::uint32_t pushed = 0, popped = 0;
  std::uint8_t b = 0;
  for (int burst = 0; burst < 5000; ++burst) {
    for (int k = 0; k < 1 + burst % 8; ++k) ASSERT_TRUE(q.push(static_cast<std::uint8_t>(pushed++)));
    while (q.take(b) == Take<8>::kByte) ASSERT_EQ(b, static_cast<std::uint8_t>(popped++));
  }
  EXPECT_EQ(pushed, popped);
  EXPECT_GT(pushed, 8U * 1000U);
  EXPECT_EQ(q.lost(), 0U);
}

TEST(IsrByteQueue, AProducerAndAConsumerOnTwoThreadsGetExactlyTheAcceptedBytesAndTheirGaps) {
  IsrByteQueue<16> q;
  constexpr int kBursts = 5000;
  // The producer logs what it queued: each accepted byte's index, and whether a loss came right before it.
  std::vector<std::uint32_t> accepted;
  std::vector<bool> after_loss;
  accepted.reserve(40U * kBursts);
  after_loss.reserve(40U * kBursts);
  std::atomic<bool> done{false};
  // Every other burst the consumer is held (it acknowledges, then waits), so that burst surely overflows whatever
  // the scheduler does: losses and the marks after them are exercised on a loaded machine too. The other bursts race.
  enum : int { kRun = 0, kHoldAsked = 1, kHeld = 2 };
  std::atomic<int> hold{kRun};
  std::thread producer([&] {
    bool lost = false;
    std::uint32_t i = 0;
    // Bursts of 40 bytes into 16 slots, like a frame arriving while the main loop is busy: unless the consumer keeps
    // up, the end of each burst is lost; then the producer waits for the queue to drain (the next frame comes later).
    for (int burst = 0; burst < kBursts; ++burst) {
      const bool held = burst % 2 == 1;
      if (held) {
        hold.store(kHoldAsked, std::memory_order_release);
        while (hold.load(std::memory_order_acquire) != kHeld) std::this_thread::yield();
      }
      for (int k = 0; k < 40; ++k, ++i) {
        // Like a UART: a byte that finds the queue full is gone; the next byte is the next value.
        if (q.push(static_cast<std::uint8_t>(i))) {
          accepted.push_back(i);
          after_loss.push_back(lost);
          lost = false;
        } else {
          lost = true;
        }
      }
      if (held) hold.store(kRun, std::memory_order_release);
      while (q.size() > 0) std::this_thread::yield();
    }
    done.store(true, std::memory_order_release);
  });
  std::vector<std::uint8_t> received;
  std::vector<bool> received_after_loss;
  received.reserve(40U * kBursts);
  bool loss = false;
  std::uint8_t b = 0;
  const auto drain = [&] {
    for (;;) {
      const auto t = q.take(b);
      if (t == Take<16>::kEmpty) return;
      if (t == Take<16>::kLost) {
        EXPECT_FALSE(loss) << "a loss reported twice";
        loss = true;
        continue;
      }
      received.push_back(b);
      received_after_loss.push_back(loss);
      loss = false;
    }
  };
  while (!done.load(std::memory_order_acquire)) {
    if (hold.load(std::memory_order_acquire) == kHoldAsked) {
      hold.store(kHeld, std::memory_order_release);
      while (hold.load(std::memory_order_acquire) == kHeld) std::this_thread::yield();
    }
    drain();
    std::this_thread::yield();  // on one core, the producer runs now rather than at the next tick
  }
  producer.join();
  drain();
  ASSERT_EQ(received.size(), accepted.size());
  for (std::size_t i = 0; i < accepted.size(); ++i) {
    ASSERT_EQ(received[i], static_cast<std::uint8_t>(accepted[i])) << "byte " << i;
    ASSERT_EQ(received_after_loss[i], after_loss[i]) << "the loss mark before byte " << i;
  }
  EXPECT_EQ(q.lost(), 40U * kBursts - accepted.size());
  // The test means something only if losses were followed by bytes (the marks were exercised): each held burst
  // loses its last 24 bytes, and the next burst's first byte carries the mark (the last burst has no next).
  EXPECT_GE(std::count(after_loss.begin(), after_loss.end(), true), kBursts / 2 - 1);
}

}  // namespace
