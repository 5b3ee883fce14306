#include "lashid/sim/friction_gap.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "lashid/sim/operator_fit.hpp"
#include "lashid/sim/scenario.hpp"

namespace lashid::sim {

FrictionGapOperator::FrictionGapOperator(Border curve, double stiffness)
    : curve_(std::move(curve)), stiffness_(stiffness) {
  if (!(curve_.lo() < 0.0 && curve_.hi() > 0.0)) {
    throw std::invalid_argument(fmt::format("FrictionGapOperator: the play [{}, {}] must contain 0 inside",
                                            curve_.lo(), curve_.hi()));
  }
  if (!std::isfinite(stiffness)) throw std::invalid_argument("FrictionGapOperator: stiffness is not finite");
}

double FrictionGapOperator::step(double v) {
  if (std::isnan(v)) throw std::invalid_argument("FrictionGapOperator::step: input is NaN");
  const double e = v - z_;
  if (e > curve_.hi()) z_ = v - curve_.hi();
  if (e < curve_.lo()) z_ = v - curve_.lo();
  return curve_(v - z_) + stiffness_ * v;
}

void FrictionGapOperator::reset(double v_prev, double u_prev) {
  const double level = u_prev - stiffness_ * v_prev;
  const double lo = curve_.lo(), hi = curve_.hi();
  const auto first = curve_.first_reach(level, lo, hi);
  double e = 0;
  if (first) {
    const double last = curve_.last_reach(level, lo, hi).value_or(*first);
    e = std::clamp(0.5 * (lo + hi), *first, last);
  } else {
    e = std::fabs(curve_(lo) - level) < std::fabs(curve_(hi) - level) ? lo : hi;
  }
  z_ = v_prev - e;
}

std::unique_ptr<HysteresisOperator> FrictionGapOperator::clone() const {
  return std::make_unique<FrictionGapOperator>(*this);
}

std::string FrictionGapOperator::name() const { return "friction_gap"; }

}  // namespace lashid::sim

// ------------------------------------------------------------------------- a scenario with any operator as actuator

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
