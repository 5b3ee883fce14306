// libFuzzer target: the friction damper CSV reader (untrusted file). Any input either parses or throws DataError.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "lashid/io/damper_data.hpp"
#include "lashid/io/data_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    (void)lashid::sim::parse_damper_csv(text, "fuzz.csv");
  } catch (const lashid::sim::DataError&) {
  }
  return 0;
}
