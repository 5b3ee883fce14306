// The bytes a UART's receive interrupt takes off the wire, kept until the firmware's next poll (hal::Board's
// link_read). A UART without a FIFO holds one byte: the sequencer polls the link once per sample (1 ms), in which
// time 11 bytes arrive at 115200 baud, so a command sent during a run would overrun it. The interrupt moves each byte
// here within a character time instead.
//
// One producer (the interrupt handler) and one consumer (the main loop), on one core: each index is written by one
// side only, so plain atomic loads and stores suffice (no read-modify-write, which ARMv6-M lacks). Bytes that find
// the queue full are counted as lost, as the UART's own overrun is (note_lost()); the consumer reports them once.
// Freestanding, no heap.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>

namespace lashid::hal {

template <std::size_t Capacity>
class IsrByteQueue {
  static_assert(Capacity >= 2 && (Capacity & (Capacity - 1)) == 0, "Capacity: a power of two, at least 2");
  static_assert(std::atomic<std::uint32_t>::is_always_lock_free, "the indices must be lock-free atomics");

 public:
  static constexpr std::size_t kCapacity = Capacity;

  /// Producer (interrupt handler): appends `byte`; false, and the byte counted as lost, if the queue is full.
  bool push(std::uint8_t byte) {
    const std::uint32_t head = head_.load(std::memory_order_relaxed);
    const std::uint32_t tail = tail_.load(std::memory_order_acquire);
    if (head - tail == Capacity) {
      note_lost();
      return false;
    }
    bytes_[head % Capacity] = byte;
    head_.store(head + 1U, std::memory_order_release);  // the byte is written before the consumer can see it
    return true;
  }

  /// Producer: bytes lost before they reached the queue (the UART's overrun, framing or noise errors).
  void note_lost() { lost_.store(lost_.load(std::memory_order_relaxed) + 1U, std::memory_order_release); }

  /// Consumer (main loop): the oldest byte, if any.
  bool pop(std::uint8_t& byte) {
    const std::uint32_t tail = tail_.load(std::memory_order_relaxed);
    if (head_.load(std::memory_order_acquire) == tail) return false;
    byte = bytes_[tail % Capacity];
    tail_.store(tail + 1U, std::memory_order_release);  // the slot is read before the producer may reuse it
    return true;
  }

  /// Consumer: whether bytes were lost since the last call (each loss is reported once).
  bool take_lost() {
    const std::uint32_t lost = lost_.load(std::memory_order_acquire);
    if (lost == lost_seen_) return false;
    lost_seen_ = lost;
    return true;
  }

  /// Consumer: bytes waiting.
  std::size_t size() const {
    return static_cast<std::size_t>(head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_relaxed));
  }

 private:
  // Free-running indices (wrapping at 2^32, a multiple of Capacity): head - tail is the fill level.
  std::atomic<std::uint32_t> head_{0};
  std::atomic<std::uint32_t> tail_{0};
  std::atomic<std::uint32_t> lost_{0};
  std::uint32_t lost_seen_ = 0;  // consumer only
  std::uint8_t bytes_[Capacity] = {};
};

}  // namespace lashid::hal
