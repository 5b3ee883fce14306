// The actuator and the sensor reached over a byte channel (on QEMU: UART1, with `lashid hil` playing the actuator
// and the plant). One exchange per sample: kActuate(t, v) out, kMeasurement(t, y) back (hal/link_protocol.hpp).
// A damaged frame is dropped and counted, and the request is sent again at once; a missing answer is sent again
// after a timeout that starts at `timeout_cycles` and doubles with each repetition (a lost byte costs one short
// wait, while a peer that is only slow for a while, e.g. a loaded host, is not given up on); an answer for another t
// is stale, counted and ignored. The peer must answer a repeated t with the same y (it must not step the plant
// twice). Nothing unverified is ever returned as a measurement.
#pragma once

#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>

#include "lashid/hal/link_protocol.hpp"
#include "lashid/hal/status.hpp"

namespace lashid::hal {

template <class D>
concept ByteChannel = requires(D& d, const D& cd, std::uint8_t& byte, const std::uint8_t* data, std::size_t size) {
  { d.write(data, size) } -> std::same_as<Status>;  // all bytes; kOk / kLinkError / kTimeout
  { d.read(byte) } -> std::same_as<Status>;         // non-blocking; kOk / kWouldBlock / kLinkError
  { cd.cycles() } -> std::same_as<std::uint32_t>;   // monotonic clock for the timeout
};

template <ByteChannel Channel>
class RemotePlantPort {
 public:
  RemotePlantPort(Channel& channel, std::uint32_t timeout_cycles, int max_retries)
      : channel_(channel), timeout_cycles_(timeout_cycles), max_retries_(max_retries) {}

  /// Sends v for the next sample. kOk, or the channel's error.
  Status actuate(float v) {
    v_ = v;
    return send_request();
  }

  /// Waits for y of the sample last actuated. kOk; kOutOfRange (a verified answer whose value is NaN or infinite:
  /// y holds it, the sensor's fault, not the link's); kSensorFault (no valid answer after max_retries
  /// repetitions); kStopped (the peer sent an empty measurement: end of the session).
  Status measure(float& y) {
    std::uint32_t timeout = timeout_cycles_;
    for (int attempt = 0; attempt <= max_retries_; ++attempt) {
      if (attempt > 0) {
        ++retries_;
        // The answer is overdue: a frame still open in the decoder lost a byte. Dropped now, it cannot swallow the
        // start of the answer to the repeated request.
        if (decoder_.abandon_partial()) ++errors_;
        // Doubled up to half the counter's range, so that the difference below stays meaningful.
        if (timeout < 0x8000'0000U) timeout *= 2U;
        if (send_request() != Status::kOk) continue;
      }
      const std::uint32_t start = channel_.cycles();
      while (channel_.cycles() - start < timeout) {
        std::uint8_t byte = 0;
        const Status s = channel_.read(byte);
        if (s == Status::kWouldBlock) {
          if constexpr (requires { channel_.idle(); }) channel_.idle();  // e.g. sleep until an interrupt
          continue;
        }
        if (s != Status::kOk) {  // overrun/framing: bytes were lost, the answer may be among them
          ++errors_;
          break;
        }
        const auto r = decoder_.push(byte);
        if (r == link::FrameDecoder::Result::kDropped) {
          ++errors_;
          break;
        }
        if (r != link::FrameDecoder::Result::kFrame) continue;
        const link::Frame& f = decoder_.frame();
        if (f.type != link::MessageType::kMeasurement) continue;
        if (f.size == 0) return Status::kStopped;
        auto reader = f.reader();
        const std::uint32_t t = reader.u32();
        const float value = reader.f32();
        if (!reader.ok() || !reader.at_end() || t != t_) {
          ++stale_;
          continue;
        }
        ++t_;
        y = value;
        return std::isfinite(value) ? Status::kOk : Status::kOutOfRange;
      }
    }
    ++t_;  // give the sample up; the next exchange is a new t
    return Status::kSensorFault;
  }

  std::uint32_t errors() const { return errors_ + stale_; }
  std::uint32_t retries() const { return retries_; }
  std::uint32_t next_sample() const { return t_; }

 private:
  Status send_request() {
    link::PayloadWriter w;
    w.u32(t_);
    w.f32(v_);
    std::uint8_t frame[link::kMaxFrame];
    const std::size_t size = link::encode_frame(link::MessageType::kActuate, seq_++, w.data(), w.size(), frame);
    return channel_.write(frame, size);
  }

  Channel& channel_;
  std::uint32_t timeout_cycles_;
  int max_retries_;
  link::FrameDecoder decoder_{link::kExchangePayload};
  std::uint32_t t_ = 0;
  float v_ = 0;
  std::uint8_t seq_ = 0;
  std::uint32_t errors_ = 0;
  std::uint32_t stale_ = 0;
  std::uint32_t retries_ = 0;
};

}  // namespace lashid::hal
