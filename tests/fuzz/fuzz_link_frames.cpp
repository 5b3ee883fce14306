// libFuzzer target: the host's side of the link (untrusted bytes from a UART): the frame decoder, and every report
// record's decoder on each frame's payload, as `lashid hil` decodes them (firmware/messages.hpp). Nothing may crash;
// a decoded estimate must have n, m within the records' capacity.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "lashid/firmware/messages.hpp"
#include "lashid/firmware/run_design.hpp"
#include "lashid/hal/link_protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fw = lashid::fw;
  lashid::hal::link::FrameDecoder decoder;
  for (std::size_t i = 0; i < size; ++i) {
    if (decoder.push(data[i]) != lashid::hal::link::FrameDecoder::Result::kFrame) continue;
    const lashid::hal::link::Frame& f = decoder.frame();
    fw::EstimateRecord e;
    if (e.decode(f.reader()) && (e.n > fw::kMaxRecordOrder || e.m > fw::kMaxRecordPoints)) std::abort();
    fw::CrossCheckRecord c;
    (void)c.decode(f.reader());
    fw::CostRecord k;
    (void)k.decode(f.reader());
    fw::RunDesign d;
    if (d.decode(f.reader()) == fw::DesignStatus::kOk && d.m > fw::kMaxPoints) std::abort();
    (void)fw::check_design(d);
  }
  return 0;
}
