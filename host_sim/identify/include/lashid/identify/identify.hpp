// Runs the estimator (estimator/, compile-time n and m) on a recording (runtime n and m): dispatches the config's
// orders to the compiled instantiations and copies the estimate into runtime-sized vectors. Same estimator code
// as the firmware; double by default, float32 on request to see what the target would compute.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "lashid/estimator/cross_check.hpp"
#include "lashid/estimator/design.hpp"
#include "lashid/estimator/status.hpp"
#include "lashid/io/config.hpp"
#include "lashid/io/recording.hpp"

namespace lashid::sim {

enum class Precision { kDouble, kFloat };

// The least squares is always the recursive estimator the firmware runs (GroupedLeastSquares). The batch (3.21)
// reference is used by the tests at fixed orders: instantiating its fixed-size eigen-solvers for every (n, m) of
// the dispatch would cost minutes of compile time for no user-facing benefit.
struct IdentifyOptions {
  Precision precision = Precision::kDouble;
  /// A sample whose y the estimator cannot take (NaN, infinite, or beyond est::kMaxSampleMagnitude in the precision
  /// run) is left out with the rows that lag it, as the firmware leaves out a bad sensor value, instead of being an
  /// error naming it: for `lashid hil`'s check of a recording against the device's estimates (the samples the
  /// firmware set aside are NaN there; a finite reading too large for the estimator passes the firmware's sensor
  /// test when the design gives no sensor range). Files read by `lashid identify` never hold NaN.
  bool leave_out_unusable_y = false;
};

/// One scheme's estimate, in the paper's order and the scaling of (3.11c).
struct SchemeResult {
  est::Scheme scheme = est::Scheme::kDescending;
  est::Status status = est::Status::kNotExcited;
  std::vector<double> a, b, c, F, F_centered, theta, theta_std_error;
  double ybar0 = 0;         ///< step-experiment mean (3.7)
  double held_output = 0;   ///< A(1)/B(1) ybar0: u_M (DIS) or u_m (AIS)
  double noise_variance = 0;
  double rcond = 0;
  std::uint32_t rows = 0;
  std::int64_t step_samples = 0;
  std::int64_t pulse_samples = 0;
  /// Samples of the two phases whose y lay outside the config's sensor_range: left out with the rows that lag them,
  /// as the device leaves out a bad sensor value (docs/data-format.md).
  std::int64_t out_of_sensor_range = 0;
};

/// Identifies one scheme from its two phases (step_d + dis, or step_a + ais). A y outside the config's sensor_range
/// is left out as the device leaves it out (SchemeResult::out_of_sensor_range). Throws DataError (naming the data
/// source, phase, t and the reason) when a sample is off the design of `config`, or when the phases are missing.
/// Numerical failure (ill-conditioning, degenerate gain) is not thrown: it is the result's status.
SchemeResult identify_scheme(const ExperimentConfig& config, const Recording& recording, est::Scheme scheme,
                             const IdentifyOptions& options, std::string_view data_name);

/// Remark 3b on the two schemes' results of one recording: est::cross_check over a and b, with se(a_i) and
/// se(mu_i1) from the results' theta_std_error and se(b_i) = (v_M - v_m) se(mu_i1). Status kNotExcited when a
/// result has no standard errors (its scheme failed).
est::CrossCheck<double> cross_check(const ExperimentConfig& config, const SchemeResult& dis, const SchemeResult& ais);

/// Supported orders of the runtime dispatch (the compiled instantiations).
inline constexpr int kDispatchMaxOrder = kMaxOrder;
inline constexpr int kDispatchMaxPoints = kMaxPoints;

}  // namespace lashid::sim
