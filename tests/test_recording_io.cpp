// Recording model and CSV format: every reader error names file and line; writing round-trips exactly
// and is atomic.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>

#include "lashid/io/recording.hpp"

#include "data_error_matchers.hpp"
#include "lashid/io/files.hpp"

namespace lashid::sim {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kSource = "rec.csv";

using test::Contains;
using test::error_of;


std::string parse_error(std::string_view text) {
  return error_of([&] { parse_recording_csv(text, kSource); });
}

// Unique scratch directory, removed with everything in it at the end of the test.
class RecordingFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device entropy;
    dir_ = fs::temp_directory_path() / fmt::format("lashid_recording_io_{:08x}{:08x}", entropy(), entropy());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }
  std::size_t entries_in_dir() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }

  fs::path dir_;
};

TEST(RecordingPhase, NamesRoundTrip) {
  for (const Phase phase : kAllPhases) EXPECT_EQ(parse_phase(to_string(phase)), phase);
  EXPECT_EQ(to_string(Phase::kStepD), "step_d");
  EXPECT_EQ(to_string(Phase::kAis), "ais");
  EXPECT_FALSE(parse_phase("DIS"));
  EXPECT_FALSE(parse_phase(""));
  EXPECT_FALSE(parse_phase("dis "));
}

TEST(RecordingModel, AppendBuildsContiguousBlocksInOrder) {
  Recording recording;
  EXPECT_EQ(recording.size(), 0U);
  recording.append(Phase::kVal, 1.0, 2.0);
  recording.append(Phase::kDis, 3.0, 4.0);
  recording.append(Phase::kDis, 5.0, 6.0);
  EXPECT_EQ(recording.order(), (std::vector<Phase>{Phase::kVal, Phase::kDis}));
  EXPECT_TRUE(recording.has(Phase::kDis));
  EXPECT_FALSE(recording.has(Phase::kAis));
  EXPECT_TRUE(recording.phase(Phase::kAis).empty());
  ASSERT_EQ(recording.phase(Phase::kDis).size(), 2U);
  EXPECT_EQ(recording.phase(Phase::kDis)[1], (Sample{5.0, 6.0}));
  EXPECT_EQ(recording.size(), 3U);
  // A closed block cannot be reopened: phases are contiguous.
  EXPECT_THROW(recording.append(Phase::kVal, 0.0, 0.0), std::invalid_argument);
}

TEST(RecordingCsvParse, AcceptsCommentsAnywhereAndTrailingBlankLines) {
  const Recording recording = parse_recording_csv(
      "# made by hand\n"
      "phase,t,v,y\n"
      "# before the first row\n"
      "step_d,0,-3,0.5\n"
      "step_d,1,4,-1.25e-3\n"
      "#between phases\n"
      "dis,0,4,7\n"
      "# at the end\n"
      "\n"
      "  \n",
      kSource);
  EXPECT_EQ(recording.order(), (std::vector<Phase>{Phase::kStepD, Phase::kDis}));
  ASSERT_EQ(recording.phase(Phase::kStepD).size(), 2U);
  EXPECT_EQ(recording.phase(Phase::kStepD)[0], (Sample{-3.0, 0.5}));
  EXPECT_EQ(recording.phase(Phase::kStepD)[1], (Sample{4.0, -1.25e-3}));
  EXPECT_EQ(recording.phase(Phase::kDis)[0], (Sample{4.0, 7.0}));
}

TEST(RecordingCsvParse, AcceptsCrlfByteOrderMarkAndMissingFinalNewline) {
  const Recording recording = parse_recording_csv("\xEF\xBB\xBFphase,t,v,y\r\nval,0,1,2\r\nval,1,3,4", kSource);
  ASSERT_EQ(recording.phase(Phase::kVal).size(), 2U);
  EXPECT_EQ(recording.phase(Phase::kVal)[1], (Sample{3.0, 4.0}));
}

TEST(RecordingCsvParse, PhaseOrderIsFree) {
  const Recording recording = parse_recording_csv("phase,t,v,y\nval,0,1,2\nais,0,1,2\nstep_d,0,1,2\n", kSource);
  EXPECT_EQ(recording.order(), (std::vector<Phase>{Phase::kVal, Phase::kAis, Phase::kStepD}));
}

