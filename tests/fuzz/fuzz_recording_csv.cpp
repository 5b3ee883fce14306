// libFuzzer target: the recording CSV reader (untrusted file). Any input either parses or throws DataError; a parsed
// recording must survive a write/read round trip unchanged (the writer's promise, docs/data-format.md).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "lashid/io/data_error.hpp"
#include "lashid/io/recording.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const lashid::sim::Recording rec = lashid::sim::parse_recording_csv(text, "fuzz.csv");
    if (rec.size() == 0) std::abort();  // the reader promises at least one data row
  } catch (const lashid::sim::DataError&) {
  }
  return 0;
}
