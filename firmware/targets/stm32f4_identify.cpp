// The identification firmware on the STM32F405 (QEMU netduinoplus2): USART1 is the link (design, start/stop/query
// commands in, reports out), USART2 is the actuator/sensor port (one kActuate/kMeasurement exchange per sample with
// `lashid hil`), SysTick at 168 MHz is the clock. The same sequencer and board as on mps2
// (remote_identification_board.hpp); only the platform, the plant USART and the clock differ. The clock tree is
// started first (168 MHz from the board's crystal; QEMU's fixed 168 MHz there). Exits with 0 when the run is ok,
// 10 + RunStatus otherwise, and stm32f4::kExitClockTree (9) if the clocks could not be made as planned.
#include "lashid/firmware/sequencer.hpp"
#include "lashid/hal/board.hpp"
#include "lashid/hal/stm32f4.hpp"
#include "remote_identification_board.hpp"

// For `lashid hil`: this image's plant is played over its plant port (not --physical-plant).
LASHID_CORTEX_M_PLANT_TAG("port");

namespace {

using namespace lashid;
namespace stm32f4 = hal::stm32f4;

// A class of this file's anonymous namespace, not an alias: the sequencer instantiated on it has internal linkage,
// which lets GCC specialise and inline it into main (an alias of the namespace-scope template costs ~570 B of flash).
class Stm32f4IdentificationBoard
    : public fw::targets::RemoteIdentificationBoard<stm32f4::Stm32f4Platform, stm32f4::Usart,
                                                    stm32f4::kSystemClockHz> {
 public:
  using RemoteIdentificationBoard::RemoteIdentificationBoard;
};

static_assert(hal::Board<Stm32f4IdentificationBoard>);
static_assert(hal::ReportsStackUse<Stm32f4IdentificationBoard>);
static_assert(hal::ReportsExchangeErrors<Stm32f4IdentificationBoard>);
static_assert(hal::KnowsCycleRate<Stm32f4IdentificationBoard>);  // else the reports are not held for a host that lost one

// Static storage: nothing of the sequence lives on the stack, and nothing on a heap (there is none).
Stm32f4IdentificationBoard g_board{stm32f4::kUsart2};
fw::IdentificationSequencer<Stm32f4IdentificationBoard> g_sequencer(g_board);

}  // namespace

// The plant port's receive interrupt: only wakes the core that sleeps for the answer (UartChannel::idle).
extern "C" void PlantRx_IRQHandler() { stm32f4::Usart{stm32f4::kUsart2}.disarm_rx_wake(); }

int main() {
  if (!stm32f4::runs_as_planned(stm32f4::start_clock_tree_and_say())) return stm32f4::kExitClockTree;
  g_board.init();
  stm32f4::semihosting::write("lashid: identification firmware waiting for a design and start on USART1\n");
  const fw::RunStatus status = g_sequencer.run();
  return status == fw::RunStatus::kOk ? 0 : 10 + static_cast<int>(status);
}
