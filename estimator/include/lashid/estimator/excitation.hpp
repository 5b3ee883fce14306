// Input signals of the two experiments of each scheme, sample by sample:
//   step experiment (3.4) (DIS) / (4.1) (AIS): the first sample at the opposite bound, then the held level;
//   pulse experiment (3.1) (DP) / (4.2) (AP): the held level except v(t_k + tau_j) = V_j, schedule of (3.25).
// N and M are capacities; the order n and the design's m are chosen at run time (n <= N, m <= M).
#pragma once

#include <cstdint>

#include "lashid/estimator/design.hpp"

namespace lashid::est {

template <class Scalar, int N, int M>
class ExcitationGenerator {
 public:
  /// `n` must lie in [1, N] and the design must be valid (SchemeIdentifier::configure checks both).
  explicit ExcitationGenerator(const ExperimentDesign<Scalar, M>& design, int n = N)
      : design_(design), n_(n), period_(schedule::period(n, design.m)) {}

  /// v(t) of the step experiment.
  Scalar step_input(std::int64_t t) const { return t == 0 ? design_.step_start_level() : design_.held_level(); }

  /// v(t) of the periodic pulse experiment.
  Scalar pulse_input(std::int64_t t) const { return pulse_input_at_phase(static_cast<int>(t % period_)); }

  /// v at `phase` = t mod T of the pulse experiment: callers that count the phase themselves avoid a 64-bit
  /// division per sample (a library call on Cortex-M).
  Scalar pulse_input_at_phase(int phase) const {
    const int j = schedule::pulse_at_phase(n_, design_.m, phase);
    return j == 0 ? design_.held_level() : design_.V(j - 1);
  }

  /// Pulse period T of (3.25).
  int period() const { return period_; }

  /// Generator form: the step experiment for `step_length` samples, then the pulse experiment forever.
  Scalar next() {
    const Scalar v = t_ < step_length_ ? step_input(t_) : pulse_input(t_ - step_length_);
    ++t_;
    return v;
  }
  void restart(std::int64_t step_length) {
    step_length_ = step_length;
    t_ = 0;
  }
  /// True while next() is still in the step experiment.
  bool in_step_experiment() const { return t_ < step_length_; }

 private:
  ExperimentDesign<Scalar, M> design_;
  int n_;
  int period_;
  std::int64_t step_length_ = 0;
  std::int64_t t_ = 0;
};

}  // namespace lashid::est
