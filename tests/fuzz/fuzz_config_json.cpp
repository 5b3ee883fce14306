// libFuzzer target: the experiment config reader (untrusted JSON), with the host's and the firmware's limits. Any
// input either gives a config or throws DataError; a config is converted to the firmware's design (to_run_design,
// what `lashid hil --config` sends), which may refuse with DataError or std::invalid_argument, never crash.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "lashid/hil/config_design.hpp"
#include "lashid/io/config.hpp"
#include "lashid/io/data_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (const lashid::sim::ConfigLimits limits :
       {lashid::sim::ConfigLimits{}, lashid::sim::ConfigLimits{.max_order = 4, .max_points = 10}}) {
    try {
      const lashid::sim::ExperimentConfig c = lashid::sim::parse_config_json(text, "fuzz.json", limits);
      (void)lashid::sim::experiment_lengths(c);
      try {
        (void)lashid::sim::to_run_design(c, "fuzz.json");
      } catch (const std::invalid_argument&) {
      }
    } catch (const lashid::sim::DataError&) {
    }
  }
  return 0;
}
