// The experiment config JSON of docs/data-format.md: reader with key-naming errors, and the writer.
#include "lashid/io/config.hpp"
#include "lashid/io/json.hpp"

#include "lashid/estimator/design.hpp"
#include "lashid/io/files.hpp"
#include "json_document.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>  // fmt::join

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>

namespace lashid::sim {

namespace {

using nlohmann::json;

constexpr std::array<std::string_view, 14> kConfigKeys = {
    "n", "m", "v_min", "v_max", "V_d", "V_a", "operator",
    "step_length", "pulse_length_d", "pulse_length_a", "val_length", "val_seed", "sensor_range", "truth"};
constexpr std::array<std::string_view, 6> kTruthKeys = {"a", "b", "F_d", "F_a", "ybar0_d", "ybar0_a"};

// Turns the JSON document into an ExperimentConfig, naming the offending key in every error.
class ConfigReader : detail::JsonFieldReader {
 public:
  ConfigReader(std::string_view source_name, const ConfigLimits& limits)
      : JsonFieldReader(source_name), limits_(limits) {}

  ExperimentConfig read(const json& document) const {
    if (!document.is_object()) fail(fmt::format("the top level must be a JSON object, got {}", document.type_name()));
    reject_unknown_keys(document, kConfigKeys, "");

    ExperimentConfig config{};
    config.n = read_int(document, "n", kMinOrder, limits_.max_order);
    config.m = read_int(document, "m", kMinPoints, limits_.max_points);
    config.v_min = read_finite(required(document, "v_min"), "v_min");
    config.v_max = read_finite(required(document, "v_max"), "v_max");
    if (!(config.v_min < config.v_max)) {
      fail(fmt::format("'v_max' = {} must be greater than 'v_min' = {}", config.v_max, config.v_min));
    }
    config.op = read_operator(required(document, "operator"));
    const auto m = static_cast<std::size_t>(config.m);
    if (document.contains("V_d")) {
      config.V_d = read_array(document.at("V_d"), "V_d", m, "m");
      check_descendent_levels(config);
    }
    if (document.contains("V_a")) {
      config.V_a = read_array(document.at("V_a"), "V_a", m, "m");
      check_ascendent_levels(config);
    }
    read_lengths(document, config);
    if (document.contains("truth")) config.truth = read_truth(document.at("truth"), config);
    return config;
  }

 private:
  void reject_unknown_keys(const json& object, std::span<const std::string_view> known, std::string_view prefix) const {
    for (const auto& [key, value] : object.items()) {
      if (std::find(known.begin(), known.end(), key) == known.end()) {
        fail(fmt::format("unknown key '{}{}' (allowed: {})", prefix, key, fmt::join(known, ", ")));
      }
    }
  }

  const json& required(const json& object, std::string_view key) const {
    const auto found = object.find(key);
    if (found == object.end()) fail(fmt::format("missing required key '{}'", key));
    return *found;
  }

  int read_int(const json& object, std::string_view key, int min, int max) const {
    const json& value = required(object, key);
    if (!value.is_number_integer()) fail(fmt::format("'{}' must be an integer, got {}", key, detail::shown(value)));
    // Unsigned JSON integers may exceed int64: compared as they are, and quoted as the file has them (a clamped
    // stand-in was quoted as if the file held it).
    if (value.is_number_unsigned() && value.get<std::uint64_t>() > static_cast<std::uint64_t>(max)) {
      fail(fmt::format("'{}' = {} is outside {} [{}, {}]", key, value.get<std::uint64_t>(), limits_.range_name, min,
                       max));
    }
    const std::int64_t number = value.get<std::int64_t>();
    if (number < min || number > max) {
      fail(fmt::format("'{}' = {} is outside {} [{}, {}]", key, number, limits_.range_name, min, max));
    }
    return static_cast<int>(number);
  }

  // An optional integer key within [min, max]; `rule` says why when it is below min. The message quotes the value
  // as written, also when it is beyond 64 bits.
  template <class Int>
  std::optional<Int> read_optional_integer(const json& object, std::string_view key, std::int64_t min, Int max,
                                           std::string_view rule) const {
    const auto found = object.find(key);
    if (found == object.end()) return std::nullopt;
    const json& value = *found;
    if (!value.is_number_integer()) fail(fmt::format("'{}' must be an integer, got {}", key, detail::shown(value)));
    const bool too_large = value.is_number_unsigned() ? value.get<std::uint64_t>() > static_cast<std::uint64_t>(max)
                                                      : value.get<std::int64_t>() > static_cast<std::int64_t>(max);
    if (too_large) fail(fmt::format("'{}' = {} is too large (at most {})", key, detail::shown(value), max));
    // Not too large, so within int64 whether nlohmann stored it signed or unsigned.
    const auto number = value.get<std::int64_t>();
    if (number < min) fail(fmt::format("'{}' = {} {}", key, detail::shown(value), rule));
    return static_cast<Int>(number);
  }

