// End-to-end tests of `lashid design` (write a config, --check one) and of the lengths `simulate --config-out`
// writes. The written files are also read here through the host reader and the firmware's check_design, apart from
// the program. Every expected number is worked out by hand in the comments from the paper's rules.
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "json_text.hpp"

#include "cli_harness.hpp"
#include "lashid/firmware/run_design.hpp"
#include "lashid/hil/config_design.hpp"
#include "lashid/io/config.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace lashid::test;

class CliDesign : public LashidExeTest {
 protected:
  json read_json(const std::string& name) const { return parse_json(slurp(work_ / name)); }
  void write_json(const std::string& name, const json& value) const {
    std::ofstream(work_ / name) << value.dump(2) << "\n";
  }
  Outcome design(std::vector<std::string> args) const {
    args.insert(args.begin(), "design");
    return run(args);
  }
  // The written file through the host reader and the firmware's rules, without the program.
  void expect_host_and_firmware_accept(const std::string& name) const {
    const lashid::sim::ExperimentConfig config = lashid::sim::read_config_json(work_ / name);
    const lashid::fw::RunDesign run =
        lashid::sim::run_design_as_is(config, lashid::sim::experiment_lengths(config), name);
    EXPECT_EQ(lashid::fw::check_design(run), lashid::fw::DesignStatus::kOk);
  }
  // A valid config (n = 2, m = 6 of docs/data-format.md, T = 18) with `key` set to `value`.
  std::string config_with(const std::string& key, const json& value) const {
    json config = parse_json(R"({"n": 2, "m": 6, "v_min": -3, "v_max": 4, "V_d": [-3, -2, -1, 0, 1, 2],
                                  "V_a": [4, 3, 2, 1, 0, -1], "operator": "backlash"})");
    if (value.is_null()) {
      config.erase(key);
    } else {
      config[key] = value;
    }
    write_json("in.json", config);
    return "in.json";
  }
};

TEST_F(CliDesign, HelpDocumentsBothModes) {
  const Outcome top = run({"--help"});
  EXPECT_TRUE(Contains(top.out, "design"));
  const Outcome help = design({"--help"});
  ASSERT_EQ(help.exit_code, 0) << help;
  for (const char* option : {"--check", "--n", "--m", "--v-min", "--v-max", "--operator", "--levels", "--step-length",
                             "--pulse-length", "--val-length", "--val-seed", "--out"}) {
    EXPECT_TRUE(Contains(help.out, option)) << option;
  }
}

TEST_F(CliDesign, WritesEvenlySpacedLevelsAndThePapersLengths) {
  const Outcome r = design({"--n", "3", "--m", "8", "--v-min", "-2", "--v-max", "2", "--operator", "backlash", "--out",
                            "cfg.json"});
  ASSERT_EQ(r.exit_code, 0) << r;
  const json c = read_json("cfg.json");
  EXPECT_EQ(c.at("n"), 3);
  EXPECT_EQ(c.at("m"), 8);
  EXPECT_EQ(c.at("operator"), "backlash");
  // K = m + 1 = 9 levels over [-2, 2], 0.5 apart: V_d the 8 lowest, V_a the 8 highest from v_max down.
  EXPECT_EQ(c.at("V_d"), json({-2.0, -1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5}));
  EXPECT_EQ(c.at("V_a"), json({2.0, 1.5, 1.0, 0.5, 0.0, -0.5, -1.0, -1.5}));
  EXPECT_EQ(c.at("step_length"), 2000);
  EXPECT_EQ(c.at("pulse_length_d"), 2013);  // T = 3 (8 + 3) = 33; 2000 / 33 = 60.6, so 61 periods
  EXPECT_EQ(c.at("pulse_length_a"), 2013);
  EXPECT_EQ(c.at("val_length"), 1000);
  EXPECT_EQ(c.at("val_seed"), 1);
  expect_host_and_firmware_accept("cfg.json");

  const Outcome check = design({"--check", "cfg.json"});
  ASSERT_EQ(check.exit_code, 0) << check;
  EXPECT_TRUE(Contains(check.out, "T = max(n,2)(m+3) = 33"));
  EXPECT_TRUE(Contains(check.out, "61 periods"));
  // Interval check 16T = 528 (backlash), steps 2 (2000 + 1) = 4002, pulses 2 * 2013 = 4026, validation 1000.
  EXPECT_TRUE(Contains(check.out, "firmware run: 9556 samples = 528 interval check + 4002 steps + 4026 pulses + "
                                  "1000 validation"));
  EXPECT_TRUE(Contains(check.out, "cfg.json: valid for the host and the firmware image"));
}

