// An experiment config (runtime n, m) as the estimator's types: the ExperimentDesign of one scheme, at a capacity.
// Shared by the estimator run on a recording (identify/) and the excitation of a simulation (sim/), so both read a
// config the same way.
#pragma once

#include <cstddef>
#include <stdexcept>

#include "lashid/estimator/design.hpp"
#include "lashid/io/config.hpp"

namespace lashid::sim {

/// The design of one scheme of `config` (interval, held level, its m abscissas V_d or V_a) for an estimator of
/// capacity M >= config.m points (the entries past m are unused). Throws std::out_of_range when config.m > M or the
/// scheme's levels are missing.
template <class Scalar, int M>
est::ExperimentDesign<Scalar, M> experiment_design(const ExperimentConfig& config, est::Scheme scheme) {
  est::ExperimentDesign<Scalar, M> design;
  design.scheme = scheme;
  design.m = config.m;
  design.v_min = static_cast<Scalar>(config.v_min);
  design.v_max = static_cast<Scalar>(config.v_max);
  const auto& V = scheme == est::Scheme::kDescending ? config.V_d : config.V_a;
  if (config.m < 1 || config.m > M) throw std::out_of_range("experiment_design: m outside the capacity");
  for (int j = 0; j < config.m; ++j) design.V(j) = static_cast<Scalar>(V.at(static_cast<std::size_t>(j)));
  return design;
}

}  // namespace lashid::sim
