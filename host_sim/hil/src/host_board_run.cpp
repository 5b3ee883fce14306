// The firmware on the in-process host board, and which firmware configuration belongs to which scenario.
#include <algorithm>
#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "lashid/firmware/paper_configs.hpp"
#include "lashid/firmware/sequencer.hpp"
#include "lashid/hil/hil.hpp"
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

// The compiled configuration as the run-time design of a run: what the image executes (no validation phase).
template <fw::FirmwareConfig C>
fw::RunDesign run_design_of_config() {
  fw::RunDesign d;
  d.op = C::kCheckInterval ? fw::OperatorKind::kBacklash : fw::OperatorKind::kSwitch;
  d.n = static_cast<std::uint8_t>(C::kOrder);
  d.m = static_cast<std::uint8_t>(C::kPoints);
  d.v_min = C::kVMin;
  d.v_max = C::kVMax;
  std::copy(C::kVd.begin(), C::kVd.end(), d.V_d.begin());
  std::copy(C::kVa.begin(), C::kVa.end(), d.V_a.begin());
  d.step_length = static_cast<std::uint32_t>(C::kStepLength);
  d.pulse_length_d = static_cast<std::uint32_t>(C::kPulseLengthD);
  d.pulse_length_a = static_cast<std::uint32_t>(C::kPulseLengthA);
  return d;
}

// The firmware images (firmware/CMakeLists.txt: one per configuration of paper_configs.hpp) and the scenario whose
// plant each was configured for.
struct FirmwareBuild {
  std::string_view scenario;
  std::string_view config;
  std::vector<std::string> (*differences)(const Scenario&);
  int (*run)(ScenarioBoard&);
  fw::RunDesign (*design)();
};

constexpr std::array<FirmwareBuild, 2> kFirmwareBuilds{{
    {"dis_paper", "DisPaperConfig", &design_differences<fw::DisPaperConfig>, &run_firmware<fw::DisPaperConfig>,
     &run_design_of_config<fw::DisPaperConfig>},
    {"ais_paper", "AisPaperConfig", &design_differences<fw::AisPaperConfig>, &run_firmware<fw::AisPaperConfig>,
     &run_design_of_config<fw::AisPaperConfig>},
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

fw::RunDesign firmware_design_of(const Scenario& scenario) { return firmware_build(scenario).design(); }

ScenarioBoard make_scenario_board(const Scenario& scenario, std::uint64_t seed) {
  return ScenarioBoard(AnyPlant(ScenarioPlant(scenario, seed)), static_cast<float>(scenario.config.v_min),
                       static_cast<float>(scenario.config.v_max));
}

HilResult run_on_host_board(const std::string& scenario_name, std::uint64_t seed) {
  HilOptions options;
  options.scenario = scenario_name;
  options.seed = seed;
  return run_on_host_board(options);
}

HilResult run_on_host_board(const HilOptions& options) {
  if (options.design) {
    throw std::invalid_argument("hil: the in-process board runs the paper images' compiled designs only");
  }
  const FirmwareBuild& build = firmware_build(find_scenario(options.scenario));
  const fw::RunDesign design = build.design();
  std::optional<RunRecorder> recorder;
  detail::start_recording(recorder, options, design);
  ScenarioBoard board(detail::played_plant(options, design), design.v_min, design.v_max);
  HilResult result;
  result.done = build.run(board);
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
