// The plant file of docs/data-format.md: reader with errors that name the file and the key.
#include "lashid/io/plant_file.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "json_document.hpp"
#include "lashid/io/data_error.hpp"
#include "lashid/io/files.hpp"

namespace lashid::sim {

namespace {

using nlohmann::json;

constexpr std::array<std::string_view, 9> kPlantKeys = {
    "operator",  "borders",     "a",         "b", "equation_noise_std", "sensor_noise", "input_lag",
    "dead_time", "sensor_drift_per_sample"};
constexpr std::array<std::string_view, 3> kBorderKeys = {"v", "ascending", "descending"};
constexpr std::array<std::string_view, 2> kSensorNoiseKeys = {"std", "pole"};

// Schur-Cohn (step-down) test: A(z^-1) = 1 + a1 z^-1 + ... + an z^-n has all its roots strictly inside the unit
// circle iff every reflection coefficient of the step-down recursion has modulus < 1. No root finding, any order.
bool is_stable(const std::vector<double>& a) {
  std::vector<double> p{1.0};
  p.insert(p.end(), a.begin(), a.end());
  for (std::size_t i = a.size(); i >= 1; --i) {
    const double k = p[i];
    if (!(std::fabs(k) < 1.0)) return false;
    std::vector<double> lower(i);
    for (std::size_t j = 0; j < i; ++j) lower[j] = (p[j] - k * p[i - j]) / (1.0 - k * k);
    p = std::move(lower);
  }
  return true;
}

// Turns the JSON document into a PlantSpec, naming the offending key in every error.
class PlantReader : detail::JsonFieldReader {
 public:
  explicit PlantReader(std::string_view source_name) : JsonFieldReader(source_name) {}

  PlantSpec read(const json& document) {
    if (!document.is_object()) fail(fmt::format("the top level must be a JSON object, got {}", document.type_name()));
    note_unknown_keys(document, kPlantKeys, "");
    spec_.op = read_operator(required(document, "operator"));
    read_borders(required(document, "borders"));
    spec_.a = read_numbers(required(document, "a"), "a");
    spec_.b = read_numbers(required(document, "b"), "b");
    if (spec_.a.size() != spec_.b.size() || spec_.a.empty()) {
      fail(fmt::format("'a' and 'b' must have the same length n >= 1 (got {} and {})", spec_.a.size(),
                       spec_.b.size()));
    }
    if (!is_stable(spec_.a)) {
      fail(fmt::format("'a' = [{}]: A(q^-1) has a pole on or outside the unit circle; the plant must be stable (the "
                       "step experiments average a settled output, (3.7))",
                       fmt::join(spec_.a, ", ")));
    }
    spec_.equation_noise_std = read_non_negative(required(document, "equation_noise_std"), "equation_noise_std");
    if (const json* noise = optional(document, "sensor_noise")) read_sensor_noise(*noise);
    if (const json* lag = optional(document, "input_lag")) {
      spec_.input_lag = read_finite(*lag, "input_lag");
      if (!(spec_.input_lag >= 0.0 && spec_.input_lag < 1.0)) {
        fail(fmt::format("'input_lag' = {} must lie in [0, 1) (lambda of (1-lambda)/(1-lambda q^-1))",
                         spec_.input_lag));
      }
    }
    if (const json* delay = optional(document, "dead_time")) spec_.dead_time = read_dead_time(*delay);
    if (const json* drift = optional(document, "sensor_drift_per_sample")) {
      spec_.sensor_drift_per_sample = read_finite(*drift, "sensor_drift_per_sample");
    }
    return std::move(spec_);
  }

 private:

  // "More keys allowed" (issue 10): a plant file may carry a name, notes, provenance. They are kept as a list so
  // the commands can mention them.
  void note_unknown_keys(const json& object, std::span<const std::string_view> known, std::string_view prefix) {
    for (const auto& [key, value] : object.items()) {
      if (std::find(known.begin(), known.end(), key) == known.end()) {
        spec_.ignored_keys.push_back(fmt::format("{}{}", prefix, key));
      }
    }
  }

  const json& required(const json& object, std::string_view key) const {
    const auto found = object.find(key);
    if (found == object.end() || found->is_null()) fail(fmt::format("missing required key '{}'", key));
    return *found;
  }

  // An optional key; null counts as absent.
  static const json* optional(const json& object, std::string_view key) {
    const auto found = object.find(key);
    return found == object.end() || found->is_null() ? nullptr : &*found;
  }

