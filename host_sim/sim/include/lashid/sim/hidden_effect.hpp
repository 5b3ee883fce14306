// Recordings with a hidden effect, for testing `lashid diagnose`: a random plant (stable A of order n, B,
// borders, switch or backlash, noise level) with one physical effect the user's model does not contain, or none.
// The effect and its size are the truth, known only to the caller (the test), never written to the config.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "lashid/io/config.hpp"
#include "lashid/io/recording.hpp"
#include "lashid/plant/effect.hpp"
#include "lashid/plant/linear_plant.hpp"

namespace lashid::sim {

/// The truth of one generated case.
struct HiddenEffect {
  Cause cause = Cause::kNone;
  double lambda = 0;             ///< input_lag
  int delay = 0;                 ///< dead_time
  double drift_total = 0;        ///< sensor_drift: offset change from the first to the last sample of the file
  double sensor_snr_db = 0;      ///< colored_noise: white sensor noise added to y, at this SNR
  OperatorKind true_operator = OperatorKind::kBacklash;  ///< the plant's operator (the config may say otherwise)
  std::vector<double> border_v;                           ///< the true borders: linear between these abscissas
  std::vector<double> border_ascending, border_descending;
};

struct HiddenEffectCase {
  ExperimentConfig config;  ///< what the user believes: the design and the operator type, no truth
  Recording recording;      ///< step_d, dis, step_a, ais, val (val with small reversals)
  HiddenEffect effect;
  LinearModel model;
  double noise_variance = 0;  ///< of the white equation error
};

/// Lengths of the phases (about 15,000 samples in all).
struct HiddenEffectLengths {
  int step = 800;
  int pulses = 5000;
  int validation = 3000;
};

/// Deterministic for (cause, seed). Magnitudes: lambda in [0.15, 0.5], delay in {1, 2, 3}, |drift_total| in
/// [0.3, 0.6] x the output's standard deviation, sensor SNR in [20, 30] dB.
HiddenEffectCase generate_hidden_effect_case(Cause cause, std::uint64_t seed, const HiddenEffectLengths& lengths = {});

}  // namespace lashid::sim