TEST(RecordingCsvParse, RejectsEmptyFileAndMissingData) {
  EXPECT_TRUE(Contains(parse_error(""), "rec.csv: file is empty"));
  EXPECT_TRUE(Contains(parse_error("# only a comment\n\n"), "rec.csv: no header 'phase,t,v,y'"));
  EXPECT_TRUE(Contains(parse_error("# c\nphase,t,v,y\n# c\n"), "rec.csv:2: header is not followed by any data"));
}

TEST(RecordingCsvParse, RejectsWrongHeader) {
  EXPECT_TRUE(
      Contains(parse_error("# c\nphase,t,v\nval,0,1\n"), "rec.csv:2: expected header 'phase,t,v,y', got 'phase,t,v'"));
  EXPECT_TRUE(Contains(parse_error("val,0,1,2\n"), "rec.csv:1: expected header"));
  EXPECT_TRUE(Contains(parse_error("phase, t, v, y\nval,0,1,2\n"), "rec.csv:1: expected header"));
}

TEST(RecordingCsvParse, RejectsWrongColumnCount) {
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,1,2\nval,1,3\n"),
                       "rec.csv:3: expected 4 comma-separated fields (phase,t,v,y), got 3"));
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,1,2,\n"), "rec.csv:2: expected 4 comma-separated fields"));
}

TEST(RecordingCsvParse, RejectsUnknownPhase) {
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,1,2\n# c\nDIS,0,1,2\n"), "rec.csv:4: unknown phase 'DIS'"));
}

TEST(RecordingCsvParse, RejectsMalformedNumbers) {
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,abc,2\n"), "rec.csv:2: column v: 'abc' is not a number"));
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,1,\n"), "rec.csv:2: column y: '' is not a number"));
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0, 1,2\n"), "rec.csv:2: column v: ' 1' is not a number"));
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,1,2.5x\n"),
                       "rec.csv:2: column y: trailing characters 'x' after the number in '2.5x'"));
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,1 ,2\n"), "rec.csv:2: column v: trailing characters ' '"));
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,0x10,2\n"), "rec.csv:2: column v: trailing characters"));
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,1e999,2\n"), "rec.csv:2: column v: '1e999' is out of"));
}

TEST(RecordingCsvParse, RejectsNonFiniteValues) {
  for (const std::string_view bad : {"nan", "NaN", "inf", "-inf", "infinity"}) {
    EXPECT_TRUE(Contains(parse_error(fmt::format("phase,t,v,y\nval,0,{},2\n", bad)),
                         fmt::format("rec.csv:2: column v: non-finite value '{}'", bad)));
    EXPECT_TRUE(Contains(parse_error(fmt::format("phase,t,v,y\nval,0,1,2\nval,1,1,{}\n", bad)),
                         fmt::format("rec.csv:3: column y: non-finite value '{}'", bad)));
  }
}

TEST(RecordingCsvParse, RejectsMalformedTime) {
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,1.0,1,2\n"), "rec.csv:2: column t: '1.0' is not a non-negative"));
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,-1,1,2\n"), "rec.csv:2: column t: '-1' is not a non-negative"));
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,,1,2\n"), "rec.csv:2: column t: '' is not a non-negative"));
}

TEST(RecordingCsvParse, RejectsTimeNotConsecutiveFromZero) {
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,1,1,2\n"), "rec.csv:2: column t: expected 0, got 1"));
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,1,2\nval,1,1,2\nval,3,1,2\n"),
                       "rec.csv:4: column t: expected 2, got 3"));
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,1,2\nval,0,1,2\n"), "rec.csv:3: column t: expected 1, got 0"));
  // Each phase restarts at 0.
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,1,2\ndis,1,1,2\n"), "rec.csv:3: column t: expected 0, got 1"));
}

TEST(RecordingCsvParse, RejectsPhaseAppearingTwice) {
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nstep_d,0,1,2\nstep_d,1,1,2\ndis,0,1,2\nstep_d,0,1,2\n"),
                       "rec.csv:5: phase 'step_d' appears again after its block ended at line 3"));
}

