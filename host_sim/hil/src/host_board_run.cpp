// The firmware on the in-process host board, and which firmware configuration belongs to which scenario.
#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "lashid/firmware/paper_configs.hpp"
#include "lashid/firmware/sequencer.hpp"
#include "lashid/hil/hil.hpp"
#include "reports.hpp"

namespace lashid::sim {

namespace detail {

void collect(const hal::link::Frame& f, HilResult& result) {
  namespace link = hal::link;
  switch (f.type) {
    case link::MessageType::kEstimate: {
      fw::EstimateRecord e;
      if (e.decode(f.reader())) {
        result.estimates.push_back(e);
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
    case link::MessageType::kDone: result.done = f.size == 1 ? f.payload[0] : -1; break;
    default: break;
  }
}

}  // namespace detail

namespace {

// Where the scenario's experiment design (n, m, interval, abscissas, lengths) differs from the configuration C the
// firmware was compiled with, compared in float32 as the firmware holds it. Empty: the same design.
template <fw::FirmwareConfig C>
std::vector<std::string> design_differences(const Scenario& s) {
  std::vector<std::string> out;
  const ExperimentConfig& c = s.config;
  const auto compare = [&out](std::string_view what, auto scenario, auto firmware) {
    if (scenario != firmware) out.push_back(fmt::format("{} {} (firmware {})", what, scenario, firmware));
  };
  compare("n", c.n, C::kOrder);
  compare("m", c.m, C::kPoints);
  compare("v_min", static_cast<float>(c.v_min), C::kVMin);
  compare("v_max", static_cast<float>(c.v_max), C::kVMax);
  const auto abscissas = [&](std::string_view name, const std::vector<double>& V, const auto& firmware) {
    std::vector<float> v(V.begin(), V.end());
    if (!std::equal(v.begin(), v.end(), firmware.begin(), firmware.end())) {
      out.push_back(fmt::format("{} [{}] (firmware [{}])", name, fmt::join(v, ", "), fmt::join(firmware, ", ")));
    }
  };
  abscissas("V_d", c.V_d, C::kVd);
  abscissas("V_a", c.V_a, C::kVa);
  compare("L of the DIS step experiment", s.step_length_d, C::kStepLength);
  compare("L of the AIS step experiment", s.step_length_a, C::kStepLength);
  compare("N of the DP experiment", s.pulse_length_d, C::kPulseLengthD);
  compare("N of the AP experiment", s.pulse_length_a, C::kPulseLengthA);
  return out;
}

template <fw::FirmwareConfig C>
int run_firmware(ScenarioBoard& board) {
  fw::IdentificationSequencer<ScenarioBoard, C> firmware(board);
  return static_cast<int>(firmware.run());
}

// The firmware images (firmware/CMakeLists.txt: one per configuration of paper_configs.hpp) and the scenario whose
// plant each was configured for.
struct FirmwareBuild {
  std::string_view scenario;
  std::string_view config;
  std::vector<std::string> (*differences)(const Scenario&);
  int (*run)(ScenarioBoard&);
};

constexpr std::array<FirmwareBuild, 2> kFirmwareBuilds{{
    {"dis_paper", "DisPaperConfig", &design_differences<fw::DisPaperConfig>, &run_firmware<fw::DisPaperConfig>},
    {"ais_paper", "AisPaperConfig", &design_differences<fw::AisPaperConfig>, &run_firmware<fw::AisPaperConfig>},
}};

const FirmwareBuild& firmware_build(const Scenario& scenario) {
  for (const FirmwareBuild& b : kFirmwareBuilds) {
    if (b.scenario == scenario.name) {
      const std::vector<std::string> d = b.differences(scenario);
      if (!d.empty()) {
        throw std::invalid_argument(fmt::format("hil: scenario '{}' does not have the design of the firmware "
                                                "configuration {}: {}",
                                                scenario.name, b.config, fmt::join(d, "; ")));
      }
      return b;
    }
  }
  throw std::invalid_argument("hil: no firmware configuration for scenario '" + scenario.name + "'");
}

}  // namespace

std::string_view firmware_config_of(const Scenario& scenario) { return firmware_build(scenario).config; }

ScenarioBoard make_scenario_board(const Scenario& scenario, std::uint64_t seed) {
  return ScenarioBoard(ScenarioPlant(scenario, seed), static_cast<float>(scenario.config.v_min),
                       static_cast<float>(scenario.config.v_max));
}

HilResult run_on_host_board(const std::string& scenario_name, std::uint64_t seed) {
  const Scenario& scenario = find_scenario(scenario_name);
  const FirmwareBuild& build = firmware_build(scenario);
  ScenarioBoard board = make_scenario_board(scenario, seed);
  HilResult result;
  result.done = build.run(board);
  hal::link::FrameDecoder decoder;
  for (std::uint8_t b : board.link_output()) {
    if (decoder.push(b) == hal::link::FrameDecoder::Result::kFrame) detail::collect(decoder.frame(), result);
  }
  result.samples = static_cast<std::uint32_t>(board.exchanges().size());
  return result;
}

}  // namespace lashid::sim
