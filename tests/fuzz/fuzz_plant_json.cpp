// libFuzzer target: the plant file reader (untrusted JSON). Any input either gives a plant spec or throws DataError.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "lashid/io/data_error.hpp"
#include "lashid/io/plant_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    (void)lashid::sim::parse_plant_json(text, "fuzz.json");
  } catch (const lashid::sim::DataError&) {
  }
  return 0;
}
