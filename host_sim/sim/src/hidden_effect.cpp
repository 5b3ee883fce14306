#include "lashid/sim/hidden_effect.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "lashid/plant/operators.hpp"
#include "lashid/sim/scenario.hpp"
#include "uniform_draw.hpp"

namespace lashid::sim {

namespace {

// A(q^-1) from its poles: real poles in [0.3, 0.85], complex pairs with radius in [0.5, 0.85].
std::vector<double> stable_denominator(int n, Draw& draw) {
  std::vector<double> poly{1.0};
  const auto multiply = [&](const std::vector<double>& factor) {
    std::vector<double> out(poly.size() + factor.size() - 1, 0.0);
    for (std::size_t i = 0; i < poly.size(); ++i) {
      for (std::size_t j = 0; j < factor.size(); ++j) out[i + j] += poly[i] * factor[j];
    }
    poly = std::move(out);
  };
  int left = n;
  if (n >= 2 && draw.coin(0.6)) {
    const double r = draw.uniform(0.5, 0.85);
    const double angle = draw.uniform(0.2, 1.0);
    multiply({1.0, -2.0 * r * std::cos(angle), r * r});
    left -= 2;
  }
  for (; left > 0; --left) multiply({1.0, -draw.uniform(0.3, 0.85)});
  return {poly.begin() + 1, poly.end()};
}

// Borders C_d = h + g and C_a = h - g: a rising base h with a gentle wave, and a half-gap g that closes at both
// ends (the borders meet at v_m and v_M). s in [0, 1] is the position in the input interval.
struct BorderCurves {
  double rise = 0, wave = 0, phase = 0, gap = 0;
  // Curved borders only (all zero for linear ones): a tanh step and a faster sine on h, a ripple on g. The sine's
  // slope can exceed the rise's, so the borders may be non-monotone.
  double tanh_height = 0, tanh_slope = 0, tanh_centre = 0.5;
  double sine_height = 0, sine_cycles = 0, sine_phase = 0;
  double gap_ripple = 0, gap_cycles = 0, gap_phase = 0;

