#include "stop_signals.hpp"

#include "lashid/hil/hil.hpp"

namespace lashid::sim::detail {

void throw_if_stopped() {
  const int number = pending_stop_signal();
  if (number != 0) throw HilInterrupted(stopped_message("hil", number), number);
}

}  // namespace lashid::sim::detail
