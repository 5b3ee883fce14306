// `lashid design`: writes an experiment config from n, m, the interval and a level count, or checks a given one, by
// the rules of both readers of the file: the host's config reader (docs/data-format.md) and the firmware's
// run-time check (fw::check_design, on the float32 design the device would run).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "lashid/estimator/design.hpp"
#include "lashid/firmware/run_design.hpp"
#include "lashid/hil/config_design.hpp"
#include "lashid/io/config.hpp"
#include "lashid/io/data_error.hpp"
#include "lashid/io/files.hpp"
#include "lashid/io/json.hpp"

namespace lashid::app {

using namespace lashid::sim;

namespace {

// DataError's what() is "SOURCE: message"; callers that name the file themselves want the message alone.
std::string without_source(const DataError& error, std::string_view source) {
  std::string_view text = error.what();
  const std::string prefix = fmt::format("{}: ", source);
  if (text.starts_with(prefix)) text.remove_prefix(prefix.size());
  return std::string(text);
}

// What each side makes of a config: empty when it accepts it, else why not (naming the key).
struct Verdict {
  std::string firmware;
  std::optional<fw::RunDesign> run;  // the float32 design, when the config can be expressed as one
};

// The host estimator runs at the firmware image's capacity (io/config.hpp): a design is never one side's only.
static_assert(kMaxOrder == fw::kMaxOrder && kMaxPoints == fw::kMaxPoints);

Verdict judge(const ExperimentConfig& config, const std::string& source) {
  Verdict v;
  try {
    v.run = run_design_as_is(config, experiment_lengths(config), source);
  } catch (const DataError& e) {
    v.firmware = without_source(e, source);
    return v;
  }
  if (const fw::DesignStatus status = fw::check_design(*v.run); status != fw::DesignStatus::kOk) {
    v.firmware = fmt::format("{} (firmware status: {})", design_status_message(status, *v.run), fw::to_string(status));
  }
  return v;
}

std::string periods(int length, int period) {
  const int whole = length / period;
  const int rest = length % period;
  return rest == 0 ? fmt::format("{} periods", whole) : fmt::format("{} periods + {} samples", whole, rest);
}

void print_summary(const ExperimentConfig& c, const Verdict& v, const std::string& source) {
  const ExperimentLengths l = experiment_lengths(c);
  const int T = est::schedule::period(c.n, c.m);
  const auto given = [](bool present) { return present ? "" : "  (default)"; };
  fmt::print("{}: {}, n = {}, m = {}, [v_min, v_max] = [{}, {}]\n", source, to_string(c.op), c.n, c.m, c.v_min,
             c.v_max);
  fmt::print("  V_d = {}\n", c.V_d.empty() ? std::string("absent (no DIS)") : fmt::format("[{}]", fmt::join(c.V_d, ", ")));
  fmt::print("  V_a = {}\n", c.V_a.empty() ? std::string("absent (no AIS)") : fmt::format("[{}]", fmt::join(c.V_a, ", ")));
  fmt::print("  pulse period T = max(n,2)(m+3) = {}\n", T);
  fmt::print("  step_length    L = {} (each step experiment: {} samples){}\n", l.step_length,
             static_cast<std::int64_t>(l.step_length) + 1, given(c.step_length.has_value()));
  fmt::print("  pulse_length_d N = {} ({}){}\n", l.pulse_length_d, periods(l.pulse_length_d, T),
             given(c.pulse_length_d.has_value()));
  fmt::print("  pulse_length_a N = {} ({}){}\n", l.pulse_length_a, periods(l.pulse_length_a, T),
             given(c.pulse_length_a.has_value()));
  fmt::print("  val_length       = {}{}\n", l.val_length, given(c.val_length.has_value()));
  fmt::print("  val_seed         = {}{}\n", l.val_seed, given(c.val_seed.has_value()));
  if (v.run) {
    const FirmwareRunSamples s = firmware_run_samples(*v.run);
    fmt::print("  firmware run: {} samples = {} interval check + {} steps + {} pulses + {} validation\n", s.total(),
               s.interval_check, s.steps, s.pulses, s.validation);
  }
  fmt::print("  host estimator (n <= {}, m <= {}): fits\n", kMaxOrder, kMaxPoints);
  fmt::print("  firmware image (n <= {}, m <= {}, levels distinct in float32): {}\n", fw::kMaxOrder, fw::kMaxPoints,
             v.firmware.empty() ? "fits" : "does NOT fit: " + v.firmware);
}

// The reader of `design --check`: n and m up to the capacity the host estimator and the image share.
ConfigLimits check_limits() {
  return {.max_order = kMaxOrder,
          .max_points = kMaxPoints,
          .range_name = "what the host estimator and the firmware image can take"};
}

int run_check(const std::string& path) {
  const ExperimentConfig config = read_config_json(path, check_limits());
  const Verdict v = judge(config, path);
  print_summary(config, v, path);
  // One file for host and device: it passes only when both can run it.
  if (!v.firmware.empty()) throw DataError(path, "valid for the host, but the firmware image cannot run it: " + v.firmware);
  fmt::print("{}: valid for the host and the firmware image\n", path);
  return 0;
}

// Level i of K evenly spaced levels from v_min (i = 0) to v_max (i = K - 1). V_d and V_a take their shared levels
// from this one formula, so they agree bit for bit; (a (K-1-i) + b i) / (K-1) is exact whenever the level is (e.g.
// whole numbers), and only the 2m levels used are computed, whatever K.
double grid_level(double v_min, double v_max, int K, int i) {
  if (i == 0) return v_min;
  if (i == K - 1) return v_max;
  const double steps = K - 1;
  const double exact = (v_min * (steps - i) + v_max * i) / steps;
  if (std::isfinite(exact)) return exact;
  // Near the double range's end the products overflow; the weights' form cannot (a convex combination).
  return v_min * ((steps - i) / steps) + v_max * (i / steps);
}

// A rule the reader states on a config key ('val_length' = -1 must not be negative), said in terms of the option
// that gave the value: the options are at fault, not the file about to be written.
std::string in_option_terms(std::string message) {
  // The pair first: one option sets both pulse lengths, and a message naming both keys names it once.
  static constexpr std::pair<std::string_view, std::string_view> kOptions[] = {
      {"'pulse_length_d', 'pulse_length_a'", "--pulse-length"},
      {"'pulse_length_d'", "--pulse-length"}, {"'pulse_length_a'", "--pulse-length"},
      {"'step_length'", "--step-length"},     {"'val_length'", "--val-length"},
      {"'val_seed'", "--val-seed"},           {"'v_min'", "--v-min"},
      {"'v_max'", "--v-max"},                 {"'V_d'", "V_d (from --v-min, --v-max, --levels)"},
      {"'V_a'", "V_a (from --v-min, --v-max, --levels)"}};
  for (const auto& [key, option] : kOptions) {
    for (std::size_t at = message.find(key); at != std::string::npos; at = message.find(key, at + option.size())) {
      message.replace(at, key.size(), option);
    }
  }
  return message;
}

int run_write(const DesignArgs& a) {
  if (a.n < kMinOrder || a.n > kMaxOrder || a.m < kMinPoints || a.m > kMaxPoints) {
    throw std::invalid_argument(fmt::format("--n {} --m {}: need n in [{}, {}] and m in [{}, {}]; nothing written", a.n,
                                            a.m, kMinOrder, kMaxOrder, kMinPoints, kMaxPoints));
  }
  const int K = a.levels.value_or(a.m + 1);
  if (K < a.m + 1) {
    throw std::invalid_argument(fmt::format(
        "--levels {} must be at least m + 1 = {}: V_d takes the m lowest of the K levels and must stay below v_max, "
        "V_a the m highest and must stay above v_min; nothing written",
        K, a.m + 1));
  }
  // The document as the reader sees it, so that the reader's rules (and messages, naming the key) judge the options.
  std::vector<double> V_d;
  std::vector<double> V_a;
  for (int j = 0; j < a.m; ++j) {
    V_d.push_back(grid_level(a.v_min, a.v_max, K, j));
    V_a.push_back(grid_level(a.v_min, a.v_max, K, K - 1 - j));
  }
  nlohmann::json document = {
      {"n", a.n},
      {"m", a.m},
      {"v_min", a.v_min},
      {"v_max", a.v_max},
      {"operator", a.op},
      {"V_d", V_d},
      {"V_a", V_a},
      {"step_length", a.step_length},
      {"pulse_length_d", a.pulse_length.value_or(default_pulse_length(a.n, a.m))},
      {"pulse_length_a", a.pulse_length.value_or(default_pulse_length(a.n, a.m))},
      {"val_length", a.val_length},
      {"val_seed", a.val_seed}};
  ExperimentConfig config{};
  try {
    config = parse_config_json(document.dump(), a.out);
  } catch (const DataError& e) {
    throw std::invalid_argument(in_option_terms(without_source(e, a.out)) + "; nothing written");
  }
  const Verdict v = judge(config, a.out);
  if (!v.firmware.empty()) {
    throw std::invalid_argument("the firmware image could not run this design: " + in_option_terms(v.firmware) +
                                "; nothing written");
  }
  write_json_file(a.out, to_json(config));
  print_summary(config, v, a.out);
  fmt::print("wrote {}\n", a.out);
  return 0;
}

}  // namespace

int run_design(const DesignArgs& args) { return args.check.empty() ? run_write(args) : run_check(args.check); }

}  // namespace lashid::app