TEST(RecordingCsvParse, RejectsBlankLineBeforeMoreData) {
  EXPECT_TRUE(Contains(parse_error("phase,t,v,y\nval,0,1,2\n\nval,1,1,2\n"), "rec.csv:3: blank line before more data"));
  EXPECT_TRUE(Contains(parse_error("\nphase,t,v,y\nval,0,1,2\n"), "rec.csv:1: blank line before more data"));
}

TEST(RecordingCsvParse, QuotesOnlyTheStartOfLongGarbage) {
  const std::string garbage(200, 'z');
  const std::string message = parse_error(fmt::format("phase,t,v,y\n{},0,1,2\n", garbage));
  EXPECT_TRUE(Contains(message, "unknown phase 'zzzz"));
  EXPECT_LT(message.size(), 150U);
}

TEST(RecordingCsvParse, ErrorCarriesLineNumber) {
  try {
    parse_recording_csv("phase,t,v,y\nval,0,1,2\nval,1,x,2\n", kSource);
    FAIL() << "expected DataError";
  } catch (const DataError& error) {
    EXPECT_EQ(error.line(), std::optional<std::size_t>(3));
  }
}

TEST_F(RecordingFiles, ReadRejectsMissingFileAndDirectory) {
  const fs::path missing = dir_ / "missing.csv";
  try {
    read_recording_csv(missing);
    FAIL() << "expected DataError";
  } catch (const DataError& error) {
    EXPECT_EQ(std::string(error.what()), missing.string() + ": file not found");
    EXPECT_FALSE(error.line());
  }
  EXPECT_TRUE(Contains(error_of([&] { read_recording_csv(dir_); }), dir_.string() + ": is a directory, not a file"));
}

TEST_F(RecordingFiles, ReadErrorsNameTheFile) {
  const fs::path path = dir_ / "bad.csv";
  std::ofstream(path) << "phase,t,v,y\nval,0,1,2\nval,1,1,oops\n";
  try {
    read_recording_csv(path);
    FAIL() << "expected DataError";
  } catch (const DataError& error) {
    EXPECT_TRUE(Contains(error.what(), path.string() + ":3: column y: 'oops' is not a number"));
  }
}

TEST_F(RecordingFiles, WriteThenReadRoundTripsBitExactly) {
  const std::vector<double> values = {0.0,
                                      -0.0,
                                      0.1,
                                      1.0 / 3.0,
                                      -2.0 / 3.0,
                                      std::numbers::pi * 1e10,
                                      1e-300,
                                      123456789012345678.0,
                                      std::numeric_limits<double>::denorm_min(),
                                      std::numeric_limits<double>::min(),
                                      std::numeric_limits<double>::max(),
                                      std::numeric_limits<double>::lowest(),
                                      std::nextafter(1.0, 2.0)};
  Recording original;
  std::size_t k = 0;
  for (const Phase phase : kAllPhases) {  // the order `simulate` writes
    for (std::size_t t = 0; t < values.size(); ++t, ++k) {
      original.append(phase, values[t], values[(t + k) % values.size()]);
    }
  }
  const fs::path path = dir_ / "round_trip.csv";
  write_recording_csv(path, original, {"seed 42", "two\nlines", ""});

  const std::string text = slurp(path);
  EXPECT_TRUE(text.starts_with("# seed 42\n# two\n# lines\n#\nphase,t,v,y\nstep_d,0,0,"));
  EXPECT_TRUE(text.ends_with("\n"));

  const Recording read_back = read_recording_csv(path);
  ASSERT_EQ(read_back.order(), original.order());
  for (const Phase phase : kAllPhases) {
    const auto expected = original.phase(phase);
    const auto actual = read_back.phase(phase);
    ASSERT_EQ(actual.size(), expected.size());
    for (std::size_t t = 0; t < expected.size(); ++t) {
      EXPECT_EQ(std::bit_cast<std::uint64_t>(actual[t].v), std::bit_cast<std::uint64_t>(expected[t].v))
          << to_string(phase) << " t=" << t;
      EXPECT_EQ(std::bit_cast<std::uint64_t>(actual[t].y), std::bit_cast<std::uint64_t>(expected[t].y))
          << to_string(phase) << " t=" << t;
    }
  }
}

