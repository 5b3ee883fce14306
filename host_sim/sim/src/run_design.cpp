// A config as the design of one device run, and the device's validation input.
#include "lashid/sim/run_design.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "lashid/firmware/validation_excitation.hpp"

namespace lashid::sim {

RunLengths run_lengths(const ExperimentConfig& /*config*/) { return RunLengths{}; }

fw::RunDesign to_run_design(const ExperimentConfig& config, const RunLengths& lengths) {
  if (config.V_d.empty() || config.V_a.empty()) {
    throw std::invalid_argument("a device run has both schemes: the config needs V_d and V_a");
  }
  if (config.m > fw::kMaxPoints || config.n > fw::kMaxOrder) {
    throw std::invalid_argument(fmt::format("n = {}, m = {} exceed the firmware image's capacity n <= {}, m <= {}",
                                            config.n, config.m, fw::kMaxOrder, fw::kMaxPoints));
  }
  const auto non_negative = [](int length, const char* key) {
    if (length < 0) throw std::invalid_argument(fmt::format("'{}' = {} is negative", key, length));
    return static_cast<std::uint32_t>(length);
  };
  fw::RunDesign d;
  d.op = config.op == OperatorKind::kBacklash ? fw::OperatorKind::kBacklash : fw::OperatorKind::kSwitch;
  d.n = static_cast<std::uint8_t>(config.n);
  d.m = static_cast<std::uint8_t>(config.m);
  d.v_min = static_cast<float>(config.v_min);
  d.v_max = static_cast<float>(config.v_max);
  for (std::size_t j = 0; j < config.V_d.size(); ++j) {
    d.V_d[j] = static_cast<float>(config.V_d[j]);
    d.V_a[j] = static_cast<float>(config.V_a[j]);
  }
  d.step_length = non_negative(lengths.step_length, "step_length");
  d.pulse_length_d = non_negative(lengths.pulse_length_d, "pulse_length_d");
  d.pulse_length_a = non_negative(lengths.pulse_length_a, "pulse_length_a");
  d.val_length = non_negative(lengths.val_length, "val_length");
  d.val_seed = lengths.val_seed;
  if (const fw::DesignStatus s = fw::check_design(d); s != fw::DesignStatus::kOk) {
    throw std::invalid_argument(fmt::format("the device would refuse this design: {}", fw::to_string(s)));
  }
  return d;
}

std::vector<double> device_validation_input(const fw::RunDesign& design) {
  fw::ValidationExcitation excitation(design);
  std::vector<double> v(design.val_length);
  for (double& x : v) x = static_cast<double>(excitation.next());
  return v;
}

}  // namespace lashid::sim
