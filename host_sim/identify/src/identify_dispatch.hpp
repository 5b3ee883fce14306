// Private to host_sim: the estimator run on a recording, at the capacity (kMaxOrder, kMaxPoints) the firmware image
// has, with the config's n and m chosen at run time (SchemeIdentifier::configure(design, n), design.m): the host
// runs every design the image runs, with the code the image runs. One translation unit per precision
// (identify_float.cpp, identify_double.cpp), so the two build in parallel.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "lashid/estimator/identifier.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/io/compiled_design.hpp"
#include "identify_residual.hpp"

namespace lashid::sim::detail {

/// The first `count` entries of an estimator vector (the estimate of order n and m points; the rest is capacity).
template <class Vec>
std::vector<double> to_vector(const Vec& v, int count) {
  std::vector<double> out(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) out[static_cast<std::size_t>(i)] = static_cast<double>(v(i));
  return out;
}

inline std::string describe(est::Status s, const ExperimentConfig& config, est::Scheme scheme, double v) {
  if (s == est::Status::kInputOffDesign) {
    const bool dis = scheme == est::Scheme::kDescending;
    return fmt::format("v = {} is not on the design (held level {}, abscissas {} = [{}]), or two pulses are "
                       "closer than n = {} samples",
                       v, dis ? config.v_max : config.v_min, dis ? "V_d" : "V_a",
                       fmt::join(dis ? config.V_d : config.V_a, ", "), config.n);
  }
  return est::to_string(s);
}

template <class Scalar>
SchemeResult run(const ExperimentConfig& config, const Recording& recording, est::Scheme scheme,
                 std::string_view data_name, bool leave_out_unusable_y) {
  const bool dis = scheme == est::Scheme::kDescending;
  const Phase step_phase = dis ? Phase::kStepD : Phase::kStepA;
  const Phase pulse_phase = dis ? Phase::kDis : Phase::kAis;
  if (!recording.has(step_phase) || !recording.has(pulse_phase)) {
    throw DataError(data_name, fmt::format("the {} needs phases '{}' and '{}'", dis ? "DIS" : "AIS",
                                           to_string(step_phase), to_string(pulse_phase)));
  }
  if (config.n < kMinOrder || config.n > kMaxOrder) {
    throw DataError(data_name, fmt::format("n = {} is outside the compiled range [{}, {}]", config.n, kMinOrder,
                                           kMaxOrder));
  }
  if (config.m < kMinPoints || config.m > kMaxPoints) {
    throw DataError(data_name, fmt::format("m = {} is outside the compiled range [{}, {}]", config.m, kMinPoints,
                                           kMaxPoints));
  }
  const est::ExperimentDesign<Scalar, kMaxPoints> design = experiment_design<Scalar, kMaxPoints>(config, scheme);
  est::SchemeIdentifier<Scalar, kMaxOrder, kMaxPoints, est::GroupedLeastSquares> id;
  if (const est::Status s = id.configure(design, config.n); s != est::Status::kOk) {
    throw DataError(data_name, fmt::format("config rejected by the estimator: {}", est::to_string(s)));
  }
  // The config's sensor range, as the device applies it: in float32 with its bounds rounded outwards (the design
  // it is sent in: float32_sensor_range), exactly in double. A y outside it is a bad sensor value: left out, with the
  // rows that lag it, as the device leaves it out.
  Scalar range_lo = -std::numeric_limits<Scalar>::infinity(), range_hi = std::numeric_limits<Scalar>::infinity();
  if constexpr (std::is_same_v<Scalar, float>) {
    const std::array<float, 2> range = float32_sensor_range(config);
    range_lo = range[0];
    range_hi = range[1];
  } else if (config.sensor_range) {
    range_lo = (*config.sensor_range)[0];
    range_hi = (*config.sensor_range)[1];
  }
  std::int64_t out_of_range = 0;
  const auto feed = [&](Phase phase, auto add) {
    const auto samples = recording.phase(phase);
    const auto n = static_cast<std::size_t>(config.n);
    // Samples since the last y outside the sensor range, and since the last other unusable y of the phase (NaN,
    // infinite, or beyond what the estimator takes: est::usable, in the precision run; IdentifyOptions::
    // leave_out_unusable_y). A row whose y or any of its n lags is either is left out by the estimator, as on the
    // device, and is no error then; an unusable y is an error naming it unless the option says otherwise.
    std::size_t since_range = n + 1, since_unusable = n + 1;
    for (std::size_t t = 0; t < samples.size(); ++t) {
      Scalar y = static_cast<Scalar>(samples[t].y);
      const bool outside = est::usable(y) && !(y >= range_lo && y <= range_hi);
      if (outside) {
        y = std::numeric_limits<Scalar>::quiet_NaN();
        ++out_of_range;
      }
      since_range = outside ? 0 : since_range + 1;
      since_unusable = outside || est::usable(y) ? since_unusable + 1 : 0;
      const est::Status s = add(static_cast<Scalar>(samples[t].v), y);
      const bool left_out = since_range <= n || (leave_out_unusable_y && since_unusable <= n);
      const bool unexcused = !leave_out_unusable_y && since_unusable <= n;
      if (s == est::Status::kNonFinite && std::isfinite(samples[t].v) && left_out && !unexcused) continue;
      if (s != est::Status::kOk) {
        throw DataError(data_name, fmt::format("phase {} t = {}: {}", to_string(phase), t,
                                               describe(s, config, scheme, samples[t].v)));
      }
    }
  };
  feed(step_phase, [&](Scalar v, Scalar y) { return id.add_step_sample(v, y); });
  if (!id.step_mean().ready()) {
    // Said here, not as the first pulse sample's "before the step-experiment mean".
    const std::size_t samples = recording.phase(step_phase).size();
    throw DataError(data_name, fmt::format("phase {}: no usable sample for the step mean ({})", to_string(step_phase),
                                           out_of_range > 0
                                               ? fmt::format("{} of its {} outside the config's sensor_range",
                                                             out_of_range, samples)
                                               : fmt::format("its {} samples NaN or too large", samples)));
  }
  feed(pulse_phase, [&](Scalar v, Scalar y) { return id.add_pulse_sample(v, y); });

  const auto e = id.estimate();
  const int n = config.n, m = config.m;
  SchemeResult r;
  r.scheme = scheme;
  r.status = e.status;
  r.a = to_vector(e.a, n);
  r.b = to_vector(e.b, n);
  r.c = to_vector(e.c, m);
  r.F = to_vector(e.F, m);
  r.F_centered = to_vector(e.F_centered, m);
  r.theta = to_vector(e.ls.theta, n + n * m);  // [a_1..a_n, mu_11..mu_n1, ..., mu_1m..mu_nm] (recovery.hpp)
  r.theta_std_error = to_vector(e.ls.std_error, n + n * m);
  r.ybar0 = static_cast<double>(e.ybar0);
  r.held_output = static_cast<double>(e.held_output);
  r.noise_variance = static_cast<double>(e.ls.noise_variance);
  r.rcond = static_cast<double>(e.ls.rcond);
  r.rows = e.ls.rows;
  r.step_samples = id.step_samples();
  r.pulse_samples = id.pulse_samples();
  r.out_of_sensor_range = out_of_range;
  if constexpr (std::is_same_v<Scalar, float>) {
    // The float32 residual sum cancels (identify_residual.hpp): the variance from the residuals themselves, and the
    // standard errors, proportional to its square root, with it.
    const DirectResidual direct = direct_residual<Scalar, kMaxOrder, kMaxPoints>(
        design, n, id.step_mean().mean(), r.theta, recording.phase(pulse_phase), range_lo, range_hi);
    const auto dim = static_cast<std::uint32_t>(n + n * m);
    if (r.status == est::Status::kOk && direct.rows == r.rows && direct.rows > dim) {
      const double variance = direct.sum_of_squares / static_cast<double>(direct.rows - dim);
      if (r.noise_variance > 0) {
        for (double& se : r.theta_std_error) se *= std::sqrt(variance / r.noise_variance);
      } else {
        // Cancelled to 0, and the standard errors with it: their factors sqrt(diag) are the double run's.
        const SchemeResult reference = run<double>(config, recording, scheme, data_name, leave_out_unusable_y);
        if (reference.status == est::Status::kOk && reference.noise_variance > 0) {
          for (std::size_t k = 0; k < r.theta_std_error.size(); ++k) {
            r.theta_std_error[k] = reference.theta_std_error[k] * std::sqrt(variance / reference.noise_variance);
          }
        }
      }
      r.noise_variance = variance;
    }
  }
  return r;
}

extern template SchemeResult run<float>(const ExperimentConfig&, const Recording&, est::Scheme, std::string_view,
                                        bool);
extern template SchemeResult run<double>(const ExperimentConfig&, const Recording&, est::Scheme, std::string_view,
                                         bool);

}  // namespace lashid::sim::detail
