// Shared by the firmware tests: the frames a firmware wrote to its link, decoded as the host decodes them.
#pragma once

#include <cstdint>
#include <vector>

#include "lashid/firmware/run_design.hpp"
#include "lashid/hal/link_protocol.hpp"

namespace lashid::test {

/// Every complete frame in `bytes`; *errors (if given) gets the decoder's count of dropped frames.
inline std::vector<hal::link::Frame> frames_of(const std::vector<std::uint8_t>& bytes,
                                               std::uint32_t* errors = nullptr) {
  hal::link::FrameDecoder decoder;
  std::vector<hal::link::Frame> frames;
  for (std::uint8_t b : bytes) {
    if (decoder.push(b) == hal::link::FrameDecoder::Result::kFrame) frames.push_back(decoder.frame());
  }
  if (errors != nullptr) *errors = decoder.errors();
  return frames;
}

/// The kDesign frame the host sends for `design`.
inline std::vector<std::uint8_t> design_frame(const fw::RunDesign& design) {
  hal::link::PayloadWriter w;
  design.encode(w);
  std::vector<std::uint8_t> frame(hal::link::kMaxFrame);
  frame.resize(hal::link::encode_frame(hal::link::MessageType::kDesign, 0, w.data(), w.size(), frame.data()));
  return frame;
}

}  // namespace lashid::test
