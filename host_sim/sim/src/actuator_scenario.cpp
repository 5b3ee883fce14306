#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "lashid/sim/scenario.hpp"

namespace lashid::sim {

Scenario actuator_scenario(const HysteresisOperator& actuator, double v_min, double v_max, double noise_variance) {
  if (!(v_min < 0 && v_max > 0)) throw std::invalid_argument("actuator_scenario: need v_min < 0 < v_max");
  std::shared_ptr<const HysteresisOperator> prototype = actuator.clone();
  Scenario s;
  s.name = "actuator_" + actuator.name();
  s.description = fmt::format("{} actuator on [{}, {}], A = 1 + q^-1 + 0.21 q^-2, B = q^-1 - 0.5 q^-2, noise "
                              "variance {}", actuator.name(), v_min, v_max, noise_variance);
  s.model = {{1.0, 0.21}, {1.0, -0.5}};
  s.noise_variance = noise_variance;
  s.make_operator = [prototype] { return prototype->clone(); };
  auto op = prototype->clone();
  op->reset(v_max, 0.0);
  op->step(v_max);
  s.initial_output = op->step(v_min);
  s.config.n = 2;
  s.config.m = 6;
  s.config.v_min = v_min;
  s.config.v_max = v_max;
  s.config.V_d = {v_min, 0.5 * v_min, 0.0, 0.5 * v_max, 0.8 * v_max, 0.9 * v_max};
  s.config.V_a = {v_max, 0.5 * v_max, 0.0, 0.5 * v_min, 0.8 * v_min, 0.9 * v_min};
  s.config.op = OperatorKind::kBacklash;
  s.config.truth = scenario_truth(s);
  return s;
}

}  // namespace lashid::sim
