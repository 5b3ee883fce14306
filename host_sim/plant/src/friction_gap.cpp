#include "lashid/plant/friction_gap.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include <fmt/format.h>

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

void FrictionGapOperator::place(double v_prev, double offset) {
  if (!std::isfinite(v_prev) || !std::isfinite(offset)) {
    throw std::invalid_argument("FrictionGapOperator::place: position or offset is not finite");
  }
  z_ = v_prev - std::clamp(offset, curve_.lo(), curve_.hi());
}

std::unique_ptr<HysteresisOperator> FrictionGapOperator::clone() const {
  return std::make_unique<FrictionGapOperator>(*this);
}

std::string FrictionGapOperator::name() const { return "friction_gap"; }

}  // namespace lashid::sim
