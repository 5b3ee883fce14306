// Private to the hil layer: the host's side of the plant port (UART1) in a QEMU session (session.cpp).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "lashid/hal/link_protocol.hpp"
#include "lashid/hil/any_plant.hpp"
#include "lashid/hil/hil.hpp"
#include "lashid/hil/run_recording.hpp"
#include "reports.hpp"

namespace lashid::sim::detail {

// The host's side of the plant port: answers kActuate(t, v) with kMeasurement(t, y), stepping the plant once per t
// and recording each t once (retries are answered from the cache, not recorded again).
class PlantPeer {
 public:

  PlantPeer(AnyPlant plant, RunRecorder* recorder, int corrupt_every, HilResult& result)
      : plant_(std::move(plant)), recorder_(recorder), corrupt_every_(corrupt_every), result_(result) {}

  /// After a silence: a frame cut short is dropped (counted), not completed with the next request's bytes.
  void silence() {
    if (decoder_.abandon_partial()) ++result_.protocol_errors;
  }

  // Returns the bytes to send back for the received bytes.
  std::vector<std::uint8_t> receive(const std::vector<std::uint8_t>& bytes) {
    std::vector<std::uint8_t> reply;
    for (const std::uint8_t byte : bytes) {
      const auto r = decoder_.push(byte);
      if (r == hal::link::FrameDecoder::Result::kDropped) ++result_.protocol_errors;
      if (r != hal::link::FrameDecoder::Result::kFrame) continue;
      const hal::link::Frame& f = decoder_.frame();
      auto reader = f.reader();
      const std::uint32_t t = reader.u32();
      const float v = reader.f32();
      if (f.type != hal::link::MessageType::kActuate || !reader.ok() || !reader.at_end()) {
        ++result_.protocol_errors;
        continue;
      }
      if (t == next_t_) {  // a new sample: step the plant (the command as the firmware sent it, a float)
        last_y_ = static_cast<float>(plant_.step(static_cast<double>(v)));
        if (recorder_ != nullptr) recorder_->sample(t, v, last_y_);
        ++next_t_;
        ++result_.samples;
      } else if (next_t_ > 0 && t == next_t_ - 1) {  // a repeat after a lost/damaged answer: same y
        ++result_.repeated_requests;
      } else {
        ++result_.protocol_errors;
        continue;
      }
      hal::link::PayloadWriter w;
      w.u32(t);
      w.f32(last_y_);
      auto out = frame_bytes(hal::link::MessageType::kMeasurement, w);
      if (corrupt_every_ > 0 && ++answers_ % static_cast<std::uint32_t>(corrupt_every_) == 0) {
        out[7] ^= 0x04;  // one bit of y: the firmware must reject it by the checksum
        ++result_.corrupted_by_host;
      }
      reply.insert(reply.end(), out.begin(), out.end());
    }
    return reply;
  }

 private:
  AnyPlant plant_;
  RunRecorder* recorder_;
  int corrupt_every_;
  HilResult& result_;
  hal::link::FrameDecoder decoder_{hal::link::kExchangePayload};
  std::uint32_t next_t_ = 0;
  std::uint32_t answers_ = 0;
  float last_y_ = 0;
};

}  // namespace lashid::sim::detail
