// Recordings with a hidden effect, for testing `lashid diagnose`: a random plant (stable A of order n, B,
// borders, switch or backlash, noise level) with one or two physical effects the user's model does not contain, or
// none. The effects and their sizes are the truth, known only to the caller (the test), never written to the config.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "lashid/io/config.hpp"
#include "lashid/io/recording.hpp"
#include "lashid/plant/border.hpp"
#include "lashid/plant/effect.hpp"
#include "lashid/plant/linear_plant.hpp"

namespace lashid::sim {

/// The truth of one generated case.
struct HiddenEffect {
  Cause cause = Cause::kNone;    ///< the first hidden cause (kNone when there is none)
  std::vector<Cause> causes;     ///< every hidden cause, in the order asked for ({kNone} when there is none)
  double lambda = 0;             ///< input_lag
  int delay = 0;                 ///< dead_time
  double drift_total = 0;        ///< sensor_drift: offset change from the first to the last sample of the file
  double sensor_snr_db = 0;      ///< colored_noise: white sensor noise added to y, at this SNR
  OperatorKind true_operator = OperatorKind::kBacklash;  ///< the plant's operator (the config may say otherwise)
  /// The true borders at the experiment's levels (V_d and v_max); between them they are linear or curved, as the
  /// options asked.
  std::vector<double> border_v;
  std::vector<double> border_ascending, border_descending;
  /// The plant's borders themselves (ascending, descending), as the plant runs them: at the levels and linear in
  /// between, or curved on 400 segments. For checks of a fitted model against the truth.
  std::shared_ptr<const std::pair<Border, Border>> borders;
};

struct HiddenEffectCase {
  ExperimentConfig config;  ///< what the user believes: the design and the operator type, no truth
  Recording recording;      ///< step_d, dis, step_a, ais, val (val with small reversals)
  HiddenEffect effect;
  LinearModel model;
  double noise_variance = 0;  ///< of the white equation error
  /// The true model's output on val: the plant with every hidden effect but without the equation error and the
  /// sensor noise (the drift included). Its fit to the measured val is what a perfect model can reach.
  std::vector<double> val_true_output;
};

/// Lengths of the phases (about 15,000 samples in all).
struct HiddenEffectLengths {
  int step = 800;
  int pulses = 5000;
  int validation = 3000;
};

/// The borders' shape between the experiment's levels.
enum class BorderShape {
  kLinearBetweenLevels,  ///< exactly the model class the identification represents (m points per border)
  kCurved,               ///< smooth curves with tanh and sine terms, possibly non-monotone, as real borders are
};

struct HiddenEffectOptions {
  HiddenEffectLengths lengths;
  BorderShape borders = BorderShape::kLinearBetweenLevels;
};

/// Deterministic for (cause, seed). Magnitudes: lambda in [0.15, 0.5], delay in {1, 2, 3}, |drift_total| in
/// [0.3, 0.6] x the output's standard deviation, sensor SNR in [20, 30] dB.
HiddenEffectCase generate_hidden_effect_case(Cause cause, std::uint64_t seed, const HiddenEffectLengths& lengths = {});

/// One or more causes hidden at once (at most one each; none must come alone), deterministic for (causes, seed,
/// options). A single cause with linear borders gives exactly the case of the overload above. With curved borders
/// the plant, levels and sizes are the same as with linear ones; only the borders between the levels differ.
/// Throws std::invalid_argument for an empty list, a repeated cause, or none with another cause.
HiddenEffectCase generate_hidden_effect_case(std::span<const Cause> causes, std::uint64_t seed,
                                             const HiddenEffectOptions& options);

}  // namespace lashid::sim
