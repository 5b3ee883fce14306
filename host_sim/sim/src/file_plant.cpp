// The plant of a plant file, built from the plant layer's operators (switch, backlash, input lag, dead time) and
// noises (the linear block's white equation error, Ar1Noise), and its five-phase recording.
#include "lashid/sim/file_plant.hpp"

#include <utility>
#include <vector>

#include "lashid/plant/border.hpp"
#include "lashid/firmware/validation_excitation.hpp"
#include "lashid/sim/scenario.hpp"

namespace lashid::sim {

namespace {

// Sensor noise seed: a fixed mix of --seed, so it does not replay the equation noise's stream.
constexpr std::uint64_t kSensorSeedMix = 0x5bd1e995ULL;

Border border_of(const std::vector<double>& v, const std::vector<double>& u) {
  std::vector<std::pair<double, double>> points;
  points.reserve(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) points.emplace_back(v[k], u[k]);
  return Border::from_table(std::move(points));
}

std::unique_ptr<HysteresisOperator> make_operator(const PlantSpec& spec) {
  Border ascending = border_of(spec.border_v, spec.border_ascending);
  Border descending = border_of(spec.border_v, spec.border_descending);
  std::unique_ptr<HysteresisOperator> op;
  if (spec.op == OperatorKind::kSwitch) {
    op = std::make_unique<SwitchOperator>(std::move(ascending), std::move(descending));
  } else {
    op = std::make_unique<BacklashOperator>(std::move(ascending), std::move(descending));
  }
  if (spec.dead_time > 0) op = std::make_unique<DeadTimeOperator>(std::move(op), spec.dead_time);
  if (spec.input_lag > 0.0) op = std::make_unique<InputLagOperator>(std::move(op), spec.input_lag);
  return op;
}

}  // namespace

FilePlant::FilePlant(const PlantSpec& spec, double v_start, std::uint64_t seed)
    : operator_(make_operator(spec)),
      plant_(LinearModel{spec.a, spec.b}, spec.equation_noise_std * spec.equation_noise_std, seed),
      drift_per_sample_(spec.sensor_drift_per_sample) {
  if (spec.sensor_noise) sensor_noise_.emplace(spec.sensor_noise->std, spec.sensor_noise->pole, seed ^ kSensorSeedMix);
  // C_d(v_start): the descending border is linear between the grid points (Border::from_table).
  operator_->reset(v_start, border_of(spec.border_v, spec.border_descending)(v_start));
}

double FilePlant::step(double v) {
  double y = plant_.step(operator_->step(v));
  if (sensor_noise_) y += sensor_noise_->next();
  y += drift_per_sample_ * static_cast<double>(samples_++);
  return y;
}

Recording simulate_file_plant(const PlantSpec& spec, std::string_view plant_name, const ExperimentConfig& config,
                              const fw::RunDesign& design, std::uint64_t seed) {
  Recording rec;
  stream_file_plant(spec, plant_name, config, design, seed, append_to(rec));
  return rec;
}

void stream_file_plant(const PlantSpec& spec, std::string_view plant_name, const ExperimentConfig& config,
                       const fw::RunDesign& design, std::uint64_t seed, const SampleSink& sink) {
  check_plant_covers(spec, config.v_min, config.v_max, plant_name);
  SimulationOptions options;
  options.seed = seed;
  options.validation_phase = false;  // below, from the device's generator
  FilePlant plant(spec, config.v_min, seed);
  const auto step = static_cast<int>(design.step_length);
  const PhaseLengths phases{step, static_cast<int>(design.pulse_length_d), step, static_cast<int>(design.pulse_length_a),
                            static_cast<int>(design.val_length)};
  stream_phases(config, phases, options, [&plant](double v) { return plant.step(v); }, sink);
  // The device's validation input (its own generator, so that a recording simulated from a config and one recorded
  // through the firmware apply the same input): the float the device sends, widened to double.
  fw::ValidationExcitation excitation(design);
  for (std::uint32_t t = 0; t < design.val_length; ++t) {
    const auto v = static_cast<double>(excitation.next());
    sink(Phase::kVal, v, plant.step(v));
  }
}

}  // namespace lashid::sim
