// The physical effects a plant can have beyond the paper's model (operator -> linear block + white equation
// error): the vocabulary shared by the hidden-effect generator (sim/) and the diagnosis (diagnose/), with the names
// used in the JSON output and on the command line.
#pragma once

#include <array>
#include <optional>
#include <string_view>

namespace lashid::sim {

/// none: the paper's model holds; input_lag: G = (1-lambda)/(1-lambda q^-1) before the operator; dead_time: v
/// reaches the operator `delay` samples late; sensor_drift: a slow offset on y; colored_noise: non-white noise on y;
/// operator_type: switch where the user assumed backlash, or the reverse.
enum class Cause { kNone, kInputLag, kDeadTime, kSensorDrift, kColoredNoise, kOperatorType };
inline constexpr std::array<Cause, 6> kAllCauses = {Cause::kNone,        Cause::kInputLag,     Cause::kDeadTime,
                                                    Cause::kSensorDrift, Cause::kColoredNoise, Cause::kOperatorType};
/// "none", "input_lag", "dead_time", "sensor_drift", "colored_noise", "operator_type".
std::string_view to_string(Cause cause);
/// Inverse of to_string; exact match.
std::optional<Cause> parse_cause(std::string_view name);

}  // namespace lashid::sim
