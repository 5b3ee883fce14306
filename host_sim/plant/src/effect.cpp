#include "lashid/plant/effect.hpp"

#include <cstddef>

namespace lashid::sim {

namespace {
constexpr std::array<std::string_view, kAllCauses.size()> kCauseNames = {
    "none", "input_lag", "dead_time", "sensor_drift", "colored_noise", "operator_type"};
}  // namespace

std::string_view to_string(Cause cause) { return kCauseNames[static_cast<std::size_t>(cause)]; }

std::optional<Cause> parse_cause(std::string_view name) {
  for (std::size_t i = 0; i < kCauseNames.size(); ++i) {
    if (kCauseNames[i] == name) return kAllCauses[i];
  }
  return std::nullopt;
}

}  // namespace lashid::sim
