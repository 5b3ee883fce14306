// The design, the plant and the recorder of a firmware run, shared by the QEMU loop (hil.cpp) and the in-process
// board (host_board_run.cpp).
#include "played_run.hpp"

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "lashid/io/plant_file.hpp"
#include "lashid/sim/file_plant.hpp"

namespace lashid::sim::detail {

fw::RunDesign run_design_of(const HilOptions& options) {
  if (options.design) return *options.design;
  if (options.scenario.empty()) {
    throw std::invalid_argument("hil: no design: give a config or a scenario");
  }
  return run_design_of(find_scenario(options.scenario));
}

namespace {
// The plant of a physical-plant run: never stepped (no plant port is open), NaN if it were.
struct UnplayedPlant {
  double step(double /*v*/) { return std::numeric_limits<double>::quiet_NaN(); }
};
}  // namespace

AnyPlant played_plant(const HilOptions& options, const fw::RunDesign& design) {
  if (options.physical_plant) return AnyPlant(UnplayedPlant{});
  if (options.plant_file.empty()) return AnyPlant(ScenarioPlant(find_scenario(options.scenario), options.seed));
  const PlantSpec spec = read_plant_json(options.plant_file);
  const auto v_min = static_cast<double>(design.v_min), v_max = static_cast<double>(design.v_max);
  check_plant_covers(spec, v_min, v_max, options.plant_file);
  return AnyPlant(FilePlant(spec, v_min, options.seed));
}

void start_recording(std::optional<RunRecorder>& recorder, const HilOptions& options, const fw::RunDesign& design) {
  if (options.record.empty()) return;
  const std::string plant = options.physical_plant           ? std::string("a physical plant (the board's own)")
                            : options.plant_file.empty() ? fmt::format("scenario {}, seed {}", options.scenario,
                                                                       options.seed)
                                                         : fmt::format("plant file {}, seed {}", options.plant_file,
                                                                       options.seed);
  std::vector<std::string> comments{
      fmt::format("lashid hil: {}, {}", options.firmware.empty() ? "attached board" : options.firmware, plant),
      options.physical_plant
          ? "v: the command the firmware gave its actuator; y: what its sensor measured (both float32, streamed on "
            "the link)"
          : "v: the command the firmware sent; y: the measurement the host answered (both float32, as on the link)",
      fmt::format("design: {}, n = {}, m = {}, [v_min, v_max] = [{}, {}], L = {}, N_d = {}, N_a = {}, val {} "
                  "samples (seed {})",
                  design.op == fw::OperatorKind::kBacklash ? "backlash" : "switch", design.n, design.m,
                  design.v_min, design.v_max, design.step_length, design.pulse_length_d, design.pulse_length_a,
                  design.val_length, design.val_seed)};
  if (const std::uint64_t check = design.interval_check_samples(); check > 0) {
    comments.push_back(fmt::format("the interval check (the run's first {} samples) is not recorded: the data format "
                                   "has no phase for it",
                                   check));
  }
  recorder.emplace(options.record, design, comments);
}

void finish_recording(std::optional<RunRecorder>& recorder, std::string_view how_it_ended, HilResult& result) {
  if (!recorder) return;
  result.recorded = recorder->rows();
  result.recording_complete = recorder->complete();
  // Not a sample measured (a refused design, a firmware that never started): nothing to write, and that is not the
  // run's error; the target keeps its previous content and the caller reports recorded = 0.
  if (result.recorded == 0) {
    recorder->discard();
    return;
  }
  recorder->finish(how_it_ended);
}

}  // namespace lashid::sim::detail