  // The optional experiment lengths; the rules are those the firmware's check_design applies at run time.
  void read_lengths(const json& document, ExperimentConfig& config) const {
    constexpr int kIntMax = std::numeric_limits<int>::max();
    config.step_length = read_optional_integer<int>(
        document, "step_length", std::int64_t{config.n} + 1, kIntMax,
        fmt::format("must be greater than n = {} (the step experiment's mean (3.7) needs L > n)", config.n));
    const int period = est::schedule::period(config.n, config.m);
    for (const auto& [key, field] : {std::pair{"pulse_length_d", &ExperimentConfig::pulse_length_d},
                                     std::pair{"pulse_length_a", &ExperimentConfig::pulse_length_a}}) {
      // At most est::kMaxPulseLength: the firmware's float32 estimator is not accurate beyond (check_design).
      config.*field = read_optional_integer<int>(
          document, key, 2 * std::int64_t{period}, static_cast<int>(est::kMaxPulseLength),
          fmt::format("is shorter than two pulse periods (2T = {} for n = {}, m = {})", 2 * period, config.n,
                      config.m));
    }
    config.val_length = read_optional_integer<int>(document, "val_length", 0, kIntMax, "must not be negative");
    config.val_seed = read_optional_integer<std::uint32_t>(document, "val_seed", 0,
                                                           std::numeric_limits<std::uint32_t>::max(),
                                                           "must not be negative (an unsigned 32-bit seed)");
    if (const auto found = document.find("sensor_range"); found != document.end()) {
      const std::vector<double> range = read_array(*found, "sensor_range", 2, "");
      if (!(range[0] < range[1])) {
        fail(fmt::format("'sensor_range' = [{}, {}] must have lo < hi", range[0], range[1]));
      }
      config.sensor_range = std::array<double, 2>{range[0], range[1]};
    }
  }

  // `size_name` names where the size comes from ("m": "m = 6 entries"); empty for a fixed size ("2 entries").
  std::vector<double> read_array(const json& value, std::string_view key, std::size_t expected_size,
                                 std::string_view size_name) const {
    const std::string count = size_name.empty() ? fmt::format("{}", expected_size)
                                                : fmt::format("{} = {}", size_name, expected_size);
    if (!value.is_array()) {
      fail(fmt::format("'{}' must be an array of {} numbers, got {}", key, count, value.type_name()));
    }
    if (value.size() != expected_size) {
      fail(fmt::format("'{}' must have {} entries, got {}", key, count, value.size()));
    }
    return read_numbers(value, key);
  }

  // Paper, Section 3.4 step 1: v_m = V_1^d < V_2^d < ... < V_m^d < v_M.
  void check_descendent_levels(const ExperimentConfig& config) const {
    const std::vector<double>& levels = config.V_d;
    if (levels.front() != config.v_min) {
      fail(fmt::format("'V_d[0]' = {} must equal 'v_min' = {} (the DIS pulses reach down to v_m = V_1^d)",
                       levels.front(), config.v_min));
    }
    for (std::size_t i = 1; i < levels.size(); ++i) {
      if (!(levels[i] > levels[i - 1])) {
        fail(fmt::format("'V_d[{}]' = {} must be greater than 'V_d[{}]' = {} (V_d is strictly increasing)", i,
                         levels[i], i - 1, levels[i - 1]));
      }
    }
    if (!(levels.back() < config.v_max)) {
      fail(fmt::format("'V_d[{}]' = {} must be less than 'v_max' = {} (the pulses must leave the rest level v_M)",
                       levels.size() - 1, levels.back(), config.v_max));
    }
  }

  // Paper, Section 4.1 step 1: v_M = V_1^a > V_2^a > ... > V_m^a > v_m.
  void check_ascendent_levels(const ExperimentConfig& config) const {
    const std::vector<double>& levels = config.V_a;
    if (levels.front() != config.v_max) {
      fail(fmt::format("'V_a[0]' = {} must equal 'v_max' = {} (the AIS pulses reach up to v_M = V_1^a)", levels.front(),
                       config.v_max));
    }
    for (std::size_t i = 1; i < levels.size(); ++i) {
      if (!(levels[i] < levels[i - 1])) {
        fail(fmt::format("'V_a[{}]' = {} must be less than 'V_a[{}]' = {} (V_a is strictly decreasing)", i, levels[i],
                         i - 1, levels[i - 1]));
      }
    }
    if (!(levels.back() > config.v_min)) {
      fail(fmt::format("'V_a[{}]' = {} must be greater than 'v_min' = {} (the pulses must leave the rest level v_m)",
                       levels.size() - 1, levels.back(), config.v_min));
    }
  }

