// What `lashid hil` checks a run's on-device estimates against (hil_references.hpp).
#include "hil_references.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lashid/hil/run_recording.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/io/data_error.hpp"
#include "lashid/io/json.hpp"
#include "lashid/io/recording.hpp"

namespace lashid::app {

using namespace lashid::sim;

namespace {

// The recording as the device estimated from it: the samples a streamed run named as set aside (their run indices
// in `set_aside`) become NaN, which the estimator leaves out as the firmware did. A y outside the config's sensor
// range is left out by identify_scheme itself, by the design's own float test.
Recording without_set_aside(const Recording& rec, const fw::RunDesign& design,
                            const std::vector<std::uint64_t>& set_aside) {
  std::vector<RunSamplePlace> places;
  for (const std::uint64_t t : set_aside) places.push_back(place_of_sample(design, t));
  Recording out;
  for (const Phase phase : rec.order()) {
    const auto samples = rec.phase(phase);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const bool aside = std::any_of(places.begin(), places.end(), [&](const RunSamplePlace& p) {
        return p.part == RunSamplePlace::Part::kPhase && p.phase == phase && p.t == i;
      });
      out.append(phase, samples[i].v, aside ? std::numeric_limits<double>::quiet_NaN() : samples[i].y);
    }
  }
  return out;
}

}  // namespace

// The float32 identification of the run's own recording, as `lashid identify --float` makes it (with the samples
// the firmware set aside left out, as it did): one record per scheme the firmware reported.
std::vector<fw::EstimateRecord> identify_recording(const ExperimentConfig& config, const std::string& path,
                                                   const std::vector<fw::EstimateRecord>& device,
                                                   const fw::RunDesign& design,
                                                   const std::vector<std::uint64_t>& set_aside) {
  // As `lashid identify` reads it.
  const Recording rec = without_set_aside(read_recording_for(config, path), design, set_aside);
  IdentifyOptions f32;
  f32.precision = Precision::kFloat;
  f32.leave_out_unusable_y = true;  // the set-aside samples, as on the device
  std::vector<fw::EstimateRecord> out;
  for (const fw::EstimateRecord& e : device) {
    const SchemeResult s = identify_scheme(config, rec, e.scheme, f32, path);
    fw::EstimateRecord r;
    r.scheme = e.scheme;
    r.status = static_cast<std::uint8_t>(s.status);
    r.n = static_cast<std::uint8_t>(std::min<std::size_t>(s.a.size(), fw::kMaxRecordOrder));
    r.m = static_cast<std::uint8_t>(std::min<std::size_t>(s.F.size(), fw::kMaxRecordPoints));
    for (std::size_t i = 0; i < r.n; ++i) {
      r.a[i] = static_cast<float>(s.a[i]);
      r.b[i] = static_cast<float>(s.b[i]);
    }
    for (std::size_t j = 0; j < r.m; ++j) r.F[j] = static_cast<float>(s.F[j]);
    out.push_back(r);
  }
  return out;
}

// The estimates of an earlier run's --json ("dis" and "ais": a, b, F, status), as records to compare with.
std::vector<fw::EstimateRecord> read_expected_estimates(const std::string& path) {
  const nlohmann::json document = read_json_file(path);
  std::vector<fw::EstimateRecord> out;
  for (const auto& [key, scheme] : {std::pair{"dis", est::Scheme::kDescending}, {"ais", est::Scheme::kAscending}}) {
    if (!document.is_object() || !document.contains(key)) continue;
    try {
      const auto& e = document.at(key);
      const auto a = e.at("a").get<std::vector<float>>(), b = e.at("b").get<std::vector<float>>();
      const auto F = e.at("F").get<std::vector<float>>();
      if (a.size() != b.size() || a.empty() || a.size() > fw::kMaxRecordOrder || F.empty() ||
          F.size() > fw::kMaxRecordPoints) {
        throw DataError(path, fmt::format("'{}': a and b need 1 to {} entries each, F 1 to {}", key,
                                          fw::kMaxRecordOrder, fw::kMaxRecordPoints));
      }
      fw::EstimateRecord r;
      r.scheme = scheme;
      r.status = e.at("status").get<std::uint8_t>();
      r.n = static_cast<std::uint8_t>(a.size());
      r.m = static_cast<std::uint8_t>(F.size());
      std::copy(a.begin(), a.end(), r.a.begin());
      std::copy(b.begin(), b.end(), r.b.begin());
      std::copy(F.begin(), F.end(), r.F.begin());
      out.push_back(r);
    } catch (const nlohmann::json::exception& e) {
      throw DataError(path, fmt::format("'{}' is not an estimate of a `lashid hil --json` file (it needs a, b and F as "
                                        "numbers and a status): {}",
                                        key, e.what()));
    }
  }
  if (out.empty()) throw DataError(path, "holds no estimate ('dis' or 'ais'): not a `lashid hil --json` file");
  return out;
}

}  // namespace lashid::app
