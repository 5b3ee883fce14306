// Private to host_sim/identify: the residual variance of an estimate computed from its residuals, for the float32 run
// (`lashid identify --float`).
//
// The estimator (estimator/grouped_rls.hpp) forms the residual sum of squares as info(n, n) - r' a, a difference of
// two sums the size of the output's scatter. In float32 it cancels: its rounding, about eps32 = 6e-8 of the scatter,
// is larger than the residual sum itself when the model fits well, and the difference is clamped at 0. On the
// noise-free dis_paper recording the float32 run reported 0 (and standard errors of 0), while the double run of the
// same data reports 4.1e-5 (the recording does not fit the model exactly: the pulses' transients). The firmware
// cannot take a second pass over its data; the host can: here each row the estimator used is rebuilt with the
// estimator's own regressor (float32, as it saw it) and its residual y~ - Phi' Theta formed in double from the float32
// Theta, so the sum has no cancellation.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "lashid/estimator/design.hpp"
#include "lashid/estimator/regressor.hpp"
#include "lashid/estimator/status.hpp"
#include "lashid/io/recording.hpp"

namespace lashid::sim::detail {

struct DirectResidual {
  double sum_of_squares = 0;
  std::uint32_t rows = 0;  ///< rows whose residual was summed: the estimator's rows, if the pass agrees with it
};

/// The residuals of `theta` (n + n m entries, the estimator's order) over the pulse phase `samples`, with the rows
/// built as SchemeIdentifier::add_pulse_sample builds them: y~ = y - step_mean in Scalar, a y outside
/// [range_lo, range_hi] or not est::usable is NaN, and a row holding a NaN (or off the design) is not a row.
template <class Scalar, int N, int M>
DirectResidual direct_residual(const est::ExperimentDesign<Scalar, M>& design, int n, Scalar step_mean,
                               const std::vector<double>& theta, std::span<const Sample> samples, Scalar range_lo,
                               Scalar range_hi) {
  est::RegressorBuilder<Scalar, N, M> builder(design.W(), n, design.m);
  const Scalar held = design.held_level();
  DirectResidual out;
  for (const Sample& sample : samples) {
    Scalar y = static_cast<Scalar>(sample.y);
    if (est::usable(y) && !(y >= range_lo && y <= range_hi)) y = std::numeric_limits<Scalar>::quiet_NaN();
    const Scalar y_tilde = est::usable(y) ? y - step_mean : std::numeric_limits<Scalar>::quiet_NaN();
    const Scalar v_tilde = static_cast<Scalar>(sample.v) - held;
    if (builder.ready()) {
      est::SparseRegressor<Scalar, N, M> row;
      if (builder.sparse(row) == est::Status::kOk) {
        double residual = static_cast<double>(y_tilde);
        for (int i = 0; i < n; ++i) {
          residual -= static_cast<double>(row.phi_y(i)) * theta[static_cast<std::size_t>(i)];
        }
        if (row.input_column >= 0) {
          residual -= static_cast<double>(row.input_value) *
                      theta[static_cast<std::size_t>(n + row.input_column)];
        }
        if (std::isfinite(residual)) {
          out.sum_of_squares += residual * residual;
          ++out.rows;
        }
      }
    }
    builder.push(v_tilde, y_tilde);
  }
  return out;
}

}  // namespace lashid::sim::detail
