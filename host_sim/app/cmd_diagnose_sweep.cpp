// `lashid diagnose-sweep`: many generated recordings with hidden effects (one cause each, or the pairs below),
// diagnosed and scored against the generator's truth: the numbers of docs/diagnose.md.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands.hpp"
#include "sweep_oracle.hpp"
#include "lashid/analysis/joint_model.hpp"
#include "lashid/diagnose/diagnosis.hpp"
#include "lashid/io/files.hpp"
#include "lashid/report/json.hpp"
#include "lashid/sim/hidden_effect.hpp"
#include "lashid/stats/metrics.hpp"

namespace lashid::app {

using namespace lashid::sim;

namespace {

// The pairs issue 12 asks the generator to hide.
const std::array<std::array<Cause, 2>, 4> kPairs = {{{Cause::kInputLag, Cause::kSensorDrift},
                                                     {Cause::kDeadTime, Cause::kColoredNoise},
                                                     {Cause::kDeadTime, Cause::kOperatorType},
                                                     {Cause::kSensorDrift, Cause::kColoredNoise}}};

// Whether the diagnosis found one hidden cause's size within the tolerance.
bool parameter_ok(Cause cause, const HiddenEffect& truth, const CauseParameters& found) {
  switch (cause) {
    case Cause::kInputLag:
      return std::abs(found.lambda.value_or(-1.0) - truth.lambda) <= 0.05;
    case Cause::kDeadTime:
      return found.delay.value_or(-1) == truth.delay;
    case Cause::kSensorDrift:
      return std::abs(found.drift_total.value_or(0.0) - truth.drift_total) <= 0.2 * std::abs(truth.drift_total);
    case Cause::kOperatorType:
      return found.op == truth.true_operator;
    default:
      return true;
  }
}

std::string names(std::span<const Cause> causes) {
  std::string text;
  for (Cause c : causes) {
    if (!text.empty()) text += '+';
    text += to_string(c);
  }
  return text;
}

// The true structure (the hidden causes with their true sizes, the true operator), as the diagnosis would fit it
// (under colored_noise, the diagnosis' IV and output error).
ModelStructure true_structure(const HiddenEffectCase& c, const DiagnosisOptions& options) {
  ModelStructure s;
  s.op = c.effect.true_operator;
  for (Cause cause : c.effect.causes) {
    if (cause == Cause::kInputLag) {
      s.input_lag = c.effect.lambda;
      s.border_segments = options.lag_border_segments;
      s.border_smoothness = options.lag_border_smoothness;
    }
    if (cause == Cause::kDeadTime) s.delay = c.effect.delay;
    if (cause == Cause::kSensorDrift) s.drift = true;
    if (cause == Cause::kColoredNoise) {
      s.instrumental = true;
      s.output_error = options.coloured_output_error;  // the estimator the diagnosis' colored_noise model uses
      s.output_error_restarts = options.coloured_output_error_restarts;
    }
  }
  return s;
}

// The true structure fitted on the identification phases by the same joint least squares, and the val fit of its
// simulation: what a perfect diagnosis reaches from these experiments. With curved borders the generator's own
// plant does better on val (its borders are exact between the levels, where the experiments never take the
// operator unless an input lag does); both are reported. With `oracle`, also the check of sweep_oracle.hpp.
struct TrueStructureFit {
  double fit = -std::numeric_limits<double>::infinity();
  std::optional<OracleCheck> oracle;
};

TrueStructureFit true_structure_fit(const HiddenEffectCase& c, const DiagnosisOptions& options, bool oracle) {
  const ModelStructure s = true_structure(c, options);
  const FlatRecording data = flatten(c.recording);
  const JointModel model = fit_joint_model(c.config, data, s);
  TrueStructureFit out;
  if (!model.ok) return out;
  if (oracle) out.oracle = oracle_check(c, data, s, model);
  out.fit = simulation_fit(model, data, data.size() - c.recording.phase(Phase::kVal).size(), data.size());
  return out;
}

// One diagnosed case scored against the truth. The fit requirement (fit_extended >= the true structure's fit - 3)
// applies where the effect is material: where the nominal model is more than 3 points below the true structure.
struct Score {
  bool causes_right = false;      ///< the same set of causes (order aside)
  bool parameters_right = false;  ///< and every hidden cause's size within tolerance
  bool material = false;
  bool fit_right = true;          ///< the fit requirement, where material
  bool plant_material = false, plant_fit_right = true;  ///< the same against the generator's plant
  bool hit() const { return causes_right && parameters_right && fit_right; }
};

Score score(const HiddenEffectCase& c, const Diagnosis& d, double fit_true, double fit_plant) {
  Score s;
  std::vector<Cause> hidden = c.effect.causes, found = d.causes;
  std::sort(hidden.begin(), hidden.end());
  std::sort(found.begin(), found.end());
  s.causes_right = hidden == found;
  s.parameters_right = s.causes_right;
  for (Cause cause : hidden) s.parameters_right = s.parameters_right && parameter_ok(cause, c.effect, d.parameters);
  s.material = c.effect.cause != Cause::kNone && fit_true - d.fit_nominal > 3.0;
  s.fit_right = !s.material || d.fit_extended >= fit_true - 3.0;
  s.plant_material = c.effect.cause != Cause::kNone && fit_plant - d.fit_nominal > 3.0;
  s.plant_fit_right = !s.plant_material || d.fit_extended >= fit_plant - 3.0;
  return s;
}

// Per row (hidden cause or pair): how often each answer was given, and the scores.
struct Row {
  std::string hidden;
  std::map<std::string, int> found;  ///< the found causes joined by '+'
  int cases = 0, hits = 0, causes_right = 0, parameters_right = 0, material = 0, fit_right = 0, gains = 0;
  int plant_material = 0, plant_fit_right = 0;
};

}  // namespace

int run_diagnose_sweep(const DiagnoseSweepArgs& args) {
  HiddenEffectOptions options;
  options.borders = parse_border_shape(args.borders);
  std::vector<std::vector<Cause>> rows_hidden;
  if (args.pairs) {
    for (const auto& pair : kPairs) rows_hidden.emplace_back(pair.begin(), pair.end());
  } else {
    for (Cause cause : kAllCauses) rows_hidden.push_back({cause});
  }
  if (!args.rows.empty()) {
    std::vector<std::vector<Cause>> chosen;
    for (const std::string& name : args.rows) {
      const auto it = std::find_if(rows_hidden.begin(), rows_hidden.end(),
                                   [&](const std::vector<Cause>& h) { return names(h) == name; });
      if (it == rows_hidden.end()) {
        std::string known;
        for (const auto& h : rows_hidden) known += (known.empty() ? "" : ", ") + names(h);
        throw std::invalid_argument(fmt::format("--row '{}' is not a row of this table ({}){}", name, known,
                                                args.pairs ? "" : "; pairs need --pairs"));
      }
      chosen.push_back(*it);
    }
    rows_hidden = std::move(chosen);
  }
  const DiagnosisOptions defaults;
  std::vector<Row> rows;
  nlohmann::json cases = nlohmann::json::array();
  double diagnosis_seconds = 0, slowest = 0;
  for (const std::vector<Cause>& hidden : rows_hidden) {
    Row row;
    row.hidden = names(hidden);
    for (int k = 0; k < args.seeds; ++k) {
      const std::uint64_t seed = args.first_seed + static_cast<std::uint64_t>(k);
      const HiddenEffectCase c = generate_hidden_effect_case(hidden, seed, options);
      const auto start = std::chrono::steady_clock::now();
      DiagnosisOptions options_for_case = defaults;
      if (args.oracle_regimes && c.effect.borders) {
        options_for_case.regime_oracle =
            DiagnosisOptions::KnownPlant{c.model.a, c.model.b, c.effect.borders->first, c.effect.borders->second};
      }
      const Diagnosis d = diagnose(c.config, c.recording, fmt::format("{}#{}", row.hidden, seed), options_for_case);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      diagnosis_seconds += seconds;
      slowest = std::max(slowest, seconds);
      const double fit_plant = stats::fit_percent(d.val_measured, c.val_true_output);
      const TrueStructureFit truth = true_structure_fit(c, defaults, args.oracle);
      const double fit_true = truth.fit;
      const Score s = score(c, d, fit_true, fit_plant);
      const std::string found = names(d.causes);
      ++row.found[found];
      ++row.cases;
      row.hits += s.hit();
      row.causes_right += s.causes_right;
      row.parameters_right += s.parameters_right;
      row.material += s.material;
      row.fit_right += s.material && s.fit_right;
      row.gains += d.fit_extended > d.fit_nominal;
      row.plant_material += s.plant_material;
      row.plant_fit_right += s.plant_material && s.plant_fit_right;
      cases.push_back({{"hidden", row.hidden}, {"seed", seed}, {"found", found}, {"parameters", to_json(d.parameters)},
                       {"hit", s.hit()}, {"fit_nominal", d.fit_nominal}, {"fit_extended", d.fit_extended},
                       {"fit_true_structure", fit_true}, {"fit_plant", fit_plant}, {"n", c.config.n}, {"m", c.config.m}, {"seconds", seconds},
                       {"truth", {{"lambda", c.effect.lambda}, {"delay", c.effect.delay},
                                  {"drift_total", c.effect.drift_total}, {"snr_db", c.effect.sensor_snr_db},
                                  {"operator", to_string(c.effect.true_operator)}}},
                       {"oracle", to_json(truth.oracle)}});
      if (args.verbose) {
        std::string steps;
        for (const AddedCause& a : d.added) {
          steps += fmt::format(" +{} LR {:.0f} Q {:.0f}->{:.0f} fit {:.1f}->{:.1f};", to_string(a.cause),
                               a.likelihood_ratio, a.ljung_box_before, a.ljung_box_after, a.fit_before, a.fit_after);
        }
        for (const CandidateCause& cand : d.candidates) {
          steps += fmt::format(" [{} LR {:.0f} Q {:.0f} fit {:.1f}]", to_string(cand.cause).substr(0, 5),
                               cand.likelihood_ratio, cand.identification.whiteness.statistic, cand.fit_val);
        }
        fmt::print("{} {} seed {} n={} m={} {} -> {} {} (fit {:.1f} -> {:.1f}, true {:.1f}) truth l={:.3f} d={} "
                   "D={:.3g} |{} {:.2f} s (plant {:.1f})\n",
                   s.hit() ? "hit " : "MISS", row.hidden, seed, c.config.n, c.config.m,
                   to_string(c.effect.true_operator), found, to_string(d.parameters), d.fit_nominal, d.fit_extended,
                   fit_true, c.effect.lambda, c.effect.delay, c.effect.drift_total, steps, seconds, fit_plant);
        if (truth.oracle) {
          const OracleCheck& o = *truth.oracle;
          fmt::print("     oracle (one-step error / rows x noise variance; val fit): true plant on the fit's tables "
                     "{:.2f} ({:.1f} %); true-structure fit {:.2f} as fitted, {:.2f} with its own regimes ({:.1f} "
                     "%); fitted from the true regimes {:.2f} as fitted, {:.2f} with its own ({:.1f} %), held to them "
                     "{:.2f} ({:.1f} %); with a regime search {:.2f} ({:.1f} %)\n",
                     o.truth, o.val_truth, o.fit_rss, o.fit_consistent, o.val_fit, o.from_true_regimes_rss,
                     o.from_true_regimes, o.val_from_true_regimes, o.from_true_regimes_consistent,
                     o.val_from_true_regimes_consistent, o.regime_search, o.val_regime_search);
        }
        std::fflush(stdout);
      }
    }
    rows.push_back(std::move(row));
  }
  const int total = args.seeds * static_cast<int>(rows_hidden.size());
  fmt::print("{} recordings per row, seeds {}..{}, {} borders; {:.2f} s per diagnosis (slowest {:.2f} s){}\n\n",
             args.seeds, args.first_seed, args.first_seed + static_cast<std::uint64_t>(args.seeds) - 1, args.borders,
             diagnosis_seconds / total, slowest,
             args.oracle_regimes ? "; --oracle-regimes: the lag search started from the true plant, not a diagnosis"
                                 : "");
  int hits = 0;
  nlohmann::json table = nlohmann::json::array();
  for (const Row& r : rows) {
    std::string answers;
    for (const auto& [found, count] : r.found) answers += fmt::format(" {} {}", found, count);
    fmt::print("{:<28} hit {:>3}/{:<3} causes {:>3} parameters {:>3} fit {:>3}/{:<3} plant {:>3}/{:<3} gain {:>3} |{}\n",
               r.hidden, r.hits, r.cases, r.causes_right, r.parameters_right, r.fit_right, r.material,
               r.plant_fit_right, r.plant_material, r.gains, answers);
    hits += r.hits;
    table.push_back({{"hidden", r.hidden}, {"found", r.found}, {"cases", r.cases}, {"hits", r.hits},
                     {"causes_right", r.causes_right}, {"parameters_right", r.parameters_right},
                     {"material", r.material}, {"fit_right", r.fit_right}, {"plant_material", r.plant_material},
                     {"plant_fit_right", r.plant_fit_right}, {"gains", r.gains}});
  }
  fmt::print("\n{} of {} hits\n", hits, total);
  if (!args.json_out.empty()) {
    write_json_file(args.json_out, {{"seeds", args.seeds}, {"first_seed", args.first_seed},
                                    {"borders", args.borders}, {"pairs", args.pairs},
                                    {"oracle_regimes", args.oracle_regimes}, {"rows", table},
                                    {"seconds_per_diagnosis", diagnosis_seconds / total}, {"cases", cases}});
  }
  return 0;
}

}  // namespace lashid::app
