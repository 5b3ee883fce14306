#include "lashid/paper/reproduction.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace lashid::sim {

std::vector<double> true_theta(const ExperimentConfig& config, est::Scheme scheme) {
  if (!config.truth) throw std::invalid_argument("true_theta: the config carries no truth");
  const Truth& truth = *config.truth;
  const bool dis = scheme == est::Scheme::kDescending;
  const auto& V = dis ? config.V_d : config.V_a;
  const auto& F = dis ? truth.F_d : truth.F_a;
  const double held_level = dis ? config.v_max : config.v_min;
  // The operator's output at the held level: u_M = F^d(v_M) for the DIS, u_m for the AIS. It is F at W = 0,
  // which the truth gives through (3.7): A(1) ybar0 = B(1) u.
  double A1 = 1, B1 = 0;
  for (double a : truth.a) A1 += a;
  for (double b : truth.b) B1 += b;
  const double held_output = A1 / B1 * (dis ? truth.ybar0_d.value() : truth.ybar0_a.value());
  std::vector<double> theta(truth.a);
  for (std::size_t j = 0; j < V.size(); ++j) {
    const double c = (F[j] - held_output) / (V[j] - held_level);
    for (double b : truth.b) theta.push_back(b * c);
  }
  return theta;
}

SchemeResult identify_scenario(const Scenario& scenario, est::Scheme scheme, const ScenarioRun& run) {
  Scenario s = scenario;
  const bool dis = scheme == est::Scheme::kDescending;
  if (run.pulse_length > 0) (dis ? s.pulse_length_d : s.pulse_length_a) = run.pulse_length;
  if (run.noise_variance >= 0) s.noise_variance = run.noise_variance;
  SimulationOptions options;
  options.seed = run.seed;
  options.input_lag = run.input_lag;
  options.dis_phases = dis;
  options.ais_phases = !dis;
  options.validation_phase = false;
  const Recording rec = simulate(s, options);
  IdentifyOptions io;
  io.precision = run.precision;
  return identify_scheme(s.config, rec, scheme, io, s.name);
}

MonteCarloSummary monte_carlo(const Scenario& scenario, est::Scheme scheme, int runs, int pulse_length, double eps,
                              std::uint64_t first_seed, bool keep_results) {
  const std::vector<double> theta = true_theta(scenario.config, scheme);
  double theta_norm = 0;
  for (double x : theta) theta_norm += x * x;
  theta_norm = std::sqrt(theta_norm);

  MonteCarloSummary out;
  out.runs = runs;
  out.pulse_length = pulse_length;
  out.eps = eps;
  out.theta_mean.assign(theta.size(), 0.0);
  std::vector<double> sum_sq(theta.size(), 0.0);
  int hits = 0, ok_runs = 0;
  for (int r = 0; r < runs; ++r) {
    ScenarioRun run;
    run.seed = first_seed + static_cast<std::uint64_t>(r);
    run.pulse_length = pulse_length;
    const SchemeResult res = identify_scenario(scenario, scheme, run);
    if (keep_results) out.results.push_back(res);
    if (res.status != est::Status::kOk) {
      ++out.failures;
      out.relative_errors.push_back(std::numeric_limits<double>::infinity());
      continue;
    }
    ++ok_runs;
    double err = 0;
    for (std::size_t k = 0; k < theta.size(); ++k) {
      err += (res.theta[k] - theta[k]) * (res.theta[k] - theta[k]);
      out.theta_mean[k] += res.theta[k];
      sum_sq[k] += res.theta[k] * res.theta[k];
    }
    const double rel = std::sqrt(err) / theta_norm;
    out.relative_errors.push_back(rel);
    out.mean_relative_error += rel;
    if (rel < eps) ++hits;
  }
  out.probability = runs > 0 ? static_cast<double>(hits) / runs : 0.0;
  if (ok_runs > 0) {
    out.mean_relative_error /= ok_runs;
    out.theta_sd.resize(theta.size());
    for (std::size_t k = 0; k < theta.size(); ++k) {
      out.theta_mean[k] /= ok_runs;
      const double var = sum_sq[k] / ok_runs - out.theta_mean[k] * out.theta_mean[k];
      out.theta_sd[k] = std::sqrt(std::fmax(var, 0.0) * ok_runs / std::fmax(ok_runs - 1, 1));
    }
  }
  return out;
}

}  // namespace lashid::sim