  double half_sum(double s) const {
    constexpr double two_pi = 2.0 * std::numbers::pi;
    return rise * s + wave * std::sin(two_pi * s + phase) + tanh_height * std::tanh(tanh_slope * (s - tanh_centre)) +
           sine_height * std::sin(two_pi * sine_cycles * s + sine_phase);
  }
  double half_gap(double s) const {
    const double ripple = 1.0 + gap_ripple * std::sin(2.0 * std::numbers::pi * gap_cycles * s + gap_phase);
    // sin(pi s) is -1e-16 rather than 0 at s = 1 + rounding: clamp, so that pow stays real.
    return gap * std::pow(std::max(std::sin(std::numbers::pi * s), 0.0), 0.7) * ripple;
  }
};

// The curved terms come from their own generator (`curve_draw`), so that a case's plant, levels and effect sizes
// are the same whatever the border shape.
BorderCurves draw_border_curves(BorderShape shape, Draw& draw, Draw& curve_draw) {
  BorderCurves b;
  b.rise = draw.uniform(1.0, 3.0);
  b.wave = draw.uniform(0.0, 0.08) * b.rise;
  b.phase = draw.uniform(0.0, 2.0 * std::numbers::pi);
  b.gap = draw.uniform(0.15, 0.35) * b.rise;
  if (shape == BorderShape::kCurved) {
    b.tanh_height = curve_draw.uniform(0.05, 0.2) * b.rise * (curve_draw.coin(0.5) ? 1.0 : -1.0);
    b.tanh_slope = curve_draw.uniform(4.0, 12.0);
    b.tanh_centre = curve_draw.uniform(0.2, 0.8);
    b.sine_height = curve_draw.uniform(0.02, 0.05) * b.rise;
    b.sine_cycles = curve_draw.uniform(1.5, 4.0);
    b.sine_phase = curve_draw.uniform(0.0, 2.0 * std::numbers::pi);
    b.gap_ripple = curve_draw.uniform(0.0, 0.3);
    b.gap_cycles = curve_draw.uniform(1.0, 3.0);
    b.gap_phase = curve_draw.uniform(0.0, 2.0 * std::numbers::pi);
  }
  return b;
}

// Linear borders are drawn at the experiment's levels and linear in between, i.e. in the model class the
// identification can represent (m points per border). Curved ones are tabulated finely enough (400 segments) to
// be smooth at the scale of the levels' spacing.
std::pair<Border, Border> make_borders(const BorderCurves& curves, BorderShape shape, const std::vector<double>& grid) {
  std::vector<double> abscissas = grid;
  const double v_min = grid.front(), v_max = grid.back();
  if (shape == BorderShape::kCurved) {
    constexpr int kSegments = 400;
    abscissas.clear();
    for (int k = 0; k < kSegments; ++k) abscissas.push_back(v_min + (v_max - v_min) * k / kSegments);
    abscissas.push_back(v_max);
  }
  std::vector<std::pair<double, double>> ascending, descending;
  for (double v : abscissas) {
    const double s = (v - v_min) / (v_max - v_min);
    ascending.emplace_back(v, curves.half_sum(s) - curves.half_gap(s));
    descending.emplace_back(v, curves.half_sum(s) + curves.half_gap(s));
  }
  return {Border::from_table(std::move(ascending)), Border::from_table(std::move(descending))};
}

// Validation input: the experiment's levels held 3..20 samples, and in a third of the moves a small reversal
// (2-8 % of the interval away from the current level and back), where a switch jumps to the other border and a
// backlash holds.
std::vector<double> validation_levels(const std::vector<double>& grid, int length, Draw& draw) {
  std::vector<double> v;
  const int last = static_cast<int>(grid.size()) - 1;
  const double range = grid.back() - grid.front();
  int index = draw.integer(0, last);
  const auto hold = [&](double level) {
    const int samples = draw.integer(3, 20);
    for (int k = 0; k < samples && static_cast<int>(v.size()) < length; ++k) v.push_back(level);
  };
  while (static_cast<int>(v.size()) < length) {
    const double level = grid[static_cast<std::size_t>(index)];
    hold(level);
    if (draw.coin(0.35)) {
      const double step = draw.uniform(0.02, 0.08) * range;
      const bool up = index == 0 || (index != last && draw.coin(0.5));
      hold(up ? level + step : level - step);
      hold(level);
    }
    int next = index;
    while (next == index) next = draw.integer(0, last);
    index = next;
  }
  v.resize(static_cast<std::size_t>(length));
  return v;
}

double standard_deviation(const Recording& rec) {
  double sum = 0, sum2 = 0;
  std::size_t count = 0;
  for (Phase p : rec.order()) {
    for (const Sample& s : rec.phase(p)) {
      sum += s.y;
      sum2 += s.y * s.y;
      ++count;
    }
  }
  const double mean = sum / static_cast<double>(count);
  return std::sqrt(std::max(sum2 / static_cast<double>(count) - mean * mean, 0.0));
}

// Applies f(tau, y) to every output, tau being the sample index from the start of the file.
template <class F>
Recording map_outputs(const Recording& rec, F f) {
  Recording out;
  std::size_t tau = 0;
  for (Phase p : rec.order()) {
    for (const Sample& s : rec.phase(p)) out.append(p, s.v, f(tau++, s.y));
  }
  return out;
}

// The sizes of every effect, drawn for every case (so a case's plant does not depend on its cause's draw order);
// only the hidden one is applied.
struct EffectSizes {
  double lambda = 0;
  int delay = 0;
  double drift_fraction = 0;  ///< of the output's standard deviation, signed
  double snr_db = 0;
};

EffectSizes draw_effect_sizes(Draw& draw) {
  EffectSizes e;
  e.lambda = draw.uniform(0.15, 0.5);
  e.delay = draw.integer(1, 3);
  e.drift_fraction = draw.uniform(0.3, 0.6) * (draw.coin(0.5) ? 1.0 : -1.0);
  e.snr_db = draw.uniform(20.0, 30.0);
  return e;
}

// Design: V_d and V_a share their interior abscissas, so both borders are known at the same levels.
ExperimentConfig draw_design(int n, int m, Draw& draw) {
  ExperimentConfig cfg;
  cfg.n = n;
  cfg.m = m;
  cfg.v_min = draw.uniform(-3.0, 0.0);
  cfg.v_max = cfg.v_min + draw.uniform(2.0, 6.0);
  const double step = (cfg.v_max - cfg.v_min) / m;
  std::vector<double> interior;
  for (int k = 1; k < m; ++k) interior.push_back(cfg.v_min + (k + draw.uniform(-0.25, 0.25)) * step);
  cfg.V_d = {cfg.v_min};
  cfg.V_d.insert(cfg.V_d.end(), interior.begin(), interior.end());
  cfg.V_a = {cfg.v_max};
  cfg.V_a.insert(cfg.V_a.end(), interior.rbegin(), interior.rend());
  return cfg;
}

// The effects that act on the recorded output (drift, sensor noise) or on the user's belief (the operator type);
// the input lag and the dead time are in the plant's operator already. Records the truth in c.effect.
void apply_effect(HiddenEffectCase& c, Cause cause, const EffectSizes& e, std::uint64_t noise_seed) {
  switch (cause) {
    case Cause::kNone:
      break;
    case Cause::kInputLag:
      c.effect.lambda = e.lambda;
      break;
    case Cause::kDeadTime:
      c.effect.delay = e.delay;
      break;
    case Cause::kSensorDrift: {
      const double total = e.drift_fraction * standard_deviation(c.recording);
      const double last = static_cast<double>(c.recording.size() - 1);
      c.effect.drift_total = total;
      c.recording = map_outputs(c.recording, [&](std::size_t tau, double y) {
        return y + total * static_cast<double>(tau) / last;
      });
      break;
    }
    case Cause::kColoredNoise: {
      c.effect.sensor_snr_db = e.snr_db;
      GaussianNoise sensor(std::pow(standard_deviation(c.recording) / std::pow(10.0, e.snr_db / 20.0), 2.0),
                           noise_seed ^ 0x5bd1e995ULL);
      c.recording = map_outputs(c.recording, [&](std::size_t, double y) { return y + sensor.next(); });
      break;
    }
    case Cause::kOperatorType:
      c.config.op = other_operator(c.effect.true_operator);
      break;
  }
}

// The order-independent checks of a list of causes (see the header).
void check_causes(std::span<const Cause> causes) {
  if (causes.empty()) throw std::invalid_argument("generate_hidden_effect_case: no cause (use none)");
  for (std::size_t i = 0; i < causes.size(); ++i) {
    if (causes[i] == Cause::kNone && causes.size() > 1) {
      throw std::invalid_argument("generate_hidden_effect_case: none cannot be combined with another cause");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (causes[i] == causes[j]) throw std::invalid_argument("generate_hidden_effect_case: a cause is repeated");
    }
  }
}

bool contains(std::span<const Cause> causes, Cause cause) {
  return std::find(causes.begin(), causes.end(), cause) != causes.end();
}

}  // namespace

HiddenEffectCase generate_hidden_effect_case(Cause cause, std::uint64_t seed, const HiddenEffectLengths& lengths) {
  const std::array<Cause, 1> causes{cause};
  HiddenEffectOptions options;
  options.lengths = lengths;
  return generate_hidden_effect_case(causes, seed, options);
}

HiddenEffectCase generate_hidden_effect_case(std::span<const Cause> causes, std::uint64_t seed,
                                             const HiddenEffectOptions& options) {
  check_causes(causes);
  const HiddenEffectLengths& lengths = options.lengths;
  // A single cause keeps the seed of the one-cause generator (so its cases are unchanged); a second one moves it.
  constexpr std::uint64_t kSeedMix = 0x9e3779b97f4a7c15U, kCauseMix = 0x2545f4914f6cdd1dU;
  constexpr std::uint64_t kSecondCauseMix = 0xbf58476d1ce4e5b9U, kCurveMix = 0x94d049bb133111ebU;
  std::uint64_t stream = seed * kSeedMix + static_cast<std::uint64_t>(causes[0]) * kCauseMix + 1U;
  for (std::size_t i = 1; i < causes.size(); ++i) stream += static_cast<std::uint64_t>(causes[i]) * kSecondCauseMix * i;
  Draw draw(stream);
  Draw curve_draw(stream ^ kCurveMix);
  HiddenEffectCase c;
  c.effect.cause = causes[0];
  c.effect.causes.assign(causes.begin(), causes.end());
  const int n = draw.integer(1, 3);
  const int m = draw.integer(3, 6);

  // Linear part: stable A, positive B with DC gain in [0.8, 2].
  c.model.a = stable_denominator(n, draw);
  for (int i = 0; i < n; ++i) c.model.b.push_back(i == 0 ? 1.0 : draw.uniform(0.1, 0.8));
  double A1 = 1.0, B1 = 0.0;
  for (double a : c.model.a) A1 += a;
  for (double b : c.model.b) B1 += b;
  const double gain = draw.uniform(0.8, 2.0);
  for (double& b : c.model.b) b *= gain * A1 / B1;

  c.config = draw_design(n, m, draw);
  const ExperimentConfig& cfg = c.config;
  std::vector<double> grid = cfg.V_d;
  grid.push_back(cfg.v_max);

  const OperatorKind kind = draw.coin(0.5) ? OperatorKind::kSwitch : OperatorKind::kBacklash;
  c.effect.true_operator = kind;
  c.config.op = kind;
  const BorderCurves curves = draw_border_curves(options.borders, draw, curve_draw);
  const std::pair<Border, Border> borders = make_borders(curves, options.borders, grid);
  const Border& ascending = borders.first;
  const Border& descending = borders.second;
  c.effect.border_v = grid;
  c.effect.borders = std::make_shared<const std::pair<Border, Border>>(borders);
  for (double v : grid) {
    c.effect.border_ascending.push_back(ascending(v));
    c.effect.border_descending.push_back(descending(v));
  }
  const double rise_scale = descending(cfg.v_max) - descending(cfg.v_min);
  c.noise_variance = std::pow(draw.uniform(0.003, 0.01) * rise_scale * gain * A1, 2.0);

  const EffectSizes sizes = draw_effect_sizes(draw);
  const std::uint64_t noise_seed = draw.raw();
  const std::vector<double> validation = validation_levels(grid, lengths.validation, draw);

  Scenario s;
  s.name = "hidden_effect";
  s.model = c.model;
  s.noise_variance = c.noise_variance;
  s.config = cfg;
  s.step_length_d = s.step_length_a = lengths.step;
  s.pulse_length_d = s.pulse_length_a = lengths.pulses;
  s.validation_length = lengths.validation;
  s.initial_output = descending(cfg.v_min);
  const double lambda = contains(causes, Cause::kInputLag) ? sizes.lambda : 0.0;
  const int delay = contains(causes, Cause::kDeadTime) ? sizes.delay : 0;
  s.make_operator = [kind, lambda, delay, borders]() -> std::unique_ptr<HysteresisOperator> {
    std::unique_ptr<HysteresisOperator> op;
    if (kind == OperatorKind::kSwitch) {
      op = std::make_unique<SwitchOperator>(borders.first, borders.second);
    } else {
      op = std::make_unique<BacklashOperator>(borders.first, borders.second);
    }
    if (lambda > 0) op = std::make_unique<InputLagOperator>(std::move(op), lambda);
    if (delay > 0) op = std::make_unique<DeadTimeOperator>(std::move(op), delay);
    return op;
  };
  SimulationOptions simulation;
  simulation.seed = noise_seed;
  simulation.validation_input = validation;
  c.recording = simulate(s, simulation);

  // The true model's val output: the same plant and inputs without the equation error.
  Scenario noise_free = s;
  noise_free.noise_variance = 0;
  const Recording truth = simulate(noise_free, simulation);
  c.val_true_output.clear();
  for (const Sample& sample : truth.phase(Phase::kVal)) c.val_true_output.push_back(sample.y);

  for (Cause cause : causes) apply_effect(c, cause, sizes, noise_seed);
  if (c.effect.drift_total != 0) {
    // The drift is part of the plant's output as recorded: tau counts from the file's first sample.
    const double last = static_cast<double>(c.recording.size() - 1);
    const double first_val = static_cast<double>(c.recording.size() - c.val_true_output.size());
    for (std::size_t k = 0; k < c.val_true_output.size(); ++k) {
      c.val_true_output[k] += c.effect.drift_total * (first_val + static_cast<double>(k)) / last;
    }
  }
  return c;
}

}  // namespace lashid::sim