TEST_F(CliDesign, LevelCountReproducesTheDocumentedExample) {
  // K = 8 levels over [-3, 4] are 1 apart: V_d = -3..2 and V_a = 4..-1, the example of docs/data-format.md.
  // T = 2 (6 + 3) = 18; 2000 / 18 = 111.1, so 112 periods = 2016.
  const Outcome r = design({"--n", "2", "--m", "6", "--v-min", "-3", "--v-max", "4", "--levels", "8", "--operator",
                            "switch", "--out", "cfg.json"});
  ASSERT_EQ(r.exit_code, 0) << r;
  const json c = read_json("cfg.json");
  EXPECT_EQ(c.at("V_d"), json({-3.0, -2.0, -1.0, 0.0, 1.0, 2.0}));
  EXPECT_EQ(c.at("V_a"), json({4.0, 3.0, 2.0, 1.0, 0.0, -1.0}));
  EXPECT_EQ(c.at("pulse_length_d"), 2016);
  EXPECT_EQ(c.at("operator"), "switch");
  expect_host_and_firmware_accept("cfg.json");

  // K = 5 over [0, 1]: 0, 0.25, 0.5, 0.75, 1; m = 2 takes the two lowest and the two highest.
  ASSERT_EQ(design({"--n", "1", "--m", "2", "--v-min", "0", "--v-max", "1", "--levels", "5", "--operator", "switch",
                    "--out", "two.json"})
                .exit_code,
            0);
  EXPECT_EQ(read_json("two.json").at("V_d"), json({0.0, 0.25}));
  EXPECT_EQ(read_json("two.json").at("V_a"), json({1.0, 0.75}));
  EXPECT_EQ(read_json("two.json").at("pulse_length_d"), 2000);  // s = max(1, 2) = 2, T = 2 (2 + 3) = 10 divides 2000
}

TEST_F(CliDesign, GivenLengthsAreWrittenAsGiven) {
  // n = 2, m = 6: 2T = 36 is the shortest pulse experiment, L = 3 the shortest step experiment.
  const Outcome r = design({"--n", "2", "--m", "6", "--v-min", "-1", "--v-max", "1", "--operator", "backlash",
                            "--step-length", "3", "--pulse-length", "36", "--val-length", "0", "--val-seed",
                            "4294967295", "--out", "cfg.json"});
  ASSERT_EQ(r.exit_code, 0) << r;
  const json c = read_json("cfg.json");
  EXPECT_EQ(c.at("step_length"), 3);
  EXPECT_EQ(c.at("pulse_length_d"), 36);
  EXPECT_EQ(c.at("pulse_length_a"), 36);
  EXPECT_EQ(c.at("val_length"), 0);
  EXPECT_EQ(c.at("val_seed"), 4294967295U);
  expect_host_and_firmware_accept("cfg.json");
}

