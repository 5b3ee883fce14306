// Recorded input/output data of one identification session, and its CSV file format.
// The format is specified in docs/data-format.md.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "lashid/io/data_error.hpp"
#include "lashid/io/files.hpp"

namespace lashid::sim {

// The experiments of the paper, in the order `simulate` records them:
// step_d / dis = descendent step and pulse experiments (Section 3),
// step_a / ais = ascendent step and pulse experiments (Section 4.1),
// val = validation data with an arbitrary input.
enum class Phase { kStepD, kDis, kStepA, kAis, kVal };

inline constexpr std::size_t kPhaseCount = 5;
inline constexpr std::array<Phase, kPhaseCount> kAllPhases = {Phase::kStepD, Phase::kDis, Phase::kStepA, Phase::kAis,
                                                              Phase::kVal};
// Position of a phase in kAllPhases: the index of per-phase arrays.
constexpr std::size_t phase_index(Phase phase) { return static_cast<std::size_t>(phase); }

// The name used in CSV files: "step_d", "dis", "step_a", "ais", "val".
std::string_view to_string(Phase phase);
// Inverse of to_string; exact, case-sensitive match.
std::optional<Phase> parse_phase(std::string_view name);

// One sample: command v applied at time t and output y measured at time t.
struct Sample {
  double v;
  double y;
  friend bool operator==(const Sample&, const Sample&) = default;
};

// A continuous recording made of phase blocks. Each phase occurs at most once, as one contiguous
// block; the sample time t within a phase is the index into that phase's samples.
class Recording {
 public:
  // Appends to the last block if `phase` is the current phase, otherwise starts a new block.
  // Throws std::invalid_argument if `phase` already has an earlier, closed block.
  void append(Phase phase, double v, double y);

  bool has(Phase phase) const;
  // Samples of `phase`; an empty span if the phase is absent.
  std::span<const Sample> phase(Phase phase) const;
  // Phases in recording order.
  const std::vector<Phase>& order() const;
  // Total number of samples over all phases.
  std::size_t size() const;

  friend bool operator==(const Recording&, const Recording&) = default;

 private:
  std::vector<Phase> order_;
  std::array<std::vector<Sample>, kPhaseCount> samples_by_phase_;
};

// Reads a recording CSV file. Throws DataError (file not found/unreadable, or any format error).
Recording read_recording_csv(const std::filesystem::path& path);
// Same as read_recording_csv, from text in memory; `source_name` stands for the file name in errors.
Recording parse_recording_csv(std::string_view text, std::string_view source_name);

// Writes `recording` as CSV, preceded by one "# " comment line per entry of `comment_lines`
// (an entry containing newlines becomes several comment lines). The file is replaced atomically.
// Numbers are written in shortest round-trip form, so reading gives back the exact doubles.
// Throws DataError if the recording could not be read back (empty, non-finite values) or the
// file cannot be written.
void write_recording_csv(const std::filesystem::path& path, const Recording& recording,
                         const std::vector<std::string>& comment_lines);

// The same CSV written row by row while the samples are measured (`lashid hil --record`): the comment lines and the
// header at once, then each sample as it is appended, flushed to the temporary file at every phase change and every
// kFlushRows rows, and renamed onto `path` by finish() (AtomicFileWriter). write_recording_csv is built on it, so
// both write the same bytes and refuse the same things.
class RecordingCsvStream {
 public:
  static constexpr std::size_t kFlushRows = 1000;

  // Throws DataError when `path` cannot be written.
  RecordingCsvStream(const std::filesystem::path& path, const std::vector<std::string>& comment_lines);

  // Appends sample t of `phase`, t counting that phase's samples from 0. Throws DataError for a non-finite sample
  // (the file could not be read back), std::invalid_argument when `phase` already had a block that ended.
  void append(Phase phase, double v, double y);
  // A comment line at this point of the file (e.g. why a recording is partial); same rules as comment_lines.
  void comment(std::string_view text);
  void flush();
  // Samples appended so far.
  std::size_t rows() const { return rows_; }
  // Renames the file onto `path`. Throws DataError, and writes no file, when no sample was appended: a recording
  // needs at least one data row to be read back.
  void finish();
  // Drops the file; `path` is untouched.
  void discard() noexcept { file_.discard(); }

 private:
  AtomicFileWriter file_;
  std::string buffer_;
  std::size_t rows_ = 0;
  std::size_t rows_since_flush_ = 0;
  std::optional<Phase> current_;
  std::array<std::size_t, kPhaseCount> count_{};
  std::array<bool, kPhaseCount> closed_{};
};

}  // namespace lashid::sim
