// Status codes of the HAL. Every board call returns one; none throws.
#pragma once

#include <cstdint>

namespace lashid::hal {

enum class [[nodiscard]] Status : std::uint8_t {
  kOk = 0,
  kWouldBlock,   ///< non-blocking read: nothing pending now
  kTimeout,      ///< nothing arrived within the time limit (or the sample tick was overrun)
  kLinkError,    ///< framing/overrun/checksum error on the byte link; the data was discarded
  kOutOfRange,   ///< actuator command outside the board's range (not applied), or a sensor value that is not usable
                 ///< (outside its range, non-finite): the firmware counts the sample as bad and goes on
  kSensorFault,  ///< no measurement exists for this sample (exchange lost after retries): the run ends
  kStopped,      ///< the peer asked to stop or closed the link
};

constexpr const char* to_string(Status s) {
  switch (s) {
    case Status::kOk: return "ok";
    case Status::kWouldBlock: return "would block";
    case Status::kTimeout: return "timeout";
    case Status::kLinkError: return "link error";
    case Status::kOutOfRange: return "out of range";
    case Status::kSensorFault: return "sensor fault";
    case Status::kStopped: return "stopped";
  }
  return "unknown";
}

}  // namespace lashid::hal