TEST_F(CliDesign, RefusesBadOptionsNamingTheRuleAndWritesNothing) {
  const std::vector<std::string> base = {"--n", "2", "--m", "6", "--v-min", "-3", "--v-max", "4", "--operator",
                                         "backlash", "--out", "cfg.json"};
  const auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = base;
    args.insert(args.end(), extra.begin(), extra.end());
    return design(args);
  };
  struct Case {
    std::vector<std::string> extra;
    std::string message;
  };
  for (const Case& c : std::vector<Case>{
           // The options are at fault, not the file to be written: named as options, and the file not at all.
           {{"--pulse-length", "20"},
            "lashid: error: --pulse-length = 20 is shorter than two pulse periods (2T = 36 for n = 2, m = 6); nothing "
            "written"},
           {{"--step-length", "2"}, "error: --step-length = 2 must be greater than n = 2"},
           {{"--val-length", "-1"}, "error: --val-length = -1 must not be negative"},
           {{"--val-seed", "4294967296"}, "error: --val-seed = 4294967296 is too large (at most 4294967295)"},
           {{"--levels", "6"}, "--levels 6 must be at least m + 1 = 7"},
       }) {
    const Outcome r = with(c.extra);
    EXPECT_EQ(r.exit_code, 1) << r;
    EXPECT_TRUE(Contains(r.err, c.message)) << r;
    EXPECT_FALSE(fs::exists(work_ / "cfg.json")) << c.message;
  }
  // A run longer than the firmware's 32-bit sample counter: the options to shorten, each named once.
  const Outcome run_too_long = design({"--n", "2", "--m", "6", "--v-min", "-3", "--v-max", "4", "--operator", "switch",
                                       "--step-length", "2147483647", "--out", "cfg.json"});
  EXPECT_EQ(run_too_long.exit_code, 1) << run_too_long;
  EXPECT_TRUE(Contains(run_too_long.err, "shorten --step-length, --pulse-length or --val-length (firmware status"))
      << run_too_long;
  EXPECT_FALSE(fs::exists(work_ / "cfg.json"));
  const Outcome inverted = design({"--n", "2", "--m", "6", "--v-min", "5", "--v-max", "4", "--operator", "switch",
                                   "--out", "cfg.json"});
  EXPECT_EQ(inverted.exit_code, 1) << inverted;
  EXPECT_TRUE(Contains(inverted.err, "error: --v-max = 4 must be greater than --v-min = 5")) << inverted;
  EXPECT_FALSE(fs::exists(work_ / "cfg.json"));
  // n = 5 is beyond both the firmware image and the host estimator (n <= 4): nothing written.
  const Outcome fifth = design({"--n", "5", "--m", "6", "--v-min", "-3", "--v-max", "4", "--operator", "switch",
                                "--out", "cfg.json"});
  EXPECT_EQ(fifth.exit_code, 1) << fifth;
  EXPECT_TRUE(Contains(fifth.err, "--n 5 --m 6: need n in [1, 4] and m in [1, 10]; nothing written")) << fifth;
  EXPECT_FALSE(fs::exists(work_ / "cfg.json"));
  // Writing needs the design; --check excludes it.
  const Outcome no_interval = design({"--n", "2", "--m", "6", "--operator", "switch", "--out", "cfg.json"});
  EXPECT_GE(no_interval.exit_code, 100) << no_interval;
  EXPECT_TRUE(Contains(no_interval.err, "--v-min (or --check CONFIG) is required")) << no_interval;
  const Outcome both = design({"--check", config_with("n", 2), "--n", "2"});
  EXPECT_GE(both.exit_code, 100) << both;
  EXPECT_TRUE(Contains(both.err, "--check excludes --n")) << both;
}

// A length or seed beyond 64 bits is quoted as typed: CLI11 clamped 2^64 - 1 to int64's end, and the message quoted
// that stand-in (`--step-length = 9223372036854775807 is too large`). The value within 64 bits is still judged by
// the reader's rule, as above.
TEST_F(CliDesign, AValueBeyond64BitsIsQuotedAsTyped) {
  for (const auto& [option, message] : std::vector<std::pair<std::string, std::string>>{
           {"--step-length", "--step-length: 18446744073709551615 is too large (at most 2147483647)"},
           {"--pulse-length", "--pulse-length: 18446744073709551615 is too large (at most 268435456)"},
           {"--val-length", "--val-length: 18446744073709551615 is too large (at most 2147483647)"},
           {"--val-seed", "--val-seed: 18446744073709551615 is too large (at most 4294967295)"}}) {
    for (const std::string value : {"18446744073709551615", "-18446744073709551615"}) {
      const Outcome r = design({"--n", "2", "--m", "6", "--v-min", "-3", "--v-max", "4", "--operator", "switch",
                                option, value, "--out", "cfg.json"});
      EXPECT_GE(r.exit_code, 100) << r;
      EXPECT_TRUE(Contains(r.err, value[0] == '-' ? option + ": " + value + " must not be negative" : message)) << r;
      EXPECT_FALSE(Contains(r.err, "922337203685477580")) << r;  // int64's ends, which the user did not type
      EXPECT_FALSE(fs::exists(work_ / "cfg.json")) << option;
    }
  }
  // m and n are quoted as typed too (CLI11's own words), and in a config file by the reader.
  const Outcome m = design({"--n", "2", "--m", "18446744073709551615", "--v-min", "-3", "--v-max", "4", "--operator",
                            "switch", "--out", "cfg.json"});
  EXPECT_GE(m.exit_code, 100) << m;
  EXPECT_TRUE(Contains(m.err, "--m = 18446744073709551615")) << m;
  const Outcome check = design({"--check", config_with("m", 18446744073709551615ULL)});
  EXPECT_EQ(check.exit_code, 1) << check;
  EXPECT_TRUE(Contains(check.err, "'m' = 18446744073709551615 is outside")) << check;
  EXPECT_FALSE(Contains(check.err, "4294967296")) << check;
}

