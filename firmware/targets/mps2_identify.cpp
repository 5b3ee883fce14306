// The identification firmware on QEMU's mps2 machines: UART0 is the link (start/stop/query commands in, reports out),
// UART1 is the actuator/sensor port (one kActuate/kMeasurement exchange per sample with `lashid hil`, which plays
// the actuator with backlash and the plant), SysTick is the clock. One image for every design within its capacity
// (n <= 4, m <= 10): it waits for the design (kDesign, answered with its DesignStatus) and a start command, runs the
// sequence, reports, and exits QEMU with 0 when the run is ok (10 + RunStatus otherwise).
#include "lashid/firmware/sequencer.hpp"
#include "lashid/hal/board.hpp"
#include "lashid/hal/mps2.hpp"
#include "remote_identification_board.hpp"

// For `lashid hil`: this image's plant is played over its plant port (not --physical-plant).
LASHID_CORTEX_M_PLANT_TAG("port");

namespace {

using namespace lashid;
namespace mps2 = hal::mps2;

// A class of this file's anonymous namespace, not an alias: the sequencer instantiated on it has internal linkage,
// which lets GCC specialise and inline it into main (an alias of the namespace-scope template costs ~570 B of flash).
class Mps2IdentificationBoard
    : public fw::targets::RemoteIdentificationBoard<mps2::Mps2Platform, mps2::Mps2Uart, mps2::kSystemClockHz> {
 public:
  using RemoteIdentificationBoard::RemoteIdentificationBoard;
};

static_assert(hal::Board<Mps2IdentificationBoard>);
static_assert(hal::ReportsStackUse<Mps2IdentificationBoard>);
static_assert(hal::ReportsExchangeErrors<Mps2IdentificationBoard>);
static_assert(hal::KnowsCycleRate<Mps2IdentificationBoard>);  // else the reports are not held for a host that lost one

// Static storage: nothing of the sequence lives on the stack, and nothing on a heap (there is none).
Mps2IdentificationBoard g_board{mps2::kUart1Base};
fw::IdentificationSequencer<Mps2IdentificationBoard> g_sequencer(g_board);

}  // namespace

// The plant port's receive interrupt: only wakes the core that sleeps for the answer (UartChannel::idle).
extern "C" void PlantRx_IRQHandler() { mps2::Mps2Uart{mps2::kUart1Base}.disarm_rx_wake(); }

int main() {
  g_board.init();
  mps2::semihosting::write("lashid: identification firmware waiting for a design and start on UART0\n");
  const fw::RunStatus status = g_sequencer.run();
  return status == fw::RunStatus::kOk ? 0 : 10 + static_cast<int>(status);
}