  double read_non_negative(const json& value, std::string_view key) const {
    const double number = read_finite(value, key);
    if (!(number >= 0.0)) fail(fmt::format("'{}' = {} must not be negative (it is a standard deviation)", key, number));
    return number;
  }


  void read_borders(const json& value) {
    if (!value.is_object()) {
      fail(fmt::format("'borders' must be a JSON object {{\"v\": [...], \"ascending\": [...], \"descending\": "
                       "[...]}}, got {}",
                       value.type_name()));
    }
    note_unknown_keys(value, kBorderKeys, "borders.");
    spec_.border_v = read_numbers(required_in(value, "borders", "v"), "borders.v");
    spec_.border_ascending = read_numbers(required_in(value, "borders", "ascending"), "borders.ascending");
    spec_.border_descending = read_numbers(required_in(value, "borders", "descending"), "borders.descending");
    const std::vector<double>& v = spec_.border_v;
    if (v.size() < 2) fail(fmt::format("'borders.v' needs at least 2 points, got {}", v.size()));
    for (std::size_t i = 1; i < v.size(); ++i) {
      if (!(v[i] > v[i - 1])) {
        fail(fmt::format("'borders.v[{}]' = {} must be greater than 'borders.v[{}]' = {} (borders.v is strictly "
                         "increasing)",
                         i, v[i], i - 1, v[i - 1]));
      }
    }
    for (const auto& [name, values] : {std::pair{"ascending", &spec_.border_ascending},
                                       std::pair{"descending", &spec_.border_descending}}) {
      if (values->size() != v.size()) {
        fail(fmt::format("'borders.{}' has {} points, 'borders.v' has {}", name, values->size(), v.size()));
      }
    }
  }

  const json& required_in(const json& object, std::string_view parent, std::string_view key) const {
    const auto found = object.find(key);
    if (found == object.end() || found->is_null()) fail(fmt::format("missing required key '{}.{}'", parent, key));
    return *found;
  }

  void read_sensor_noise(const json& value) {
    if (!value.is_object()) {
      fail(fmt::format("'sensor_noise' must be a JSON object {{\"std\": s, \"pole\": c}}, got {}", value.type_name()));
    }
    note_unknown_keys(value, kSensorNoiseKeys, "sensor_noise.");
    SensorNoiseSpec noise;
    noise.std = read_non_negative(required_in(value, "sensor_noise", "std"), "sensor_noise.std");
    noise.pole = read_finite(required_in(value, "sensor_noise", "pole"), "sensor_noise.pole");
    if (!(std::fabs(noise.pole) < 1.0)) {
      fail(fmt::format("'sensor_noise.pole' = {} must lie in (-1, 1) (the AR(1) noise must be stationary)",
                       noise.pole));
    }
    spec_.sensor_noise = noise;
  }

  int read_dead_time(const json& value) const {
    // 2.0 is refused like 2.5: a delay counts samples, and the config's integers are read the same way.
    if (!value.is_number_integer() || (!value.is_number_unsigned() && value.get<std::int64_t>() < 0)) {
      fail(fmt::format("'dead_time' must be a non-negative integer (samples), got {}", detail::shown(value)));
    }
    const auto delay = value.get<std::uint64_t>();
    if (delay > static_cast<std::uint64_t>(kMaxDeadTime)) {
      fail(fmt::format("'dead_time' = {} exceeds the limit of {} samples", delay, kMaxDeadTime));
    }
    return static_cast<int>(delay);
  }

  PlantSpec spec_;
};

}  // namespace

PlantSpec parse_plant_json(std::string_view text, std::string_view source_name) {
  return PlantReader(source_name).read(detail::parse_json_document(text, source_name));
}

PlantSpec read_plant_json(const std::filesystem::path& path) {
  return parse_plant_json(read_file_text(path), path.string());
}

void check_plant_covers(const PlantSpec& plant, double v_min, double v_max, std::string_view plant_name) {
  if (plant.border_v.empty()) return;
  const double lo = plant.border_v.front(), hi = plant.border_v.back();
  if (v_min < lo || v_max > hi) {
    throw DataError(plant_name, fmt::format("'borders.v' covers [{}, {}], which does not contain the design's working "
                                            "interval [v_min, v_max] = [{}, {}]",
                                            lo, hi, v_min, v_max));
  }
}

}  // namespace lashid::sim