TEST_F(CliDesign, CheckNamesTheKeyAndRule) {
  const Outcome pulse = design({"--check", config_with("pulse_length_a", 35)});
  EXPECT_EQ(pulse.exit_code, 1) << pulse;
  EXPECT_TRUE(Contains(pulse.err, "in.json: 'pulse_length_a' = 35 is shorter than two pulse periods (2T = 36 for "
                                  "n = 2, m = 6)"));
  const Outcome typo = design({"--check", config_with("step_lenght", 10)});
  EXPECT_EQ(typo.exit_code, 1) << typo;
  EXPECT_TRUE(Contains(typo.err, "in.json: unknown key 'step_lenght'"));
  const Outcome fifth = design({"--check", config_with("n", 5)});
  EXPECT_EQ(fifth.exit_code, 1) << fifth;
  EXPECT_TRUE(Contains(fifth.err, "'n' = 5 is outside what the host estimator and the firmware image can take [1, 4]"));
}

TEST_F(CliDesign, CheckSaysWhichSideCannotRunADesign) {
  // n = 4: the image and the host estimator both run it (the host at the image's capacity).
  const Outcome fourth = design({"--check", config_with("n", 4)});
  EXPECT_EQ(fourth.exit_code, 0) << fourth;
  EXPECT_TRUE(Contains(fourth.out, "host estimator (n <= 4, m <= 10): fits"));
  EXPECT_TRUE(Contains(fourth.out, "firmware image (n <= 4, m <= 10, levels distinct in float32): fits"));

  // 1 + 1e-10 differs from 1 in double, not in float32: the host takes it, the firmware's V_d is not increasing.
  const Outcome close = design({"--check", config_with("V_d", {-3, -2, -1, 0, 1, 1.0000000001})});
  EXPECT_EQ(close.exit_code, 1) << close;
  EXPECT_TRUE(Contains(close.out, "host estimator (n <= 4, m <= 10): fits"));
  EXPECT_TRUE(Contains(close.err, "valid for the host, but the firmware image cannot run it: in float32 'V_d[5]' = 1 "
                                  "is not greater than 'V_d[4]' = 1"));

  // A firmware run executes both schemes.
  const Outcome dis_only = design({"--check", config_with("V_a", nullptr)});
  EXPECT_EQ(dis_only.exit_code, 1) << dis_only;
  EXPECT_TRUE(Contains(dis_only.err, "'V_a' is absent: a firmware run executes both schemes"));
}

TEST_F(CliDesign, SimulateWritesTheLengthsItSimulated) {
  // The paper's lengths: Section 3.5 L = N = 2000, Section 4.2 L = 2000, N = 8000; the recording must hold exactly
  // those (L + 1 samples per step phase).
  for (const auto& [scenario, pulses] : {std::pair{"dis_paper", 2000}, std::pair{"ais_paper", 8000}}) {
    const Outcome r = run({"simulate", "--scenario", scenario, "--out", "rec.csv", "--config-out", "cfg.json"});
    ASSERT_EQ(r.exit_code, 0) << r;
    const json c = read_json("cfg.json");
    EXPECT_EQ(c.at("step_length"), 2000) << scenario;
    EXPECT_EQ(c.at("pulse_length_d"), pulses) << scenario;
    EXPECT_EQ(c.at("pulse_length_a"), pulses) << scenario;
    EXPECT_FALSE(c.contains("val_seed")) << scenario;  // simulate's validation input comes from --seed
    std::map<std::string, int> rows;
    std::istringstream lines(slurp(work_ / "rec.csv"));
    for (std::string line; std::getline(lines, line);) {
      if (!line.starts_with('#') && !line.starts_with("phase")) ++rows[line.substr(0, line.find(','))];
    }
    EXPECT_EQ(rows["step_d"], 2001);
    EXPECT_EQ(rows["step_a"], 2001);
    EXPECT_EQ(rows["dis"], pulses);
    EXPECT_EQ(rows["ais"], pulses);
    EXPECT_EQ(rows["val"], c.at("val_length").get<int>());
    expect_host_and_firmware_accept("cfg.json");
  }
}

}  // namespace
