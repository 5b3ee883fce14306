// A firmware run as a recording (docs/data-format.md): which phase each exchanged sample belongs to, and the
// recorder `lashid hil --record` writes while the run goes on.
//
// The firmware numbers its plant exchanges t = 0, 1, 2, ... over the whole run (hal::RemotePlantPort). From its
// design, the run is: [interval check, 16 T samples, backlash only] -> step_d (L + 1) -> dis (N_d) -> step_a (L + 1)
// -> ais (N_a) -> val (val_length), T = est::schedule::period(n, m). The interval check (Section 3.4 step 1, a square
// wave v_M / v_m) has no phase in the data format and no use to the estimators: it is left out of the recording,
// and the recording's header comment says how many samples it had.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "lashid/firmware/run_design.hpp"
#include "lashid/io/recording.hpp"

namespace lashid::sim {
/// Samples of the recorded phases: 2 (L + 1) + N_d + N_a + val_length.
std::uint64_t recorded_samples(const fw::RunDesign& design);

/// Where sample k of a run belongs.
struct RunSamplePlace {
  enum class Part : std::uint8_t {
    kIntervalCheck,  ///< before the phases: not recorded
    kPhase,          ///< sample t of `phase`
    kAfterRun,       ///< beyond the design's last sample (a firmware that runs another design)
  };
  Part part = Part::kPhase;
  Phase phase = Phase::kStepD;
  std::uint64_t t = 0;  ///< index within the phase, or within the interval check
  friend bool operator==(const RunSamplePlace&, const RunSamplePlace&) = default;
};

/// Pure: the place of sample k (counted from 0 over the whole run) in a run of `design`.
RunSamplePlace place_of_sample(const fw::RunDesign& design, std::uint64_t k);

/// Writes the samples of a run as they are exchanged (RecordingCsvStream: flushed at every phase change and every
/// 1000 rows, renamed onto the target by finish()). Each t is recorded once: a repeated t (a retry the host answered
/// from its cache) is ignored, and so is anything after a gap in t (the run cannot continue past a lost sample).
class RunRecorder {
 public:
  /// Throws DataError when `path` cannot be written, before the run starts.
  RunRecorder(const std::filesystem::path& path, const fw::RunDesign& design,
              const std::vector<std::string>& comment_lines);

  /// Sample t of the run: the command v the firmware sent and the y the plant answered, as they crossed the link.
  /// Whether it became a row (not a retry, not past a gap, not the interval check, not beyond the design).
  bool sample(std::uint64_t t, float v, float y);
  /// A comment row here (e.g. about the row just written).
  void note(std::string_view text) { stream_.comment(text); }
  /// Nothing after this point is recorded (a sample a recording cannot hold), and `why` says so here.
  void end_here(std::string_view why) {
    if (gap_) return;
    stream_.comment(why);
    gap_ = true;
  }

  /// Renames the recording onto its path. A run that ended before the design's last sample keeps what it measured:
  /// a comment row at the end says the recording is partial, why (`how_it_ended`, e.g. "firmware status: sensor
  /// fault") and how many samples it has. Throws DataError when not a single sample was recorded (no file is
  /// written then) or the file cannot be written.
  void finish(std::string_view how_it_ended);
  /// Drops the recording (the target keeps its previous content).
  void discard() noexcept { stream_.discard(); }

  std::uint64_t rows() const { return stream_.rows(); }
  bool complete() const { return stream_.rows() == recorded_samples(design_); }

 private:
  RecordingCsvStream stream_;
  fw::RunDesign design_;
  std::uint64_t next_t_ = 0;
  std::uint64_t beyond_design_ = 0;
  bool gap_ = false;
};

}  // namespace lashid::sim
