// What a host board steps in place of the real actuator and plant: one command in, one measurement out, per sample.
// The HAL defines the interface and the host side supplies it (host_sim's ScenarioPlant, or a test's fake), so the
// HAL never depends on the simulator.
#pragma once

#include <concepts>

namespace lashid::hal {

/// p.step(v): apply command v for one sample period and return the output measured at that sample. Called once
/// per sample, in order; it may throw only for a programming error (a NaN command), never for a physical one.
template <class P>
concept PlantModel = requires(P p, double v) {
  { p.step(v) } -> std::convertible_to<double>;
};

}  // namespace lashid::hal
