// The device's validation input for a design.
#include "lashid/sim/device_validation.hpp"

#include "lashid/firmware/validation_excitation.hpp"

namespace lashid::sim {

std::vector<double> device_validation_input(const fw::RunDesign& design) {
  fw::ValidationExcitation excitation(design);
  std::vector<double> v(design.val_length);
  for (double& x : v) x = static_cast<double>(excitation.next());
  return v;
}

}  // namespace lashid::sim
