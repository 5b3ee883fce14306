#include "lashid/sim/hidden_effect.hpp"

#include <cmath>
#include <numbers>
#include <random>
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
// ends (the borders meet at v_m and v_M). Drawn at the experiment's levels and linear in between, i.e. in the
// model class the identification can represent (m points per border); docs/diagnose.md reports what curved
// borders between the levels do to the input-lag estimate.
std::pair<Border, Border> random_borders(const std::vector<double>& grid, Draw& draw) {
  const double rise = draw.uniform(1.0, 3.0);
  const double wave = draw.uniform(0.0, 0.08) * rise;
  const double phase = draw.uniform(0.0, 2.0 * std::numbers::pi);
  const double gap = draw.uniform(0.15, 0.35) * rise;
  std::vector<std::pair<double, double>> ascending, descending;
  const double v_min = grid.front(), v_max = grid.back();
  for (double v : grid) {
    const double s = (v - v_min) / (v_max - v_min);
    const double h = rise * s + wave * std::sin(2.0 * std::numbers::pi * s + phase);
    const double g = gap * std::pow(std::sin(std::numbers::pi * s), 0.7);
    ascending.emplace_back(v, h - g);
    descending.emplace_back(v, h + g);
  }
  return {Border::from_table(std::move(ascending)), Border::from_table(std::move(descending))};
}

// Validation input: the experiment's levels held 3..20 samples, and in a third of the moves a small reversal
// (2-8 % of the interval away from the current level and back), where a switch jumps to the other border and a
// backlash holds. The borders are linear between the levels, so off-level inputs need no border extrapolation.
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
      c.config.op = c.effect.true_operator == OperatorKind::kSwitch ? OperatorKind::kBacklash : OperatorKind::kSwitch;
      break;
  }
}

}  // namespace

HiddenEffectCase generate_hidden_effect_case(Cause cause, std::uint64_t seed, const HiddenEffectLengths& lengths) {
  constexpr std::uint64_t kSeedMix = 0x9e3779b97f4a7c15U, kCauseMix = 0x2545f4914f6cdd1dU;
  Draw draw(seed * kSeedMix + static_cast<std::uint64_t>(cause) * kCauseMix + 1U);
  HiddenEffectCase c;
  c.effect.cause = cause;
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
  const std::pair<Border, Border> borders = random_borders(grid, draw);
  const Border& ascending = borders.first;
  const Border& descending = borders.second;
  c.effect.border_v = grid;
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
  s.make_operator = [kind, cause, borders, sizes]() -> std::unique_ptr<HysteresisOperator> {
    std::unique_ptr<HysteresisOperator> op;
    if (kind == OperatorKind::kSwitch) {
      op = std::make_unique<SwitchOperator>(borders.first, borders.second);
    } else {
      op = std::make_unique<BacklashOperator>(borders.first, borders.second);
    }
    if (cause == Cause::kInputLag) return std::make_unique<InputLagOperator>(std::move(op), sizes.lambda);
    if (cause == Cause::kDeadTime) return std::make_unique<DeadTimeOperator>(std::move(op), sizes.delay);
    return op;
  };
  SimulationOptions options;
  options.seed = noise_seed;
  options.validation_input = validation;
  c.recording = simulate(s, options);
  apply_effect(c, cause, sizes, noise_seed);
  return c;
}

}  // namespace lashid::sim
