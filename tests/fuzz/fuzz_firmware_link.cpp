// libFuzzer target: the firmware's command and frame parser, compiled for the host: untrusted bytes arrive on the
// sequencer's link (design, start, stop, query and garbage) while it runs on the host board against a first-order
// plant. Nothing may crash; the sequencer must either refuse the design or run within its own checks, and every run
// ends (a bounded number of steps: a stop, a refusal or the end of a short design).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "lashid/firmware/sequencer.hpp"
#include "lashid/hal/host_board.hpp"

namespace {

struct FirstOrderPlant {
  double y = 0;
  double step(double v) { return y = 0.5 * y + v; }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using Board = lashid::hal::HostBoard<FirstOrderPlant>;
  Board board(FirstOrderPlant{}, -1e6f, 1e6f);
  lashid::fw::IdentificationSequencer<Board> firmware(board);
  // The bytes arrive in chunks between steps, as from a UART; then the sequencer runs on (a bounded number of steps).
  std::size_t offset = 0;
  for (int step = 0; step < 4096; ++step) {
    if (offset < size) {
      const std::size_t chunk = size - offset < 16 ? size - offset : 16;
      board.link_input(data + offset, chunk);
      offset += chunk;
    }
    if (!firmware.step()) break;
  }
  // A design refused by check_design never actuates.
  if (firmware.result() == lashid::fw::RunStatus::kDesignRejected && !board.exchanges().empty() &&
      firmware.design_status() != lashid::fw::DesignStatus::kOk) {
    std::abort();
  }
  return 0;
}
