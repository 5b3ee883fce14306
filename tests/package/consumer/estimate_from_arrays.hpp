// The estimator in your own firmware: arrays in, estimates out, no HAL, no heap (docs/package.md).
#pragma once

namespace consumer {

struct DisResult {
  int status = -1;  ///< lashid::est::Status as an int: 0 is ok
  float a[2] = {};  ///< A(q^-1) = 1 + a1 q^-1 + a2 q^-2
  float b[2] = {};  ///< B(q^-1) = b1 q^-1 + b2 q^-2, in the scaling of (3.11c)
  float F[6] = {};  ///< the descending border at the design's 6 levels, same scaling
};

/// The DIS of the paper's Section 3.5 design (n = 2, m = 6 on [-3, 4]) on samples you measured: the step experiment
/// (v_step, y_step: L + 1 samples) and the pulse experiment (v_pulse, y_pulse). The inputs must be the design's
/// (lashid::est::ExcitationGenerator makes them).
DisResult identify_dis(const float* v_step, const float* y_step, int step_samples, const float* v_pulse,
                       const float* y_pulse, int pulse_samples);

}  // namespace consumer
