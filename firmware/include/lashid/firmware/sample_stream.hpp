// The samples of a run sent on the link as they are measured (kStartStreamSamples), for the host's recording of a
// plant it does not play (lashid hil --physical-plant --record): blocks of SampleBlock::kCapacity consecutive
// samples, one kSamples frame each, a block sent when full and before every stage change (so that none spans two).
// Only a board whose link writes do not wait for the wire may stream (hal::BuffersLinkWrites): on the others the
// stream is an empty class and costs no RAM. Heap-free.
#pragma once

#include <cstdint>

#include "lashid/firmware/messages.hpp"
#include "lashid/hal/link_protocol.hpp"

namespace lashid::fw {

template <bool Enabled>
class SampleStream {
 public:
  /// On or off for the run (the start command's flag).
  void start(bool on) { on_ = on; }
  /// Sample `index` as measured (`bad`: set aside as a bad sensor value); `send(writer)` sends a full block.
  template <class Send>
  void add(std::uint32_t index, float v, float y, bool bad, Send send) {
    if (!on_) return;
    block_.add(index, v, y, bad);
    if (block_.full()) flush(send);
  }
  /// Sends what the block holds, if anything.
  template <class Send>
  void flush(Send send) {
    if (block_.count == 0) return;
    hal::link::PayloadWriter w;
    block_.encode(w);
    send(w);
    block_.count = 0;
  }

 private:
  bool on_ = false;
  SampleBlock block_{};
};

/// A board that cannot stream: the flag is ignored, nothing is kept.
template <>
class SampleStream<false> {
 public:
  void start(bool /*on*/) {}
  template <class Send>
  void add(std::uint32_t /*index*/, float /*v*/, float /*y*/, bool /*bad*/, Send /*send*/) {}
  template <class Send>
  void flush(Send /*send*/) {}
};

}  // namespace lashid::fw
