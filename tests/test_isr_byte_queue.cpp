// The receive queue between a UART's interrupt handler and the firmware's link_read (hal::IsrByteQueue): order,
// a full queue counted as a loss and reported once, many wraps of its indices, and a producer and a consumer on two
// threads (the interrupt and the main loop of the boards).
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "lashid/hal/isr_byte_queue.hpp"

namespace {

using lashid::hal::IsrByteQueue;

TEST(IsrByteQueue, GivesTheBytesBackInTheOrderTheyCame) {
  IsrByteQueue<8> q;
  std::uint8_t b = 0;
  EXPECT_FALSE(q.pop(b));
  for (std::uint8_t i = 1; i <= 5; ++i) EXPECT_TRUE(q.push(i));
  EXPECT_EQ(q.size(), 5U);
  for (std::uint8_t i = 1; i <= 5; ++i) {
    ASSERT_TRUE(q.pop(b));
    EXPECT_EQ(b, i);
  }
  EXPECT_FALSE(q.pop(b));
  EXPECT_EQ(q.size(), 0U);
  EXPECT_FALSE(q.take_lost());
}

TEST(IsrByteQueue, AByteThatFindsItFullIsLostAndReportedOnce) {
  IsrByteQueue<4> q;
  for (std::uint8_t i = 0; i < 4; ++i) EXPECT_TRUE(q.push(i));
  EXPECT_FALSE(q.push(4));  // full: dropped
  EXPECT_FALSE(q.push(5));
  EXPECT_TRUE(q.take_lost());   // the losses so far, once
  EXPECT_FALSE(q.take_lost());
  std::uint8_t b = 0;
  for (std::uint8_t i = 0; i < 4; ++i) {
    ASSERT_TRUE(q.pop(b));
    EXPECT_EQ(b, i);  // what was queued is intact
  }
  q.note_lost();  // the UART's own overrun
  EXPECT_TRUE(q.take_lost());
  EXPECT_FALSE(q.take_lost());
}

TEST(IsrByteQueue, KeepsTheOrderOverManyWrapsOfItsSlots) {
  IsrByteQueue<8> q;
  std::uint32_t pushed = 0, popped = 0;
  std::uint8_t b = 0;
  for (int burst = 0; burst < 5000; ++burst) {
    for (int k = 0; k < 1 + burst % 8; ++k) ASSERT_TRUE(q.push(static_cast<std::uint8_t>(pushed++)));
    while (q.pop(b)) ASSERT_EQ(b, static_cast<std::uint8_t>(popped++));
  }
  EXPECT_EQ(pushed, popped);
  EXPECT_GT(pushed, 8U * 1000U);
  EXPECT_FALSE(q.take_lost());
}

TEST(IsrByteQueue, AProducerAndAConsumerOnTwoThreadsLoseNothingThatFitsAndCountWhatDoesNot) {
  IsrByteQueue<16> q;
  constexpr std::uint32_t kBytes = 200'000;
  std::uint32_t accepted = 0, dropped = 0;  // the producer's; read after join()
  std::atomic<bool> done{false};
  std::thread producer([&] {
    for (std::uint32_t i = 0; i < kBytes; ++i) {
      // Like a UART: a byte that finds the queue full is gone; the next byte is the next value.
      if (q.push(static_cast<std::uint8_t>(i))) {
        ++accepted;
      } else {
        ++dropped;
      }
    }
    done.store(true, std::memory_order_release);
  });
  std::vector<std::uint8_t> received;
  received.reserve(kBytes);
  bool lost = false;
  std::uint8_t b = 0;
  const auto drain = [&] {
    if (q.take_lost()) lost = true;
    while (q.pop(b)) received.push_back(b);
  };
  while (!done.load(std::memory_order_acquire)) drain();
  producer.join();
  drain();
  EXPECT_EQ(received.size(), accepted);
  EXPECT_EQ(accepted + dropped, kBytes);
  EXPECT_EQ(lost, dropped > 0);
  // Between losses the bytes come in order: each received byte follows the one before by 1 + (bytes dropped between).
  std::uint32_t gaps = 0;
  for (std::size_t i = 1; i < received.size(); ++i) {
    const auto step = static_cast<std::uint8_t>(received[i] - received[i - 1]);
    ASSERT_NE(step, 0U) << "a byte received twice at " << i;
    if (step != 1U) ++gaps;
  }
  EXPECT_LE(gaps, dropped);
}

}  // namespace