  Truth read_truth(const json& value, const ExperimentConfig& config) const {
    if (!value.is_object()) fail(fmt::format("'truth' must be a JSON object, got {}", value.type_name()));
    reject_unknown_keys(value, kTruthKeys, "truth.");
    const auto n = static_cast<std::size_t>(config.n);
    const auto m = static_cast<std::size_t>(config.m);
    Truth truth;
    if (value.contains("a")) truth.a = read_array(value.at("a"), "truth.a", n, "n");
    if (value.contains("b")) truth.b = read_array(value.at("b"), "truth.b", n, "n");
    // Border values are only meaningful at configured abscissas.
    if (value.contains("F_d")) {
      if (config.V_d.empty()) fail("'truth.F_d' is given but 'V_d' is absent (F_d holds F^d at the V_d levels)");
      truth.F_d = read_array(value.at("F_d"), "truth.F_d", m, "m");
    }
    if (value.contains("F_a")) {
      if (config.V_a.empty()) fail("'truth.F_a' is given but 'V_a' is absent (F_a holds F^a at the V_a levels)");
      truth.F_a = read_array(value.at("F_a"), "truth.F_a", m, "m");
    }
    if (value.contains("ybar0_d")) truth.ybar0_d = read_finite(value.at("ybar0_d"), "truth.ybar0_d");
    if (value.contains("ybar0_a")) truth.ybar0_a = read_finite(value.at("ybar0_a"), "truth.ybar0_a");
    return truth;
  }

  const ConfigLimits& limits_;
};

}  // namespace

ExperimentConfig parse_config_json(std::string_view text, std::string_view source_name, const ConfigLimits& limits) {
  return ConfigReader(source_name, limits).read(detail::parse_json_document(text, source_name));
}

ExperimentConfig read_config_json(const std::filesystem::path& path, const ConfigLimits& limits) {
  return parse_config_json(read_file_text(path), path.string(), limits);
}

nlohmann::json to_json(const ExperimentConfig& config) {
  json document = {{"n", config.n},
                   {"m", config.m},
                   {"v_min", config.v_min},
                   {"v_max", config.v_max},
                   {"operator", to_string(config.op)}};
  if (!config.V_d.empty()) document["V_d"] = config.V_d;
  if (!config.V_a.empty()) document["V_a"] = config.V_a;
  // Only the lengths the config states; absent ones stay absent, so the defaults keep applying when read back.
  if (config.step_length) document["step_length"] = *config.step_length;
  if (config.pulse_length_d) document["pulse_length_d"] = *config.pulse_length_d;
  if (config.pulse_length_a) document["pulse_length_a"] = *config.pulse_length_a;
  if (config.val_length) document["val_length"] = *config.val_length;
  if (config.val_seed) document["val_seed"] = *config.val_seed;
  if (config.sensor_range) document["sensor_range"] = *config.sensor_range;
  if (config.truth) {
    const Truth& truth = *config.truth;
    json truth_document = json::object();
    if (!truth.a.empty()) truth_document["a"] = truth.a;
    if (!truth.b.empty()) truth_document["b"] = truth.b;
    if (!truth.F_d.empty()) truth_document["F_d"] = truth.F_d;
    if (!truth.F_a.empty()) truth_document["F_a"] = truth.F_a;
    if (truth.ybar0_d) truth_document["ybar0_d"] = *truth.ybar0_d;
    if (truth.ybar0_a) truth_document["ybar0_a"] = *truth.ybar0_a;
    document["truth"] = std::move(truth_document);
  }
  return document;
}

nlohmann::json read_json_file(const std::filesystem::path& path) {
  return detail::parse_json_document(read_file_text(path), path.string());
}

void write_json_file(const std::filesystem::path& path, const nlohmann::json& document) {
  std::string text;
  try {
    text = document.dump(2);                 // nlohmann writes doubles in shortest round-trip form
  } catch (const json::type_error& error) {  // e.g. invalid UTF-8 in a string
    throw DataError(path.string(), fmt::format("cannot serialize JSON: {}", detail::without_exception_id(error.what())));
  }
  text += '\n';
  write_file_atomically(path, text);
}

}  // namespace lashid::sim
