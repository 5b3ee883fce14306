// Phases of a firmware run, and its recording while it runs.
#include "lashid/hil/run_recording.hpp"

#include <array>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "lashid/firmware/sequencer.hpp"
#include "lashid/hil/hil.hpp"

namespace lashid::sim {

namespace {

// The recorded phases in run order, with their lengths.
std::array<std::pair<Phase, std::uint64_t>, kPhaseCount> phase_blocks(const fw::RunDesign& d) {
  const std::uint64_t step = std::uint64_t{d.step_length} + 1U;
  return {{{Phase::kStepD, step},
           {Phase::kDis, d.pulse_length_d},
           {Phase::kStepA, step},
           {Phase::kAis, d.pulse_length_a},
           {Phase::kVal, d.val_length}}};
}

}  // namespace

std::uint64_t recorded_samples(const fw::RunDesign& design) {
  std::uint64_t total = 0;
  for (const auto& [phase, length] : phase_blocks(design)) total += length;
  return total;
}

RunSamplePlace place_of_sample(const fw::RunDesign& design, std::uint64_t k) {
  const std::uint64_t check = design.interval_check_samples();
  if (k < check) return {RunSamplePlace::Part::kIntervalCheck, Phase::kStepD, k};
  std::uint64_t start = check;
  for (const auto& [phase, length] : phase_blocks(design)) {
    if (k < start + length) return {RunSamplePlace::Part::kPhase, phase, k - start};
    start += length;
  }
  return {RunSamplePlace::Part::kAfterRun, Phase::kVal, k - start};
}

RunRecorder::RunRecorder(const std::filesystem::path& path, const fw::RunDesign& design,
                         const std::vector<std::string>& comment_lines)
    : stream_(path, comment_lines), design_(design) {}

bool RunRecorder::sample(std::uint64_t t, float v, float y) {
  if (t < next_t_ || gap_) return false;  // a retry of a recorded t, or past a lost sample
  if (t > next_t_) {
    gap_ = true;
    stream_.comment(fmt::format("sample t = {} of the run never arrived: nothing after it is recorded", next_t_));
    return false;
  }
  ++next_t_;
  const RunSamplePlace place = place_of_sample(design_, t);
  if (place.part == RunSamplePlace::Part::kIntervalCheck) return false;
  if (place.part == RunSamplePlace::Part::kAfterRun) {
    ++beyond_design_;
    return false;
  }
  if (!std::isfinite(v) || !std::isfinite(y)) {
    end_here(fmt::format("sample {} of the run ({} t = {}) is not finite (v = {}, y = {}): a recording cannot hold "
                         "it, nothing after it is recorded",
                         t, to_string(place.phase), place.t, v, y));
    return false;
  }
  stream_.append(place.phase, static_cast<double>(v), static_cast<double>(y));
  return true;
}

void RunRecorder::finish(std::string_view how_it_ended) {
  if (beyond_design_ > 0) {
    stream_.comment(fmt::format("{} samples after the design's last one were exchanged and not recorded: the "
                                "firmware ran a longer design than the host assumed",
                                beyond_design_));
  }
  if (!complete()) {
    stream_.comment(fmt::format("partial recording: {}; {} of the design's {} samples were measured", how_it_ended,
                                stream_.rows(), recorded_samples(design_)));
  }
  stream_.finish();
}

}  // namespace lashid::sim
