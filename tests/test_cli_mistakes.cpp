// The mistakes a new user makes on the command line (found by trying the tool as one, session 14): each gets a
// clear error naming the option or file, a non-zero exit and no file written, or, where the command runs, a
// result that cannot be mistaken for another. Each check failed before its fix.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "json_text.hpp"

#include "cli_harness.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace lashid::test;

class CliMistakes : public LashidExeTest {
 protected:
  void simulate(const std::string& csv, const std::string& config) const {
    const Outcome r =
        run({"simulate", "--scenario", "dis_paper", "--seed", "1", "--out", csv, "--config-out", config});
    ASSERT_EQ(r.exit_code, 0) << r;
  }

  // Copies the recording keeping only the rows whose phase is one of `phases` (and the comments and header).
  void keep_phases(const std::string& from, const std::string& to, const std::vector<std::string>& phases) const {
    std::istringstream in(slurp(work_ / from));
    std::ofstream out(work_ / to);
    for (std::string line; std::getline(in, line);) {
      const std::string phase = line.substr(0, line.find(','));
      const bool data = line.find(',') != std::string::npos && phase != "phase";
      if (!data || std::find(phases.begin(), phases.end(), phase) != phases.end()) out << line << "\n";
    }
  }
};

// CLI11's range checks compare, and NaN compares false with everything: "nan" passed them. Infinity too where
// only the sign was checked.
TEST_F(CliMistakes, ANumberOptionThatIsNotFiniteIsRefusedAndNothingIsWritten) {
  const std::string damper = std::string(LASHID_DAMPER_DATA) + "/char_1Hz30lbtension1amplitude.csv";
  const std::string damper2 = std::string(LASHID_DAMPER_DATA) + "/char_0.5Hz30lbtension1amplitude.csv";
  const std::vector<std::vector<std::string>> commands = {
      {"simulate", "--scenario", "dis_paper", "--noise-variance", "nan", "--out", "s.csv"},
      {"simulate", "--scenario", "dis_paper", "--noise-variance", "inf", "--out", "s.csv"},
      {"simulate", "--scenario", "dis_paper", "--input-lag", "nan", "--out", "s.csv"},
      {"design", "--n", "1", "--m", "2", "--v-min", "nan", "--v-max", "1", "--operator", "switch", "--out", "d.json"},
      {"design", "--n", "1", "--m", "2", "--v-min", "-1", "--v-max", "-inf", "--operator", "switch", "--out",
       "d.json"},
      {"operator-fit", "--train", damper, "--test", damper2, "--deadband", "nan", "--json", "o.json"},
      {"operator-fit", "--train", damper, "--test", damper2, "--reversal-window", "nan", "--json", "o.json"},
  };
  for (const auto& command : commands) {
    std::string text;
    for (const auto& word : command) text += word + " ";
    const Outcome r = run(command);
    EXPECT_NE(r.exit_code, 0) << text << "\n" << r;
    EXPECT_TRUE(Contains(r.err, "must be a finite number")) << r;
    EXPECT_TRUE(files_below(work_).empty()) << r;
  }
}

// Levels between -1e308 and 1e308: the exact formula (a (K-1-i) + b i) / (K-1) overflows to -inf; the levels are
// then those of the convex combination, -1e308 + 2e308 i / 3 for K = 4: -1e308, -1e308/3, 1e308/3 (V_d).
TEST_F(CliMistakes, LevelsNearTheEndOfTheDoubleRangeAreComputedWithoutOverflow) {
  const Outcome r = run({"design", "--n", "1", "--m", "3", "--v-min", "-1e308", "--v-max", "1e308", "--operator",
                         "switch", "--out", "d.json"});
  // The firmware works in float32, where these levels do not exist: refused, by its rule, naming the option.
  EXPECT_NE(r.exit_code, 0) << r;
  EXPECT_FALSE(Contains(r.err, "got null")) << r;
  EXPECT_TRUE(Contains(r.err, "the firmware image could not run this design: --v-min = -1e+308 is beyond the range "
                              "of float32")) << r;
  EXPECT_TRUE(files_below(work_).empty()) << r;
}

