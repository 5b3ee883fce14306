// The actuator and plant of a plant file (io/plant_file.hpp), one sample at a time, and recordings of it:
//   v(t) -> [input lag G = (1-lambda)/(1-lambda q^-1)] -> [dead time q^-d] -> switch/backlash F -> u(t)
//   A(q^-1) y = B(q^-1) u + xi,   measured y_m(t) = y(t) + e(t) + delta k
// with xi white (equation_noise_std), e AR(1) (sensor_noise) and the drift delta per sample, k counting the samples
// this plant has played from 0. The lag and the delay are linear and commute; both act before the operator.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include "lashid/firmware/run_design.hpp"
#include "lashid/io/config.hpp"
#include "lashid/io/plant_file.hpp"
#include "lashid/io/recording.hpp"
#include "lashid/plant/linear_plant.hpp"
#include "lashid/plant/operators.hpp"
#include "lashid/sim/scenario.hpp"

namespace lashid::sim {

/// Satisfies hal::PlantModel, so the host board and `lashid hil` play it like ScenarioPlant.
class FilePlant {
 public:
  /// The plant at rest: y and u histories zero, the operator at (v_start, C_d(v_start)) on its descending border
  /// (the lag filter resting at v_start and the delay line full of v_start), as ScenarioPlant starts at v_min. The
  /// callers pass the design's v_min. The equation noise is seeded with `seed` (as ScenarioPlant's), the sensor
  /// noise with a fixed mix of it, so the two streams are independent.
  FilePlant(const PlantSpec& spec, double v_start, std::uint64_t seed);
  double step(double v);

 private:
  std::unique_ptr<HysteresisOperator> operator_;
  LinearPlant plant_;
  std::optional<Ar1Noise> sensor_noise_;
  double drift_per_sample_;
  std::uint64_t samples_ = 0;
};

/// `lashid simulate --plant`: the five phases of a device run of `design` (the firmware's form of `config`, e.g.
/// hil's to_run_design) on the plant, without firmware: step_d (L + 1), dis (N_d), step_a (L + 1), ais (N_a) from the
/// estimator's excitation with the config's levels, then val (val_length) from the device's validation generator.
/// One plant, continuous from phase to phase, starting at the config's v_min. No interval check: it is not part of
/// a recording (docs/data-format.md). Throws DataError naming `plant_name` when the borders do not cover
/// [v_min, v_max].
Recording simulate_file_plant(const PlantSpec& spec, std::string_view plant_name, const ExperimentConfig& config,
                              const fw::RunDesign& design, std::uint64_t seed);

/// simulate_file_plant() streamed: each sample goes to `sink` as it is simulated, the validation input drawn from the
/// device's generator sample by sample, so memory does not grow with the design's lengths. The same samples in the
/// same order.
void stream_file_plant(const PlantSpec& spec, std::string_view plant_name, const ExperimentConfig& config,
                       const fw::RunDesign& design, std::uint64_t seed, const SampleSink& sink);

}  // namespace lashid::sim
