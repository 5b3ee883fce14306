// libFuzzer target: the recording CSV reader (untrusted file). Any input either parses or throws DataError; a parsed
// recording must survive a write/read round trip unchanged, bit for bit (the writer's promise, docs/data-format.md).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>

#include "lashid/io/data_error.hpp"
#include "lashid/io/recording.hpp"

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  lashid::sim::Recording rec;
  try {
    rec = lashid::sim::parse_recording_csv(text, "fuzz.csv");
  } catch (const lashid::sim::DataError&) {
    return 0;
  }
  if (rec.size() == 0) std::abort();  // the reader promises at least one data row
  // One file per fuzzing process, rewritten for every input and removed when the process ends.
  struct TemporaryFile {
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("lashid-fuzz-recording-" + std::to_string(::getpid()) + ".csv");
    ~TemporaryFile() {
      std::error_code ignored;
      std::filesystem::remove(path, ignored);
    }
  };
  static const TemporaryFile file;
  const std::filesystem::path& path = file.path;
  lashid::sim::write_recording_csv(path, rec, {"round trip"});
  const lashid::sim::Recording back = lashid::sim::read_recording_csv(path);
  if (back.order() != rec.order()) std::abort();
  for (const lashid::sim::Phase p : rec.order()) {
    const auto& a = rec.phase(p);
    const auto& b = back.phase(p);
    if (a.size() != b.size()) std::abort();
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!same_bits(a[i].v, b[i].v) || !same_bits(a[i].y, b[i].y)) std::abort();
    }
  }
  return 0;
}