// With fewer than 100 runs there is no "first 100 runs" to report (it divided the hits among 10 runs by 100).
TEST_F(CliMistakes, ReproduceWithFewerThanAHundredRunsReportsNoFirstHundred) {
  const Outcome r = run({"reproduce", "--runs", "10"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(Contains(r.out, "over 10 runs")) << r;
  EXPECT_FALSE(Contains(r.out, "first 100 runs")) << r;
}

// A test file that is also a training file would be scored in-sample and printed as a test fit.
TEST_F(CliMistakes, OperatorFitRefusesATestFileThatIsAlsoTrainedOn) {
  const std::string damper = std::string(LASHID_DAMPER_DATA) + "/char_1Hz30lbtension1amplitude.csv";
  const std::string other = std::string(LASHID_DAMPER_DATA) + "/char_0.5Hz30lbtension1amplitude.csv";
  const Outcome r = run({"operator-fit", "--train", damper, other, "--test", damper, "--json", "o.json"});
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(Contains(r.err, "is also a --train file")) << r;
  EXPECT_TRUE(files_below(work_).empty()) << r;
  // A gnuplot that cannot run is found before the fit, not after it: no JSON either.
  const Outcome plot = run({"operator-fit", "--train", damper, "--test", other, "--json", "o.json", "--plot",
                            "o.png", "--gnuplot", "/nonexistent/gnuplot"});
  EXPECT_EQ(plot.exit_code, 1) << plot;
  EXPECT_TRUE(Contains(plot.err, "o.png: cannot plot: '/nonexistent/gnuplot' not found")) << plot;
  EXPECT_FALSE(Contains(plot.out, "Nominal operators")) << plot;
  EXPECT_TRUE(files_below(work_).empty()) << plot;
  // A test file at half the training files' rate (every other row of a 1024 per s file): the filter after the
  // operator and the Hz figures would be wrong for it; refused before any fit, naming both files.
  std::string half, both;
  {
    std::istringstream in(slurp(other));
    std::size_t row = 0;
    for (std::string line; std::getline(in, line); ++row) {
      if (row == 0 || row % 2 == 1) half += line + "\n";
      both += row == 0 ? "t_s,x_in,F_kip,v_in_per_s,F_act1_lb,x_in\n" : line + "\n";
    }
  }
  std::ofstream(work_ / "half.csv") << half;
  const Outcome rate = run({"operator-fit", "--train", damper, "--test", (work_ / "half.csv").string()});
  EXPECT_EQ(rate.exit_code, 1) << rate;
  EXPECT_TRUE(Contains(rate.err, "half.csv: sampled at 512 per s, the first training file")) << rate;
  EXPECT_TRUE(Contains(rate.err, "at 1024: the filter after the operator needs one rate for every file")) << rate;
  EXPECT_FALSE(Contains(rate.out, "Nominal operators")) << rate;
  // Two columns named x_in (the last one replaced the F_act2 column): neither is guessed.
  std::ofstream(work_ / "twice.csv") << both;
  const Outcome twice = run({"operator-fit", "--train", damper, "--test", (work_ / "twice.csv").string()});
  EXPECT_EQ(twice.exit_code, 1) << twice;
  EXPECT_TRUE(Contains(twice.err, "twice.csv:1: column 'x_in' appears twice in the header (fields 2 and 6)")) << twice;
}

// "both" asks for both schemes: a recording without the AIS phases is an error, as with --scheme ais; "auto" (the
// default) identifies what the data holds.
TEST_F(CliMistakes, IdentifyBothNeedsBothSchemesPhasesAndAutoTakesWhatThereIs) {
  simulate("rec.csv", "cfg.json");
  keep_phases("rec.csv", "dis_only.csv", {"step_d", "dis"});
  const Outcome both = run({"identify", "--config", "cfg.json", "--data", "dis_only.csv", "--scheme", "both"});
  EXPECT_EQ(both.exit_code, 1) << both;
  EXPECT_TRUE(Contains(both.err, "step_a")) << both;
  EXPECT_FALSE(Contains(both.out, "DIS")) << "a result printed before the error: " << both;
  const Outcome automatic = run({"identify", "--config", "cfg.json", "--data", "dis_only.csv", "--json", "e.json"});
  ASSERT_EQ(automatic.exit_code, 0) << automatic;
  const json e = parse_json(slurp(work_ / "e.json"));
  EXPECT_TRUE(e.contains("dis"));
  EXPECT_FALSE(e.contains("ais"));
  // The output path is checked before the work, not after the estimates are printed.
  const Outcome no_dir = run({"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "nodir/e.json"});
  EXPECT_EQ(no_dir.exit_code, 1) << no_dir;
  EXPECT_FALSE(Contains(no_dir.out, "DIS")) << no_dir;
}

// A recording cut short (its last phase 339 samples instead of the config's 2000) is identified, as a run stopped
// early must be, but said: a note on stderr names the phase, its count and the config's key. A whole one says nothing.
TEST_F(CliMistakes, ARecordingShorterThanItsConfigIsNoted) {
  simulate("rec.csv", "cfg.json");
  const json config = parse_json(slurp(work_ / "cfg.json"));
  ASSERT_TRUE(config.contains("pulse_length_a")) << config.dump();
  const int stated = config.at("pulse_length_a").get<int>();
  const Outcome whole = run({"identify", "--config", "cfg.json", "--data", "rec.csv"});
  ASSERT_EQ(whole.exit_code, 0) << whole;
  EXPECT_FALSE(Contains(whole.err, "note:")) << whole;
  std::istringstream in(slurp(work_ / "rec.csv"));
  std::ofstream out(work_ / "cut.csv");
  int ais = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.starts_with("ais,") && ++ais > 339) continue;
    if (line.starts_with("val,")) continue;
    out << line << "\n";
  }
  out.close();
  const Outcome cut = run({"identify", "--config", "cfg.json", "--data", "cut.csv"});
  ASSERT_EQ(cut.exit_code, 0) << cut;
  EXPECT_TRUE(Contains(cut.err, "note: cut.csv: phase 'ais' has 339 samples, the config's pulse_length_a says " +
                                    std::to_string(stated)))
      << cut;
}

// A scheme without a solution: no estimates printed, and null (not the zeros they start at) in the JSON. One
// output of 1e60 makes the normal matrix too ill-conditioned to solve (1e300 is refused as a sample, naming it).
TEST_F(CliMistakes, AFailedSchemeHasNullEstimatesNotZeros) {
  simulate("rec.csv", "cfg.json");
  std::istringstream in(slurp(work_ / "rec.csv"));
  std::ofstream out(work_ / "outlier.csv");
  bool edited = false;
  for (std::string line; std::getline(in, line);) {
    if (!edited && line.starts_with("dis,")) {
      line = line.substr(0, line.rfind(',')) + ",1e60";
      edited = true;
    }
    out << line << "\n";
  }
  out.close();
  const Outcome r =
      run({"identify", "--config", "cfg.json", "--data", "outlier.csv", "--scheme", "dis", "--json", "e.json"});
  EXPECT_EQ(r.exit_code, 2) << r;
  EXPECT_TRUE(Contains(r.out, "no estimates: ")) << r;
  EXPECT_FALSE(Contains(r.out, "a1 ")) << r;
  const json e = parse_json(slurp(work_ / "e.json"));
  EXPECT_NE(e.at("dis").at("status").get<std::string>(), "ok");
  EXPECT_TRUE(e.at("dis").at("a").is_null());
  EXPECT_TRUE(e.at("dis").at("theta").is_null());
  EXPECT_TRUE(e.at("dis").at("ybar0").is_number());  // the step experiment's mean needs no solution
  // A value too large for the estimator's sums is refused as a sample, naming the phase and t.
  std::string text = slurp(work_ / "outlier.csv");
  text.replace(text.find(",1e60"), 5, ",1e300");
  std::ofstream(work_ / "huge.csv") << text;
  const Outcome huge = run({"identify", "--config", "cfg.json", "--data", "huge.csv", "--scheme", "dis"});
  EXPECT_EQ(huge.exit_code, 1) << huge;
  EXPECT_TRUE(Contains(huge.err, "huge.csv: phase dis t = 0: non-finite or too large sample")) << huge;
}

// hil: one of --firmware and --attach is required (a second callback had replaced the check), and a firmware that
// is not an ARM ELF image is refused before QEMU boots it into a lockup.
TEST_F(CliMistakes, HilNamesAMissingOrWrongFirmware) {
  const Outcome none = run({"hil", "--scenario", "dis_paper"});
  EXPECT_NE(none.exit_code, 0) << none;
  EXPECT_TRUE(Contains(none.err, "--firmware or --attach")) << none;
  std::ofstream(work_ / "text.elf") << "not an image\n";
  const Outcome text = run({"hil", "--scenario", "dis_paper", "--firmware", "text.elf", "--timeout", "5"});
  EXPECT_EQ(text.exit_code, 1) << text;
  EXPECT_TRUE(Contains(text.err, "'text.elf' is not an ARM ELF image")) << text;
  EXPECT_FALSE(Contains(text.out + text.err, "qemu")) << text;
  // An ARM ELF cut short: its one loaded segment (file bytes 4096..4351) lies past the end of the 84-byte file, then
  // its program header table does. QEMU booted the first into a lockup; the second was untagged and waited out the
  // time limit. Header fields at their System V ABI offsets, little-endian.
  std::vector<unsigned char> elf(84, 0);
  const auto put = [&](std::size_t at, std::uint32_t value, int bytes) {
    for (int k = 0; k < bytes; ++k) elf[at + static_cast<std::size_t>(k)] = static_cast<unsigned char>(value >> (8 * k));
  };
  put(0, 0x464c457f, 4);  // \x7fELF
  put(4, 1, 1);           // 32-bit
  put(5, 1, 1);           // little-endian
  put(6, 1, 1);
  put(16, 2, 2);   // executable
  put(18, 40, 2);  // EM_ARM
  put(20, 1, 4);
  put(28, 52, 4);  // e_phoff
  put(40, 52, 2);  // e_ehsize
  put(42, 32, 2);  // e_phentsize
  put(44, 1, 2);   // e_phnum
  put(52, 1, 4);        // PT_LOAD
  put(56, 4096, 4);     // p_offset
  put(68, 256, 4);      // p_filesz
  std::ofstream(work_ / "cut.elf", std::ios::binary).write(reinterpret_cast<const char*>(elf.data()), 84);
  const Outcome cut = run({"hil", "--scenario", "dis_paper", "--firmware", "cut.elf", "--timeout", "5"});
  EXPECT_EQ(cut.exit_code, 1) << cut;
  EXPECT_TRUE(Contains(cut.err, "'cut.elf' is damaged: its segment 0 ends at byte 4352, past the end of the file "
                                "(84 bytes)")) << cut;
  std::ofstream(work_ / "cut.elf", std::ios::binary).write(reinterpret_cast<const char*>(elf.data()), 60);
  const Outcome headers = run({"hil", "--scenario", "dis_paper", "--firmware", "cut.elf", "--timeout", "5"});
  EXPECT_EQ(headers.exit_code, 1) << headers;
  EXPECT_TRUE(Contains(headers.err, "'cut.elf' is damaged: its program header table lies past the end")) << headers;
  // --attach to what can never be a socket is said at once; one that is not there is waited for no longer than
  // --timeout (it waited 10 s whatever the limit, then said only "connection refused").
  const Outcome file = run({"hil", "--attach", "text.elf", "b.sock", "--scenario", "dis_paper", "--timeout", "60"});
  EXPECT_EQ(file.exit_code, 1) << file;
  EXPECT_TRUE(Contains(file.err, "cannot attach to text.elf: it is a regular file, not a Unix socket or a serial "
                                 "port")) << file;
  const Outcome absent = run({"hil", "--attach", "no.sock", "b.sock", "--scenario", "dis_paper", "--timeout", "1"});
  EXPECT_EQ(absent.exit_code, 1) << absent;
  EXPECT_TRUE(Contains(absent.err, "cannot connect to no.sock: No such file or directory (waited 1 s for it)"))
      << absent;
  // qemu-command checks the image as hil does: it printed a command line for anything.
  const Outcome missing = run({"qemu-command", "--kernel", "nonexist.elf"});
  EXPECT_EQ(missing.exit_code, 1) << missing;
  EXPECT_TRUE(Contains(missing.err, "qemu-command: firmware 'nonexist.elf' not found")) << missing;
  EXPECT_TRUE(missing.out.empty()) << missing;
  const Outcome damaged = run({"qemu-command", "--kernel", "cut.elf"});
  EXPECT_EQ(damaged.exit_code, 1) << damaged;
  EXPECT_TRUE(Contains(damaged.err, "qemu-command: firmware 'cut.elf' is damaged")) << damaged;
}

// What hil can check before the run it checks before it (the run takes seconds to minutes): the file of
// --expect-estimates and the --json path. Both are found here before the firmware file is even looked at.
TEST_F(CliMistakes, HilChecksItsInputsBeforeTheRun) {
  std::ofstream(work_ / "text.elf") << "not an image\n";
  std::ofstream(work_ / "expected.json") << R"({"dis": {"a": [1], "b": [1, 2], "F": [1], "status": 0}})";
  const Outcome shape = run({"hil", "--scenario", "dis_paper", "--firmware", "text.elf", "--expect-estimates",
                             "expected.json"});
  EXPECT_EQ(shape.exit_code, 1) << shape;
  EXPECT_TRUE(Contains(shape.err, "expected.json: 'dis': a and b need 1 to 4 entries each")) << shape;
  std::ofstream(work_ / "no_status.json") << R"({"dis": {"a": [1], "b": [1], "F": [1]}})";
  const Outcome status = run({"hil", "--scenario", "dis_paper", "--firmware", "text.elf", "--expect-estimates",
                              "no_status.json"});
  EXPECT_EQ(status.exit_code, 1) << status;
  EXPECT_TRUE(Contains(status.err, "'dis' is not an estimate of a `lashid hil --json` file")) << status;
  const Outcome json_dir = run({"hil", "--scenario", "dis_paper", "--firmware", "text.elf", "--json", "nodir/r.json"});
  EXPECT_EQ(json_dir.exit_code, 1) << json_dir;
  EXPECT_TRUE(Contains(json_dir.err, "nodir")) << json_dir;
  EXPECT_FALSE(Contains(json_dir.err, "ARM ELF")) << json_dir;
  const Outcome timeout = run({"hil", "--scenario", "dis_paper", "--firmware", "text.elf", "--timeout", "1e12"});
  EXPECT_NE(timeout.exit_code, 0) << timeout;
  EXPECT_TRUE(Contains(timeout.err, "--timeout")) << timeout;
}

// A config's sensor_range of the wrong size: the message says what it needs, once.
TEST_F(CliMistakes, ASensorRangeOfTheWrongSizeIsSaidPlainly) {
  std::ofstream(work_ / "cfg.json") << R"({"n": 2, "m": 2, "v_min": -3, "v_max": 4, "operator": "switch",
    "V_d": [-3, 1], "V_a": [4, 2], "sensor_range": [1, 2, 3]})";
  const Outcome r = run({"design", "--check", "cfg.json"});
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(Contains(r.err, "cfg.json: 'sensor_range' must have 2 entries, got 3")) << r;
}

