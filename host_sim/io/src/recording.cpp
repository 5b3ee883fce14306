#include "lashid/io/recording.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "lashid/io/data_error.hpp"

namespace lashid::sim {

namespace {

constexpr std::array<std::string_view, kPhaseCount> kPhaseNames = {"step_d", "dis", "step_a", "ais", "val"};

}  // namespace

std::string_view to_string(Phase phase) { return kPhaseNames.at(phase_index(phase)); }

std::optional<Phase> parse_phase(std::string_view name) {
  for (const Phase phase : kAllPhases) {
    if (to_string(phase) == name) return phase;
  }
  return std::nullopt;
}

void Recording::append(Phase phase, double v, double y) {
  if (order_.empty() || order_.back() != phase) {
    if (has(phase)) {
      throw std::invalid_argument(
          fmt::format("Recording::append: phase '{}' already has an earlier block", to_string(phase)));
    }
    order_.push_back(phase);
  }
  samples_by_phase_[phase_index(phase)].push_back(Sample{v, y});
}

bool Recording::has(Phase phase) const { return !samples_by_phase_[phase_index(phase)].empty(); }

std::span<const Sample> Recording::phase(Phase phase) const { return samples_by_phase_[phase_index(phase)]; }

const std::vector<Phase>& Recording::order() const { return order_; }

std::size_t Recording::size() const {
  std::size_t total = 0;
  for (const auto& samples : samples_by_phase_) total += samples.size();
  return total;
}

DataError::DataError(std::string_view source, std::string_view message)
    : std::runtime_error(fmt::format("{}: {}", source, message)) {}

DataError::DataError(std::string_view source, std::size_t line, std::string_view message)
    : std::runtime_error(fmt::format("{}:{}: {}", source, line, message)), line_(line) {}

}  // namespace lashid::sim
