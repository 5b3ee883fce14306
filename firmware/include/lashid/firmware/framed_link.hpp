// The firmware's end of the host link: frames out (numbered, encoded, written through the board) and frames in
// (bytes read through the board, decoded), with every failure counted in the run's CostRecord rather than ended on.
// The protocol itself is hal/link_protocol.hpp; what the frames mean is the sequencer's (sequencer.hpp).
// Heap-free, no exceptions.
#pragma once

#include <cstddef>
#include <cstdint>

#include "lashid/firmware/messages.hpp"
#include "lashid/hal/board.hpp"
#include "lashid/hal/link_protocol.hpp"

namespace lashid::fw {

template <hal::Board B>
class FramedLink {
 public:
  /// Bytes or link errors handled per poll at most (two whole frames' worth; the rest waits for the next poll): a
  /// board whose link_read kept failing (a sticky overrun flag) would otherwise hold the firmware in the poll
  /// forever, with no sample taken and nothing reported.
  static constexpr int kPollBudget = 2 * static_cast<int>(hal::link::kMaxFrame);

  explicit FramedLink(B& board) : board_(board) {}

  /// Sends `w` as one frame of `type`. A payload that overflowed the writer is truncated: it is not sent (the host
  /// would decode garbage or reject it) and counts in cost.send_failures; a frame the board fails to write counts
  /// in cost.link_errors. The static_asserts of messages.hpp make the first unreachable for the image's records.
  void send(hal::link::MessageType type, const hal::link::PayloadWriter& w, CostRecord& cost) {
    if (!w.ok()) {
      ++cost.send_failures;
      return;
    }
    std::uint8_t frame[hal::link::kMaxFrame];
    const std::size_t size = hal::link::encode_frame(type, seq_++, w.data(), w.size(), frame);
    if (size == 0 || board_.link_write(frame, size) != hal::Status::kOk) ++cost.link_errors;
  }

  /// Reads what the board has (kPollBudget at most) and calls on_frame(frame) for each whole frame. Lost bytes (a
  /// read error: an overrun) and dropped frames (checksum, length) count in cost.link_errors; the frame under way
  /// at a lost byte is dropped, or it would eat the next (as on the plant port).
  template <class OnFrame>
  void poll(CostRecord& cost, OnFrame on_frame) {
    std::uint8_t byte = 0;
    for (int budget = kPollBudget; budget > 0; --budget) {
      const hal::Status s = board_.link_read(byte);
      if (s == hal::Status::kWouldBlock) return;
      if (s != hal::Status::kOk) {
        ++cost.link_errors;
        static_cast<void>(decoder_.abandon_partial());
        continue;
      }
      const auto r = decoder_.push(byte);
      if (r == hal::link::FrameDecoder::Result::kDropped) ++cost.link_errors;
      if (r == hal::link::FrameDecoder::Result::kFrame) on_frame(decoder_.frame());
    }
  }

 private:
  B& board_;
  std::uint8_t seq_ = 0;
  hal::link::FrameDecoder decoder_{};
};

}  // namespace lashid::fw
