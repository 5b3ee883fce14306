// What makes a host-in-the-loop run a pass: the firmware's kDone says ok, QEMU exited with 0, both schemes' estimates
// arrived and are usable, and (on request) they equal the host build's and every damaged frame was caught. The
// `lashid hil` command prints the verdict and writes it as JSON; the rules live here.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "lashid/firmware/messages.hpp"
#include "lashid/hil/hil.hpp"

namespace lashid::sim {

enum class HilFailure : std::uint8_t {
  kNoDoneReport,         ///< no kDone frame arrived (lost, or the firmware never finished)
  kRunFailed,            ///< kDone carries a RunStatus other than kOk
  kQemuExit,             ///< QEMU exited with a non-zero status (the firmware's exit code)
  kEstimateMissing,      ///< no DIS or no AIS kEstimate arrived (e.g. both frames lost)
  kEstimateEmpty,        ///< an estimate reports n = 0 or m = 0: nothing to compare or print
  kDifferentFromHost,    ///< --compare-host: estimates or sample counts differ from the host board's
  kDamagedFramesMissed,  ///< --corrupt-every: a damaged frame was not detected and re-requested
  kDifferentFromRecording,  ///< --record: the on-device estimates differ from the float32 identification of the recording
  kDifferentFromExpected,   ///< --expect-estimates: the estimates are not exactly those of the earlier run
  /// A played plant: the firmware measured samples the host never played (an image with its own sensor, attached
  /// as if it played the host's plant), or the host played samples the firmware did not count.
  kPlantNotPlayed,
  /// A physical plant with --record: the firmware measured samples it streamed that never arrived (a sample block
  /// lost on the link: blocks are not sent again), so the recording is not the run's.
  kRecordingIncomplete,
};

constexpr const char* to_string(HilFailure f) {
  switch (f) {
    case HilFailure::kNoDoneReport: return "no kDone report";
    case HilFailure::kRunFailed: return "the firmware's run failed";
    case HilFailure::kQemuExit: return "QEMU exited with an error";
    case HilFailure::kEstimateMissing: return "an estimate is missing";
    case HilFailure::kEstimateEmpty: return "an estimate is empty (n = 0 or m = 0)";
    case HilFailure::kDifferentFromHost: return "different from the host build";
    case HilFailure::kDamagedFramesMissed: return "damaged frames not all detected";
    case HilFailure::kDifferentFromRecording: return "the on-device estimates differ from the recording's";
    case HilFailure::kDifferentFromExpected: return "the estimates differ from the expected ones";
    case HilFailure::kPlantNotPlayed: return "the firmware's samples are not the plant the host played";
    case HilFailure::kRecordingIncomplete: return "streamed samples were lost: the recording is incomplete";
  }
  return "unknown failure";
}

/// The QEMU run against the same firmware on the in-process host board (run_on_host_board).
struct HostComparison {
  std::uint32_t samples = 0;           ///< plant samples of the QEMU run
  std::uint32_t host_samples = 0;      ///< plant samples of the host board run
  double max_relative_difference = 0;  ///< over the schemes both runs reported, ||x - x_host|| / ||x_host||
  bool equal = false;                  ///< same schemes, same sample count, difference within the tolerance
};

/// Fault injection: every frame the host damaged must have been re-requested by the firmware.
struct FaultInjection {
  std::uint32_t damaged = 0;
  std::uint32_t re_requested = 0;  ///< the firmware's retries (CostRecord), 0 without a cost report
  bool all_detected = false;
};

/// The on-device estimates against the float32 identification of the run's own recording (`lashid identify
/// --float` on it): the recording is what the firmware measured, so both must agree to float32 rounding.
struct RecordingComparison {
  double max_relative_difference = 0;  ///< over the schemes, ||x_device - x_recording|| / ||x_recording|| (a, b, F)
  bool equal = false;
};

/// Compares the estimates of `run` (by scheme, as in `verdict`) with `from_recording` (one record per scheme the
/// recording was identified for). A scheme on one side only, other orders or a NaN count as different.
RecordingComparison compare_with_recording(const HilResult& run, const struct HilVerdict& verdict,
                                           const std::vector<fw::EstimateRecord>& from_recording, double tolerance);

struct HilVerdict {
  std::vector<HilFailure> failures;  ///< empty: the run passed
  /// The estimates by scheme (into HilResult::estimates), when they arrived and are not empty.
  std::optional<std::size_t> dis, ais;
  std::optional<HostComparison> host;
  std::optional<FaultInjection> fault_injection;
  std::optional<RecordingComparison> recording;

  bool ok() const { return failures.empty(); }
  bool has(HilFailure f) const;
};

struct JudgeOptions {
  /// QEMU belongs to the user (--attach): its exit status is unknown (-1), and the kDone status decides.
  bool attached = false;
  /// The host played the plant (not --physical-plant): every sample the firmware counts is one the host played.
  bool plant_played = true;
  /// --physical-plant --record: every sample the firmware counts must have been streamed to the host.
  bool streamed = false;
  /// --compare-host: a comparison was asked for, so a run judged without one (no host run given) fails.
  bool compare_host = false;
  double tolerance = 1e-3;  ///< relative tolerance of the host comparison
};

/// Judges `run`; `host` is the host board's run of the same firmware, scenario and seed, or null when not compared.
HilVerdict judge(const HilResult& run, const HilResult* host, const JudgeOptions& options);

/// "a1" .. "an", "b1" .. "bn": the parameter a CrossCheckRecord's `worst` index names, for an order n >= 1.
std::string cross_check_parameter(std::uint8_t worst, int n);

}  // namespace lashid::sim
