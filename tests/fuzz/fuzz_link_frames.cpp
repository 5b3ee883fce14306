// libFuzzer target: the host's side of the link (untrusted bytes from a UART): the frame decoder, and every report
// record's decoder on each frame's payload, as `lashid hil` decodes them (firmware/messages.hpp), the streamed sample
// blocks' too. Nothing may crash; a decoded estimate must have n, m within the records' capacity, a decoded sample
// block must round-trip through its encoding. The record decoders also get the input's first
// bytes directly as a payload: through the frame decoder only inputs with a matching CRC reach them, and a long run
// then explored no record shape but the seeds' (n = 2, m = 6; docs/reliability.md).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "lashid/firmware/messages.hpp"
#include "lashid/firmware/run_design.hpp"
#include "lashid/hal/link_protocol.hpp"

namespace {

namespace fw = lashid::fw;

void decode_records(const lashid::hal::link::PayloadReader& payload) {
  fw::EstimateRecord e;
  if (e.decode(payload) && (e.n > fw::kMaxRecordOrder || e.m > fw::kMaxRecordPoints)) std::abort();
  fw::CrossCheckRecord c;
  (void)c.decode(payload);
  fw::CostRecord k;
  (void)k.decode(payload);
  fw::RunDesign d;
  if (d.decode(payload) == fw::DesignStatus::kOk && d.m > fw::kMaxPoints) std::abort();
  (void)fw::check_design(d);
  // A streamed block (kSamples): a decoded one encodes to a payload that decodes to the same block, bit for bit.
  fw::SampleBlock b;
  if (b.decode(payload)) {
    lashid::hal::link::PayloadWriter w;
    b.encode(w);
    fw::SampleBlock again;
    if (!w.ok() || !again.decode(lashid::hal::link::PayloadReader(w.data(), w.size())) || again.first != b.first ||
        again.count != b.count || again.set_aside != b.set_aside ||
        std::memcmp(again.v.data(), b.v.data(), sizeof(float) * b.count) != 0 ||
        std::memcmp(again.y.data(), b.y.data(), sizeof(float) * b.count) != 0) {
      std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  decode_records(lashid::hal::link::PayloadReader(data, std::min(size, lashid::hal::link::kMaxPayload)));
  lashid::hal::link::FrameDecoder decoder;
  for (std::size_t i = 0; i < size; ++i) {
    if (decoder.push(data[i]) != lashid::hal::link::FrameDecoder::Result::kFrame) continue;
    decode_records(decoder.frame().reader());
  }
  return 0;
}
