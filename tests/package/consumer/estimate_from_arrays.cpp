#include "estimate_from_arrays.hpp"

#include <lashid/estimator.hpp>

namespace consumer {

namespace est = lashid::est;

DisResult identify_dis(const float* v_step, const float* y_step, int step_samples, const float* v_pulse,
                       const float* y_pulse, int pulse_samples) {
  constexpr auto& paper = est::paper::kDisPaper<float>;
  est::ExperimentDesign<float, 6> design;
  design.scheme = est::Scheme::kDescending;
  design.v_min = paper.v_min;
  design.v_max = paper.v_max;
  for (int j = 0; j < 6; ++j) design.V(j) = paper.V_d[static_cast<unsigned>(j)];

  static est::SchemeIdentifier<float, 2, 6> identifier;  // static storage (772 B of .bss on the M4F), no heap
  DisResult out;
  if (identifier.configure(design, paper.n) != est::Status::kOk) return out;
  for (int t = 0; t < step_samples; ++t) (void)identifier.add_step_sample(v_step[t], y_step[t]);
  for (int t = 0; t < pulse_samples; ++t) (void)identifier.add_pulse_sample(v_pulse[t], y_pulse[t]);
  const auto e = identifier.estimate();
  out.status = static_cast<int>(e.status);
  for (int i = 0; i < 2; ++i) {
    out.a[i] = e.a(i);
    out.b[i] = e.b(i);
  }
  for (int j = 0; j < 6; ++j) out.F[j] = e.F(j);
  return out;
}

}  // namespace consumer
