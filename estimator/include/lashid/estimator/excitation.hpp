// Input signals of the two experiments of each scheme, sample by sample:
//   step experiment (3.4) (DIS) / (4.1) (AIS): the first sample at the opposite bound, then the held level;
//   pulse experiment (3.1) (DP) / (4.2) (AP): the held level except v(t_k + tau_j) = V_j, schedule of (3.25).
#pragma once

#include <cstdint>

#include "lashid/estimator/design.hpp"

namespace lashid::est {

template <class Scalar, int N, int M>
class ExcitationGenerator {
 public:
  using Schedule = PulseSchedule<N, M>;

  explicit ExcitationGenerator(const ExperimentDesign<Scalar, M>& design) : design_(design) {}

  /// v(t) of the step experiment.
  Scalar step_input(std::int64_t t) const { return t == 0 ? design_.step_start_level() : design_.held_level(); }

  /// v(t) of the periodic pulse experiment.
  Scalar pulse_input(std::int64_t t) const {
    const int j = Schedule::pulse_at(t);
    return j == 0 ? design_.held_level() : design_.V(j - 1);
  }

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
  std::int64_t step_length_ = 0;
  std::int64_t t_ = 0;
};

}  // namespace lashid::est
