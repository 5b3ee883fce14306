// Shared by the firmware tests on the in-process board: the reports a run wrote to its link, decoded as the host
// decodes them, and a command frame.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "lashid/firmware/messages.hpp"
#include "lashid/hal/link_protocol.hpp"
#include "link_frames.hpp"

namespace lashid::test {

struct Reports {
  std::vector<fw::EstimateRecord> estimates;
  fw::CrossCheckRecord cross;
  fw::CostRecord cost;
  int done = -1;
};

/// The reports in the link output of `board` (any board with link_output()); every frame must decode.
template <class Board>
Reports reports_of(const Board& board) {
  std::uint32_t errors = 0;
  Reports r;
  for (const auto& f : frames_of(board.link_output(), &errors)) {
    if (f.type == hal::link::MessageType::kEstimate) {
      fw::EstimateRecord e;
      EXPECT_TRUE(e.decode(f.reader()));
      r.estimates.push_back(e);
    } else if (f.type == hal::link::MessageType::kCrossCheck) {
      EXPECT_TRUE(r.cross.decode(f.reader()));
    } else if (f.type == hal::link::MessageType::kCost) {
      EXPECT_TRUE(r.cost.decode(f.reader()));
    } else if (f.type == hal::link::MessageType::kDone) {
      r.done = f.payload[0];
    }
  }
  EXPECT_EQ(errors, 0u);
  return r;
}

/// A kCommand frame: the command, then its arguments (kStart's flags).
inline std::vector<std::uint8_t> command(hal::link::Command c, std::vector<std::uint8_t> arguments = {}) {
  std::vector<std::uint8_t> payload{static_cast<std::uint8_t>(c)};
  payload.insert(payload.end(), arguments.begin(), arguments.end());
  std::vector<std::uint8_t> frame(hal::link::kMaxFrame);
  frame.resize(
      hal::link::encode_frame(hal::link::MessageType::kCommand, 0, payload.data(), payload.size(), frame.data()));
  return frame;
}

}  // namespace lashid::test
