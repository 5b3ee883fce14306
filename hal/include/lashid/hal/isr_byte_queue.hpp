// The bytes a UART's receive interrupt takes off the wire, kept until the firmware's next poll (hal::Board's
// link_read); or, the other way round, the bytes the main loop queues for a transmit interrupt to put on the wire
// (the producer then checks room() first and pushes whole frames). A UART without a FIFO holds one byte: the
// sequencer polls the link once per sample (1 ms), in which time 11 bytes arrive at 115200 baud, so a command sent
// during a run would overrun it. The interrupt moves each byte here within a character time instead.
//
// One producer (the interrupt handler) and one consumer (the main loop), on one core: each index is written by one
// side only, so plain atomic loads and stores suffice (no read-modify-write, which ARMv6-M lacks). A loss (a byte
// that found the queue full, or one the UART lost: note_lost()) is reported where it happened in the stream: the
// next byte that does arrive carries a mark, and take() reports the loss (kLost) just before that byte, so the bytes
// queued before the loss are read as they came and only the frame the loss cut is broken. Freestanding, no heap.
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

  enum class Take : std::uint8_t {
    kByte,   ///< `byte` is the next byte
    kEmpty,  ///< nothing waiting
    kLost,   ///< bytes were lost here, between the byte taken last and the next one (reported once)
  };

  /// Producer (interrupt handler): appends `byte`; false, and the byte counted as lost, if the queue is full.
  bool push(std::uint8_t byte) {
    const std::uint32_t head = head_.load(std::memory_order_relaxed);
    const std::uint32_t tail = tail_.load(std::memory_order_acquire);
    if (head - tail == Capacity) {
      note_lost();
      return false;
    }
    const std::size_t slot = head % Capacity;
    bytes_[slot] = byte;
    // The slot's loss mark (a bit; one writer, so a load and a store, no read-modify-write).
    std::atomic<std::uint32_t>& marks = loss_marks_[slot / 32];
    const std::uint32_t word = marks.load(std::memory_order_relaxed);
    const std::uint32_t bit = 1U << (slot % 32);
    marks.store(loss_pending_ ? (word | bit) : (word & ~bit), std::memory_order_relaxed);
    loss_pending_ = false;
    head_.store(head + 1U, std::memory_order_release);  // byte and mark are written before the consumer can see them
    return true;
  }

  /// Producer: bytes were lost before the next one that arrives (the UART's overrun, framing or noise errors).
  void note_lost() {
    loss_pending_ = true;
    lost_.store(lost_.load(std::memory_order_relaxed) + 1U, std::memory_order_relaxed);
  }

  /// Consumer (main loop): the next byte, or the loss just before it, or nothing.
  Take take(std::uint8_t& byte) {
    const std::uint32_t tail = tail_.load(std::memory_order_relaxed);
    if (head_.load(std::memory_order_acquire) == tail) return Take::kEmpty;
    const std::size_t slot = tail % Capacity;
    const bool marked = (loss_marks_[slot / 32].load(std::memory_order_relaxed) & (1U << (slot % 32))) != 0U;
    if (marked && !loss_reported_) {
      loss_reported_ = true;
      return Take::kLost;
    }
    loss_reported_ = false;
    byte = bytes_[slot];
    tail_.store(tail + 1U, std::memory_order_release);  // the slot is read before the producer may reuse it
    return Take::kByte;
  }

  /// Bytes lost since the start (the producer's count; for reports).
  std::uint32_t lost() const { return lost_.load(std::memory_order_relaxed); }

  /// Producer: bytes that can be pushed now without a loss (the consumer may free more meanwhile, never fewer).
  std::size_t room() const {
    return Capacity -
           static_cast<std::size_t>(head_.load(std::memory_order_relaxed) - tail_.load(std::memory_order_acquire));
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
  bool loss_pending_ = false;   // producer only: a loss since the last byte queued
  bool loss_reported_ = false;  // consumer only: the mark of the slot at tail was reported
  std::uint8_t bytes_[Capacity] = {};
  std::atomic<std::uint32_t> loss_marks_[(Capacity + 31) / 32] = {};  // a bit per slot, written before head moves
};

}  // namespace lashid::hal
