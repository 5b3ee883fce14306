// The firmware on the in-process host board, and the run-time design of a scenario or a config.
#include <algorithm>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "lashid/firmware/sequencer.hpp"
#include "lashid/hil/config_design.hpp"
#include "lashid/hil/hil.hpp"
#include "lashid/io/data_error.hpp"
#include "played_run.hpp"
#include "reports.hpp"

namespace lashid::sim {

namespace detail {

void collect(const hal::link::Frame& f, HilResult& result) {
  namespace link = hal::link;
  switch (f.type) {
    case link::MessageType::kEstimate: {
      fw::EstimateRecord e;
      if (e.decode(f.reader())) {
        // A report sent again (the host asked for it after a loss) replaces the scheme's record.
        const auto same = std::find_if(result.estimates.begin(), result.estimates.end(),
                                       [&](const fw::EstimateRecord& r) { return r.scheme == e.scheme; });
        if (same != result.estimates.end()) {
          *same = e;
        } else {
          result.estimates.push_back(e);
          // DIS before AIS, as the firmware sends them, also when the first was lost and came again later.
          std::stable_sort(result.estimates.begin(), result.estimates.end(), [](const auto& x, const auto& y) {
            return static_cast<int>(x.scheme) < static_cast<int>(y.scheme);
          });
        }
      } else {
        ++result.protocol_errors;
      }
      break;
    }
    case link::MessageType::kCrossCheck: {
      fw::CrossCheckRecord c;
      if (c.decode(f.reader())) result.cross_check = c; else ++result.protocol_errors;
      break;
    }
    case link::MessageType::kCost: {
      fw::CostRecord c;
      if (c.decode(f.reader())) result.cost = c; else ++result.protocol_errors;
      break;
    }
    case link::MessageType::kDesignStatus: result.design_status = f.size == 1 ? f.payload[0] : -1; break;
    case link::MessageType::kDone: result.done = f.size == 1 ? f.payload[0] : -1; break;
    default: break;
  }
}

}  // namespace detail

fw::RunDesign to_run_design(const ExperimentConfig& config, const RunLengths& lengths) {
  // The one conversion (config_design.cpp); its DataError's source is this function's words for a refusal.
  constexpr std::string_view kRefused = "the firmware cannot run this design";
  fw::RunDesign d;
  try {
    d = run_design_as_is(config, lengths, kRefused);
  } catch (const DataError& e) {
    throw std::invalid_argument(e.what());
  }
  if (const fw::DesignStatus s = fw::check_design(d); s != fw::DesignStatus::kOk) {
    throw std::invalid_argument(
        fmt::format("{}: {} (firmware status: {})", kRefused, design_status_message(s, d), fw::to_string(s)));
  }
  return d;
}

fw::RunDesign run_design_of(const Scenario& scenario) {
  if (scenario.step_length_d != scenario.step_length_a) {
    throw std::invalid_argument(fmt::format("hil: scenario '{}' has step experiments of {} and {} samples; the "
                                            "firmware runs both with one L",
                                            scenario.name, scenario.step_length_d, scenario.step_length_a));
  }
  return to_run_design(scenario.config, RunLengths{.step_length = scenario.step_length_d,
                                                   .pulse_length_d = scenario.pulse_length_d,
                                                   .pulse_length_a = scenario.pulse_length_a,
                                                   .val_length = 0,
                                                   .val_seed = 1});
}

ScenarioBoard make_scenario_board(const Scenario& scenario, std::uint64_t seed) {
  return ScenarioBoard(AnyPlant(ScenarioPlant(scenario, seed)), static_cast<float>(scenario.config.v_min),
                       static_cast<float>(scenario.config.v_max));
}

HilResult run_on_host_board(const std::string& scenario_name, std::uint64_t seed,
                            const std::optional<fw::RunDesign>& design) {
  HilOptions options;
  options.scenario = scenario_name;
  options.seed = seed;
  options.design = design;
  return run_on_host_board(options);
}

HilResult run_on_host_board(const HilOptions& options) {
  const fw::RunDesign design = detail::run_design_of(options);
  std::optional<RunRecorder> recorder;
  detail::start_recording(recorder, options, design);
  ScenarioBoard board(detail::played_plant(options, design), design.v_min, design.v_max);
  HilResult result;
  fw::IdentificationSequencer<ScenarioBoard> firmware(board, design);
  result.done = static_cast<int>(firmware.run());
  result.design_status = static_cast<int>(firmware.design_status());
  hal::link::FrameDecoder decoder;
  for (std::uint8_t b : board.link_output()) {
    if (decoder.push(b) == hal::link::FrameDecoder::Result::kFrame) detail::collect(decoder.frame(), result);
  }
  result.samples = static_cast<std::uint32_t>(board.exchanges().size());
  if (recorder) {
    std::uint64_t t = 0;
    for (const auto& e : board.exchanges()) recorder->sample(t++, e.v, e.y);
    detail::finish_recording(recorder,
                             fmt::format("the firmware ended with status '{}'",
                                         fw::to_string(static_cast<fw::RunStatus>(result.done))),
                             result);
  }
  return result;
}

}  // namespace lashid::sim
