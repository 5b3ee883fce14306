// Named simulation scenarios (the paper's two examples and variants) and the recording generator.
//
// A recording holds the five phases of docs/data-format.md in the order step_d, dis, step_a, ais, val, simulated
// continuously on one plant: the operator's and the linear block's states carry over from phase to phase.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "lashid/io/config.hpp"
#include "lashid/io/recording.hpp"
#include "lashid/plant/linear_plant.hpp"
#include "lashid/plant/operators.hpp"

namespace lashid::sim {

struct Scenario {
  std::string name;
  std::string description;
  LinearModel model;           ///< in the scaling of (3.11c) when the borders are scaled, as the paper's are
  double noise_variance = 0;   ///< variance of the white Gaussian equation error xi
  std::function<std::unique_ptr<HysteresisOperator>()> make_operator;
  double initial_output = 0;   ///< u(-1): the operator starts at (v_min, initial_output), on its descendent border
  ExperimentConfig config;     ///< n, m, interval, V_d, V_a, operator kind (truth filled by scenario_truth())
  int step_length_d = 2000;    ///< L of the DIS step experiment (the phase has L + 1 samples, t = 0..L)
  int pulse_length_d = 2000;   ///< N of the DP experiment
  int step_length_a = 2000;
  int pulse_length_a = 2000;
  int validation_length = 2000;
};

/// The built-in scenarios: "dis_paper" (Section 3.5), "ais_paper" (Section 4.2).
const std::vector<Scenario>& builtin_scenarios();
/// Throws std::invalid_argument listing the known names when `name` is unknown.
const Scenario& find_scenario(std::string_view name);

struct SimulationOptions {
  std::uint64_t seed = 1;
  double input_lag = 0;        ///< lambda of G = (1-lambda)/(1-lambda q^-1) before the operator (Section 3.5.3)
  bool dis_phases = true;      ///< simulate step_d and dis
  bool ais_phases = true;      ///< simulate step_a and ais
  bool validation_phase = true;
  std::vector<double> validation_input;  ///< the val phase's input; empty: the simulator's own (stream_phases)
};

/// The scenario's actuator and plant, one sample at a time: v(t) -> [input lag] -> operator -> linear block + noise
/// -> y(t). Starts from rest (y = 0, operator at (v_min, initial_output)). simulate(), the in-process firmware
/// board and `lashid hil` all step the plant through this class, so they produce the same y for the same v and seed.
class ScenarioPlant {
 public:
  ScenarioPlant(const Scenario& scenario, std::uint64_t seed, double input_lag = 0.0);
  double step(double v);

 private:
  std::unique_ptr<HysteresisOperator> operator_;
  LinearPlant plant_;
};

/// Simulates the phases of `options` continuously, from rest (y = 0, operator at (v_min, C_d(v_min))).
/// Deterministic for a seed: the noise stream and the validation input use separate generators seeded from it.
Recording simulate(const Scenario& scenario, const SimulationOptions& options);

/// Samples per phase: step_d has step_d + 1 samples (t = 0..L), dis has pulse_d, and so on.
struct PhaseLengths {
  int step_d = 2000;
  int pulse_d = 2000;
  int step_a = 2000;
  int pulse_a = 2000;
  int validation = 2000;
};

/// The five-phase driver behind simulate(): the phases of `options` with the design `config` on any plant,
/// `plant(v)` returning y, called once per sample in recording order. The step and pulse inputs come from the
/// estimator's excitation generator; val is options.validation_input, or, when that is empty, lengths.validation
/// samples of random levels in [v_min, v_max] held for 1..20 samples, drawn from options.seed. options.input_lag is the caller's business (the plant's).
Recording simulate_phases(const ExperimentConfig& config, const PhaseLengths& lengths,
                          const SimulationOptions& options, const std::function<double(double)>& plant);

/// Receives each simulated sample as it is made, in recording order: its phase, v and y.
using SampleSink = std::function<void(Phase phase, double v, double y)>;

/// A sink that appends every sample to `rec` (the streamed simulations' Recording-returning forms).
SampleSink append_to(Recording& rec);

/// simulate_phases() without the recording: each sample goes to `sink` as it is simulated, and every input is
/// generated sample by sample (the excitation by its index, the validation input by a running generator), so the
/// memory used does not grow with the lengths (`lashid simulate` streams a design of 2^31 validation samples to its
/// file). The samples are those simulate_phases() records, in the same order.
void stream_phases(const ExperimentConfig& config, const PhaseLengths& lengths, const SimulationOptions& options,
                   const std::function<double(double)>& plant, const SampleSink& sink);

/// simulate() streamed to `sink` (stream_phases on the scenario's plant).
void stream_simulation(const Scenario& scenario, const SimulationOptions& options, const SampleSink& sink);

/// The true parameters in the scaling of (3.11c), obtained by replaying the experiments' inputs on the scenario's
/// operator alone (from its initial state): u at the held level after the step (u_M for (3.4), u_m for (4.1)) and
/// u at each pulse of the second period (F^d(V_j) of (3.2), F^a(V_j)); ybar0 = B(1) u_held / A(1). If the borders
/// are not already scaled (u_M - u_m != 1), b is multiplied and F divided by K = u_M - u_m (footnote 3).
Truth scenario_truth(const Scenario& scenario);

/// The scenario's config with the lengths simulate() runs, so that a written config says what its recording holds:
/// step_length (only when both step experiments have the same L, the config has one), pulse_length_d,
/// pulse_length_a and val_length. val_seed stays absent: simulate() draws its validation input from its own seed
/// with the simulator's generator (simulate_phases), not from a val_seed with the device's excitation.
ExperimentConfig config_with_lengths(const Scenario& scenario);


/// A DIS/AIS scenario whose actuator is `actuator` (any operator, e.g. a fitted FrictionGapOperator): the linear part
/// of dis_paper before its scaling (A = 1 + q^-1 + 0.21 q^-2, B = q^-1 - 0.5 q^-2), white noise of variance
/// `noise_variance`, n = 2, m = 6 levels over [v_min, v_max] (V_d = v_min, v_min/2, 0, v_max/2, 0.8 v_max, 0.9 v_max; V_a
/// mirrored), the truth from replaying the experiments on the actuator. The operator starts
/// where sliding down to v_min leaves it.
Scenario actuator_scenario(const HysteresisOperator& actuator, double v_min, double v_max, double noise_variance);

}  // namespace lashid::sim
