// Private to host_sim: the estimator run for one model order N, shared by identify_order<N>.cpp. Each order is
// instantiated in its own translation unit (identify_order_1.cpp ...): the 2 x kMaxPoints estimator instantiations
// per order are the heaviest compile of the project, and split this way they build in parallel.
#pragma once

#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "lashid/estimator/identifier.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/io/compiled_design.hpp"

namespace lashid::sim::detail {

template <class Vec>
std::vector<double> to_vector(const Vec& v) {
  std::vector<double> out(static_cast<std::size_t>(v.size()));
  for (Eigen::Index i = 0; i < v.size(); ++i) out[static_cast<std::size_t>(i)] = static_cast<double>(v(i));
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

template <class Scalar, int N, int M, template <class, int, int> class Solver>
SchemeResult run(const ExperimentConfig& config, const Recording& recording, est::Scheme scheme,
                 std::string_view data_name) {
  const bool dis = scheme == est::Scheme::kDescending;
  const Phase step_phase = dis ? Phase::kStepD : Phase::kStepA;
  const Phase pulse_phase = dis ? Phase::kDis : Phase::kAis;
  if (!recording.has(step_phase) || !recording.has(pulse_phase)) {
    throw DataError(data_name, fmt::format("the {} needs phases '{}' and '{}'", dis ? "DIS" : "AIS",
                                           to_string(step_phase), to_string(pulse_phase)));
  }
  const est::ExperimentDesign<Scalar, M> design = experiment_design<Scalar, M>(config, scheme);
  est::SchemeIdentifier<Scalar, N, M, Solver> id;
  if (const est::Status s = id.configure(design); s != est::Status::kOk) {
    throw DataError(data_name, fmt::format("config rejected by the estimator: {}", est::to_string(s)));
  }
  const auto feed = [&](Phase phase, auto add) {
    const auto samples = recording.phase(phase);
    for (std::size_t t = 0; t < samples.size(); ++t) {
      const est::Status s = add(static_cast<Scalar>(samples[t].v), static_cast<Scalar>(samples[t].y));
      if (s != est::Status::kOk) {
        throw DataError(data_name, fmt::format("phase {} t = {}: {}", to_string(phase), t,
                                               describe(s, config, scheme, samples[t].v)));
      }
    }
  };
  feed(step_phase, [&](Scalar v, Scalar y) { return id.add_step_sample(v, y); });
  feed(pulse_phase, [&](Scalar v, Scalar y) { return id.add_pulse_sample(v, y); });

  const auto e = id.estimate();
  SchemeResult r;
  r.scheme = scheme;
  r.status = e.status;
  r.a = to_vector(e.a);
  r.b = to_vector(e.b);
  r.c = to_vector(e.c);
  r.F = to_vector(e.F);
  r.F_centered = to_vector(e.F_centered);
  r.theta = to_vector(e.ls.theta);
  r.theta_std_error = to_vector(e.ls.std_error);
  r.ybar0 = static_cast<double>(e.ybar0);
  r.held_output = static_cast<double>(e.held_output);
  r.noise_variance = static_cast<double>(e.ls.noise_variance);
  r.rcond = static_cast<double>(e.ls.rcond);
  r.rows = e.ls.rows;
  r.step_samples = id.step_samples();
  r.pulse_samples = id.pulse_samples();
  return r;
}

template <int N, int M>
SchemeResult dispatch_backend(const ExperimentConfig& c, const Recording& rec, est::Scheme s,
                              const IdentifyOptions& o, std::string_view name) {
  if (o.precision == Precision::kFloat) return run<float, N, M, est::GroupedLeastSquares>(c, rec, s, name);
  return run<double, N, M, est::GroupedLeastSquares>(c, rec, s, name);
}

/// One model order N: dispatches m and the precision. Explicitly instantiated in identify_order_<N>.cpp.
template <int N>
SchemeResult identify_order(const ExperimentConfig& c, const Recording& rec, est::Scheme s, const IdentifyOptions& o,
                            std::string_view name) {
  SchemeResult r;
  const bool found = with_compiled_points(c.m, [&]<int M>() { r = dispatch_backend<N, M>(c, rec, s, o, name); });
  if (!found) throw DataError(name, fmt::format("m = {} is outside the compiled range [1, {}]", c.m, kMaxPoints));
  return r;
}

extern template SchemeResult identify_order<1>(const ExperimentConfig&, const Recording&, est::Scheme,
                                               const IdentifyOptions&, std::string_view);
extern template SchemeResult identify_order<2>(const ExperimentConfig&, const Recording&, est::Scheme,
                                               const IdentifyOptions&, std::string_view);
extern template SchemeResult identify_order<3>(const ExperimentConfig&, const Recording&, est::Scheme,
                                               const IdentifyOptions&, std::string_view);

}  // namespace lashid::sim::detail
