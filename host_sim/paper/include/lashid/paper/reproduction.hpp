// Reproduction of the paper's experiments on the simulator: one identification of a scenario, the true Theta,
// and the Monte Carlo consistency check of Section 3.5.2.
#pragma once

#include <cstdint>
#include <vector>

#include "lashid/estimator/design.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/sim/scenario.hpp"

namespace lashid::sim {

/// Theta of (3.19c) from the truth: [a, mu_11..mu_n1, ..., mu_1m..mu_nm], mu_ij = b_i c_j, c_j = F~(W_j)/W_j.
std::vector<double> true_theta(const ExperimentConfig& config, est::Scheme scheme);

struct ScenarioRun {
  std::uint64_t seed = 1;
  int pulse_length = 0;   ///< N; 0 keeps the scenario's
  double input_lag = 0;   ///< lambda of Section 3.5.3
  double noise_variance = -1;  ///< < 0 keeps the scenario's
  Precision precision = Precision::kDouble;
};

/// Simulates only the phases of `scheme` and identifies it.
SchemeResult identify_scenario(const Scenario& scenario, est::Scheme scheme, const ScenarioRun& run);

struct MonteCarloSummary {
  int runs = 0;
  int pulse_length = 0;
  double eps = 0;
  int failures = 0;                    ///< runs whose estimate had a non-ok status
  double probability = 0;              ///< fraction of runs with ||Theta_hat - Theta|| / ||Theta|| < eps
  double mean_relative_error = 0;
  std::vector<double> relative_errors; ///< per run, in run order
  std::vector<double> theta_mean, theta_sd;
  std::vector<SchemeResult> results;   ///< per run, only when asked for (keep_results)
};

/// Section 3.5.2: `runs` repetitions with seeds first_seed, first_seed + 1, ...
MonteCarloSummary monte_carlo(const Scenario& scenario, est::Scheme scheme, int runs, int pulse_length, double eps,
                              std::uint64_t first_seed, bool keep_results = false);

}  // namespace lashid::sim