TEST_F(RecordingFiles, WriteReplacesExistingFileAndLeavesNoTemporary) {
  const fs::path path = dir_ / "data.csv";
  std::ofstream(path) << "old content that is longer than the new one ...............................\n";
  Recording recording;
  recording.append(Phase::kVal, 1.5, -2.5);
  write_recording_csv(path, recording, {});
  EXPECT_EQ(slurp(path), "phase,t,v,y\nval,0,1.5,-2.5\n");
  EXPECT_EQ(entries_in_dir(), 1U);
}

TEST_F(RecordingFiles, WriteRefusesWhatCouldNotBeReadBack) {
  const fs::path path = dir_ / "data.csv";
  EXPECT_TRUE(
      Contains(error_of([&] { write_recording_csv(path, Recording{}, {}); }), "refusing to write an empty recording"));
  Recording recording;
  recording.append(Phase::kDis, 1.0, 2.0);
  recording.append(Phase::kDis, 1.0, std::nan(""));
  EXPECT_TRUE(Contains(error_of([&] { write_recording_csv(path, recording, {}); }),
                       "non-finite sample v = 1, y = nan at phase 'dis' t = 1"));
  EXPECT_EQ(entries_in_dir(), 0U);
}

TEST_F(RecordingFiles, WriteIntoMissingDirectoryCreatesNothing) {
  const fs::path missing_dir = dir_ / "no_such_dir";
  const fs::path path = missing_dir / "data.csv";
  Recording recording;
  recording.append(Phase::kVal, 1.0, 2.0);
  try {
    write_recording_csv(path, recording, {});
    FAIL() << "expected DataError";
  } catch (const DataError& error) {
    EXPECT_EQ(std::string(error.what()),
              fmt::format("{}: cannot write: directory '{}' does not exist", path.string(), missing_dir.string()));
  }
  EXPECT_FALSE(fs::exists(missing_dir));
  EXPECT_EQ(entries_in_dir(), 0U);
}

TEST_F(RecordingFiles, DirectoryAtTheTargetIsRefusedAndLeavesNothing) {
  // The target is an existing non-empty directory: refused with a clear message before anything is written
  // (it used to surface as a failed rename, "cannot replace file: Device or resource busy").
  const fs::path blocking = dir_ / "data.csv";
  fs::create_directories(blocking / "child");
  Recording recording;
  recording.append(Phase::kVal, 1.0, 2.0);
  EXPECT_TRUE(Contains(error_of([&] { write_recording_csv(blocking, recording, {}); }),
                       blocking.string() + ": cannot write: it is a directory, not a file"));
  EXPECT_EQ(entries_in_dir(), 1U);  // only the blocking directory
  EXPECT_TRUE(fs::is_directory(blocking / "child"));
}

// The content is renamed onto the target: a pipe (or a device such as /dev/null) must not become a plain file.
TEST_F(RecordingFiles, ANonRegularTargetIsRefusedAndKept) {
  const fs::path pipe = dir_ / "pipe.csv";
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  Recording recording;
  recording.append(Phase::kVal, 1.0, 2.0);
  EXPECT_TRUE(Contains(error_of([&] { write_recording_csv(pipe, recording, {}); }),
                       pipe.string() + ": cannot write: it exists and is not a regular file"));
  EXPECT_TRUE(fs::is_fifo(pipe));
  EXPECT_EQ(entries_in_dir(), 1U);
}

// Found by hand (issue 14): the rename replaced a symbolic link by a plain file and left its target unchanged.
TEST_F(RecordingFiles, ASymbolicLinkIsWrittenThroughAndStaysALink) {
  const fs::path target = dir_ / "target.txt";
  const fs::path link = dir_ / "link.txt";
  write_file_atomically(target, "old\n");
  fs::create_symlink(target, link);
  write_file_atomically(link, "new\n");
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(read_file_text(target), "new\n");
  EXPECT_EQ(entries_in_dir(), 2U);  // no temporary left behind
}

TEST_F(RecordingFiles, WriteFileAtomicallyRejectsDirectoryPath) {
  EXPECT_TRUE(Contains(error_of([&] { write_file_atomically(dir_ / "", "x"); }), "names a directory, not a file"));
}

}  // namespace
}  // namespace lashid::sim
