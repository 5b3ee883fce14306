// An experiment config (runtime n, m) as the estimator's compile-time types: the orders dispatched to the compiled
// instantiations, and the ExperimentDesign of one scheme. Shared by the estimator run on a recording (identify/)
// and the excitation of a simulation (sim/), so both read a config the same way.
#pragma once

#include <cstddef>
#include <utility>

#include "lashid/estimator/design.hpp"
#include "lashid/io/config.hpp"

namespace lashid::sim {

namespace detail {

template <class F, int... Is>
bool with_compiled(int value, std::integer_sequence<int, Is...>, F&& f) {
  return ((value == Is + 1 ? (f.template operator()<Is + 1>(), true) : false) || ...);
}

}  // namespace detail

/// Calls f.template operator()<N>() with N = n when n is in the compiled range [1, kMaxOrder]; false otherwise.
template <class F>
bool with_compiled_order(int n, F&& f) {
  static_assert(kMinOrder == 1);
  return detail::with_compiled(n, std::make_integer_sequence<int, kMaxOrder>{}, std::forward<F>(f));
}

/// Calls f.template operator()<M>() with M = m when m is in the compiled range [1, kMaxPoints]; false otherwise.
template <class F>
bool with_compiled_points(int m, F&& f) {
  static_assert(kMinPoints == 1);
  return detail::with_compiled(m, std::make_integer_sequence<int, kMaxPoints>{}, std::forward<F>(f));
}

/// The design of one scheme of `config` (interval, held level, abscissas V_d or V_a) for an estimator compiled for
/// M = config.m points.
template <class Scalar, int M>
est::ExperimentDesign<Scalar, M> experiment_design(const ExperimentConfig& config, est::Scheme scheme) {
  est::ExperimentDesign<Scalar, M> design;
  design.scheme = scheme;
  design.v_min = static_cast<Scalar>(config.v_min);
  design.v_max = static_cast<Scalar>(config.v_max);
  const auto& V = scheme == est::Scheme::kDescending ? config.V_d : config.V_a;
  for (int j = 0; j < M; ++j) design.V(j) = static_cast<Scalar>(V.at(static_cast<std::size_t>(j)));
  return design;
}

}  // namespace lashid::sim
