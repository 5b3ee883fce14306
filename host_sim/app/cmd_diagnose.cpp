// `lashid diagnose`, `lashid hidden-effect` (a recording with a hidden effect) and `lashid diagnose-sweep`
// (hit rate per cause and confusion matrix over many generated recordings, the numbers of docs/diagnose.md).
#include <array>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "commands.hpp"
#include "lashid/diagnose/diagnosis.hpp"
#include "lashid/io/files.hpp"
#include "lashid/report/diagnose_plot.hpp"
#include "lashid/report/json.hpp"
#include "lashid/sim/hidden_effect.hpp"

namespace lashid::app {

using namespace lashid::sim;

int run_diagnose(const DiagnoseArgs& args) {
  const ExperimentConfig config = read_config_json(args.config);
  const Recording rec = read_recording_csv(args.data);
  if (!args.json_out.empty()) check_can_write(args.json_out);
  if (!args.plot_out.empty()) check_can_write(args.plot_out);
  const Diagnosis d = diagnose(config, rec, args.data);
  for (const std::string& line : d.findings) fmt::print("- {}\n", line);
  fmt::print("cause: {} {}\nfit_nominal: {:.2f} %\nfit_extended: {:.2f} %\n", to_string(d.cause),
             to_string(d.parameters), d.fit_nominal, d.fit_extended);
  if (!args.plot_out.empty()) report::plot_diagnosis(d, args.plot_out);
  if (!args.json_out.empty()) write_json_file(args.json_out, to_json(d));
  return 0;
}

int run_hidden_effect(const HiddenEffectArgs& args) {
  const auto cause = parse_cause(args.cause);
  if (!cause) throw std::invalid_argument(fmt::format("unknown cause '{}'", args.cause));
  const HiddenEffectCase c = generate_hidden_effect_case(*cause, args.seed);
  check_can_write(args.data_out);
  check_can_write(args.config_out);
  write_json_file(args.config_out, to_json(c.config));
  try {
    write_recording_csv(args.data_out, c.recording,
                        {fmt::format("lashid hidden-effect --cause {} --seed {} (the effect is not in the config)",
                                     args.cause, args.seed)});
  } catch (...) {
    std::filesystem::remove(args.config_out);
    throw;
  }
  fmt::print("wrote {} and {} ({} samples; n = {}, m = {})\n", args.data_out, args.config_out, c.recording.size(),
             c.config.n, c.config.m);
  return 0;
}

namespace {

// Whether the diagnosis found the hidden effect: the cause, and its parameter within the tolerance.
bool parameter_ok(const HiddenEffect& truth, const Diagnosis& d) {
  switch (truth.cause) {
    case Cause::kInputLag:
      return std::abs(d.parameters.lambda.value_or(-1.0) - truth.lambda) <= 0.05;
    case Cause::kDeadTime:
      return d.parameters.delay.value_or(-1) == truth.delay;
    case Cause::kSensorDrift:
      return std::abs(d.parameters.drift_total.value_or(0.0) - truth.drift_total) <= 0.2 * std::abs(truth.drift_total);
    case Cause::kOperatorType:
      return d.parameters.op == truth.true_operator;
    default:
      return true;
  }
}

}  // namespace

int run_diagnose_sweep(const DiagnoseSweepArgs& args) {
  std::array<std::array<int, kAllCauses.size()>, kAllCauses.size()> confusion{};
  std::array<int, kAllCauses.size()> parameter_hits{}, gains{};
  nlohmann::json cases = nlohmann::json::array();
  const auto start = std::chrono::steady_clock::now();
  for (Cause cause : kAllCauses) {
    for (int k = 0; k < args.seeds; ++k) {
      const std::uint64_t seed = args.first_seed + static_cast<std::uint64_t>(k);
      const HiddenEffectCase c = generate_hidden_effect_case(cause, seed);
      const Diagnosis d = diagnose(c.config, c.recording, fmt::format("{}#{}", to_string(cause), seed));
      const auto row = static_cast<std::size_t>(cause);
      const auto col = static_cast<std::size_t>(d.cause);
      ++confusion[row][col];
      const bool hit = d.cause == cause && parameter_ok(c.effect, d);
      if (hit) ++parameter_hits[row];
      if (d.fit_extended > d.fit_nominal) ++gains[row];
      cases.push_back({{"cause", to_string(cause)}, {"seed", seed}, {"found", to_string(d.cause)},
                       {"parameters", to_json(d.parameters)}, {"hit", hit}, {"fit_nominal", d.fit_nominal},
                       {"fit_extended", d.fit_extended}, {"n", c.config.n}, {"m", c.config.m},
                       {"truth", {{"lambda", c.effect.lambda}, {"delay", c.effect.delay},
                                  {"drift_total", c.effect.drift_total}, {"snr_db", c.effect.sensor_snr_db}}}});
      if (args.verbose) {
        std::string evidence;
        for (const CandidateCause& cand : d.candidates) {
          evidence += fmt::format(" {}={:.3g}/Q{:.0f}", to_string(cand.cause).substr(0, 5), cand.statistic,
                                  cand.identification.whiteness.statistic);
        }
        fmt::print("{} {} seed {} n={} m={} -> {} {} (fit {:.1f} -> {:.1f}) truth l={:.3f} d={} D={:.3g} | Q {:.0f} "
                   "|{}\n",
                   hit ? "hit " : "MISS", to_string(cause), seed, c.config.n, c.config.m, to_string(d.cause),
                   to_string(d.parameters), d.fit_nominal, d.fit_extended, c.effect.lambda, c.effect.delay,
                   c.effect.drift_total, d.identification.whiteness.statistic, evidence);
      }
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fmt::print("{} recordings per cause, seeds {}..{}, {:.1f} s ({:.2f} s per diagnosis)\n\n", args.seeds,
             args.first_seed, args.first_seed + static_cast<std::uint64_t>(args.seeds) - 1, seconds,
             seconds / static_cast<double>(args.seeds * static_cast<int>(kAllCauses.size())));
  fmt::print("{:<15}", "hidden \\ found");
  for (Cause c : kAllCauses) fmt::print("{:>14}", to_string(c));
  fmt::print("{:>10}{:>10}\n", "hit %", "gain %");
  for (std::size_t r = 0; r < kAllCauses.size(); ++r) {
    fmt::print("{:<15}", to_string(kAllCauses[r]));
    for (std::size_t c = 0; c < kAllCauses.size(); ++c) fmt::print("{:>14}", confusion[r][c]);
    fmt::print("{:>10.0f}{:>10.0f}\n", 100.0 * parameter_hits[r] / args.seeds, 100.0 * gains[r] / args.seeds);
  }
  if (!args.json_out.empty()) {
    nlohmann::json matrix = nlohmann::json::object();
    for (std::size_t r = 0; r < kAllCauses.size(); ++r) {
      for (std::size_t c = 0; c < kAllCauses.size(); ++c) {
        matrix[std::string(to_string(kAllCauses[r]))][std::string(to_string(kAllCauses[c]))] = confusion[r][c];
      }
    }
    write_json_file(args.json_out, {{"seeds", args.seeds}, {"first_seed", args.first_seed}, {"confusion", matrix},
                                    {"cases", cases}});
  }
  return 0;
}

}  // namespace lashid::app