// A config's sensor_range is applied by identify as by the device: the y outside it are left out and said (the
// dis_paper recording's y reaches above 215 in both schemes' phases; its config had no range).
TEST_F(CliMistakes, IdentifyLeavesOutWhatLiesOutsideTheSensorRangeAndSaysSo) {
  simulate("rec.csv", "cfg.json");
  json cfg = parse_json(slurp(work_ / "cfg.json"));
  cfg["sensor_range"] = {-1000, 215};
  std::ofstream(work_ / "ranged.json") << cfg.dump();
  const Outcome r = run({"identify", "--config", "ranged.json", "--data", "rec.csv", "--float"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(Contains(r.err, "outside the config's sensor_range [-1000, 215] left out")) << r;
  const Outcome plain = run({"identify", "--config", "cfg.json", "--data", "rec.csv", "--float"});
  ASSERT_EQ(plain.exit_code, 0) << plain;
  EXPECT_FALSE(Contains(plain.err, "sensor_range")) << plain;
  EXPECT_NE(r.out, plain.out) << "the range changed nothing: the test tests nothing";
  // diagnose's joint model cannot leave them out: it says so.
  const Outcome d = run({"diagnose", "--config", "ranged.json", "--data", "rec.csv"});
  ASSERT_EQ(d.exit_code, 0) << d;
  EXPECT_TRUE(Contains(d.err, "lie outside the config's sensor_range [-1000, 215]: the DIS/AIS estimates leave them "
                              "out, the joint model of the diagnosis fits them")) << d;
  // A range the whole step experiment lies outside: said as such, not as a pulse sample before the step mean.
  cfg["sensor_range"] = {1e9, 2e9};
  std::ofstream(work_ / "far.json") << cfg.dump();
  const Outcome far = run({"identify", "--config", "far.json", "--data", "rec.csv"});
  EXPECT_EQ(far.exit_code, 1) << far;
  EXPECT_TRUE(Contains(far.err, "phase step_d: no usable sample for the step mean (2001 of its 2001 outside the "
                                "config's sensor_range)")) << far;
}

// CLI11 says what is missing before the word it did not know: a misspelt command was "A subcommand is required"
// and a misspelt required option "--config is required". The mistyped word is named, with the closest known name.
TEST_F(CliMistakes, AMisspeltCommandOrOptionIsNamedWithTheClosestKnownName) {
  const Outcome command = run({"idntify"});
  EXPECT_EQ(command.exit_code, 109) << command;
  EXPECT_TRUE(Contains(command.err, "'idntify' is not a command (did you mean 'identify'?); the commands: ")) << command;
  std::ofstream(work_ / "rec.csv") << "";
  const Outcome option = run({"identify", "--confg", "cfg.json", "--data", (work_ / "rec.csv").string()});
  EXPECT_EQ(option.exit_code, 109) << option;
  EXPECT_TRUE(Contains(option.err, "identify: unknown option --confg (did you mean --config?)")) << option;
  const Outcome missing = run({"identify", "--data", (work_ / "rec.csv").string()});
  EXPECT_EQ(missing.exit_code, 106) << missing;  // a required option left out is still said so
  EXPECT_TRUE(Contains(missing.err, "--config is required")) << missing;
}

// CLI11 clamps an unsigned number beyond 2^64 - 1 to 2^64 - 1 without a word: the recording was that seed's. 2^64 - 1
// itself is a seed; 2^64 is not, and a sweep must not wrap past 2^64 - 1 to seed 0.
TEST_F(CliMistakes, ASeedBeyondTwoToTheSixtyFourIsRefusedInsteadOfClamped) {
  const Outcome big = run({"simulate", "--scenario", "dis_paper", "--seed", "18446744073709551616", "--out", "rec.csv"});
  EXPECT_EQ(big.exit_code, 105) << big;  // CLI11's ValidationError, README's 100+ range
  EXPECT_TRUE(Contains(big.err, "--seed: must be at most 18446744073709551615")) << big;
  EXPECT_TRUE(files_below(work_).empty());
  const Outcome sweep = run({"diagnose-sweep", "--first-seed", "18446744073709551615", "--seeds", "2"});
  EXPECT_EQ(sweep.exit_code, 105) << sweep;
  EXPECT_TRUE(Contains(sweep.err, "--first-seed: 18446744073709551615 + --seeds 2 passes 2^64 - 1")) << sweep;
  const Outcome max = run({"simulate", "--scenario", "dis_paper", "--seed", "18446744073709551615", "--out", "rec.csv"});
  EXPECT_EQ(max.exit_code, 0) << max;
}

// The generator's rules on --cause are said in terms of the option.
TEST_F(CliMistakes, HiddenEffectNamesTheCauseListThatIsWrong) {
  const Outcome repeated = run({"hidden-effect", "--cause", "dead_time+dead_time", "--out", "r.csv", "--config-out",
                                "c.json"});
  EXPECT_EQ(repeated.exit_code, 1) << repeated;
  EXPECT_TRUE(Contains(repeated.err, "lashid: error: --cause dead_time+dead_time: a cause is repeated")) << repeated;
  const Outcome unknown = run({"hidden-effect", "--cause", "dead_time+backlash", "--out", "r.csv", "--config-out",
                               "c.json"});
  EXPECT_EQ(unknown.exit_code, 1) << unknown;
  EXPECT_TRUE(Contains(unknown.err, "--cause dead_time+backlash: unknown cause 'backlash' (none, input_lag")) << unknown;
  EXPECT_TRUE(files_below(work_).empty());
}

}  // namespace
