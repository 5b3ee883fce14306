// End-to-end tests of the `lashid` executable (LASHID_EXE, set by tests/CMakeLists.txt): the real program
// is run through the shell with stdout and stderr captured, so argument parsing, exit codes, the files
// written and the error messages a user sees are all covered, not just the library behind them.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "json_text.hpp"

#include "cli_fixture.hpp"
#include "cli_harness.hpp"
#include "lashid/sim/hidden_effect.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace lashid::test;

// ||x - ref|| / ||ref||: element-wise relative differences are meaningless for entries near zero.
double relative_difference(const json& x, const json& ref) {
  double num = 0, den = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    const double d = x.at(k).get<double>() - ref.at(k).get<double>();
    num += d * d;
    den += ref.at(k).get<double>() * ref.at(k).get<double>();
  }
  return std::sqrt(num / den);
}

// --- arguments --------------------------------------------------------------------------------------------

TEST_F(Cli, HelpListsSubcommandsAndTheirOptions) {
  const Outcome top = run({"--help"});
  ASSERT_EQ(top.exit_code, 0) << top;
  for (const char* word : {"scenarios", "simulate", "identify", "reproduce"}) EXPECT_TRUE(Contains(top.out, word));

  const std::vector<std::pair<std::string, std::vector<std::string>>> options{
      {"scenarios", {}},
      {"simulate", {"--scenario", "--seed", "--input-lag", "--noise-variance", "--out", "--config-out"}},
      {"identify", {"--config", "--data", "--json", "--scheme", "--float"}},
      {"reproduce", {"--runs", "--seed", "--json"}}};
  for (const auto& [subcommand, names] : options) {
    const Outcome r = run({subcommand, "--help"});
    ASSERT_EQ(r.exit_code, 0) << r;
    EXPECT_TRUE(Contains(r.out, "Usage:")) << subcommand;
    for (const auto& name : names) EXPECT_TRUE(Contains(r.out, name)) << subcommand;
  }
}

// The version is the project's (CMakeLists.txt's project(VERSION)), as the package and the .deb name it.
TEST_F(Cli, VersionIsTheProjects) {
  const Outcome r = run({"--version"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_EQ(r.out, std::string("lashid ") + LASHID_PROJECT_VERSION + "\n");
}

TEST_F(Cli, NoSubcommandOrUnknownOptionFails) {
  const Outcome none = run({});
  EXPECT_NE(none.exit_code, 0) << none;
  EXPECT_TRUE(Contains(none.err, "subcommand"));

  const Outcome unknown = run({"simulate", "--scenario", "dis_paper", "--out", "rec.csv", "--bogus"});
  EXPECT_NE(unknown.exit_code, 0) << unknown;
  EXPECT_TRUE(Contains(unknown.err, "--bogus"));
  EXPECT_TRUE(files_below(work_).empty()) << "nothing is simulated when the arguments are wrong";
}

TEST_F(Cli, NegativeSeedIsRejectedInsteadOfWrappingAround) {
  for (const char* subcommand : {"simulate", "reproduce", "hil"}) {
    const std::string name = subcommand;
    const Outcome r = name == "simulate"  ? run({"simulate", "--scenario", "dis_paper", "--seed", "-1", "--out", "rec.csv"})
                      : name == "reproduce" ? run({"reproduce", "--seed", "-1", "--runs", "10"})
                                            : run({"hil", "--attach", "a.sock", "b.sock", "--scenario", "dis_paper",
                                                   "--seed", "-1"});
    EXPECT_NE(r.exit_code, 0) << subcommand << ": " << r;
    EXPECT_TRUE(Contains(r.err, "--seed")) << subcommand;
  }
  EXPECT_TRUE(files_below(work_).empty());
}

// --- scenarios and simulate -------------------------------------------------------------------------------

TEST_F(Cli, ScenariosListsThePaperExamples) {
  const Outcome r = run({"scenarios"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(Contains(r.out, "dis_paper"));
  EXPECT_TRUE(Contains(r.out, "ais_paper"));
}

TEST_F(Cli, UnknownScenarioFailsAndListsTheKnownOnes) {
  const Outcome r = run({"simulate", "--scenario", "nope", "--out", "rec.csv", "--config-out", "cfg.json"});
  EXPECT_NE(r.exit_code, 0) << r;
  EXPECT_TRUE(Contains(r.err, "'nope'"));
  EXPECT_TRUE(Contains(r.err, "dis_paper"));
  EXPECT_TRUE(Contains(r.err, "ais_paper"));
  EXPECT_TRUE(files_below(work_).empty());
}

TEST_F(Cli, SimulationIsDeterministicPerSeed) {
  ASSERT_NO_FATAL_FAILURE(simulate(3, "a.csv", "a.json"));
  ASSERT_NO_FATAL_FAILURE(simulate(3, "b.csv", "b.json"));
  ASSERT_NO_FATAL_FAILURE(simulate(4, "c.csv", "c.json"));
  const std::string a = slurp(work_ / "a.csv");
  EXPECT_GT(a.size(), 10000u);
  EXPECT_EQ(a, slurp(work_ / "b.csv")) << "same seed, different recording";
  EXPECT_NE(a, slurp(work_ / "c.csv")) << "different seed, same recording";
  EXPECT_EQ(slurp(work_ / "a.json"), slurp(work_ / "c.json")) << "the config does not depend on the seed";
}

// --- identify ---------------------------------------------------------------------------------------------

TEST_F(Cli, IdentifyRecoversTheSimulatedSystem) {
  ASSERT_NO_FATAL_FAILURE(simulate(3));
  const Outcome r = run({"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "est.json"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(r.err.empty()) << r;

  // Both schemes' tables, with the truth from the config beside the estimates.
  EXPECT_TRUE(Contains(r.out, "DIS"));
  EXPECT_TRUE(Contains(r.out, "AIS"));
  EXPECT_TRUE(Contains(r.out, "truth"));
  EXPECT_TRUE(Contains(r.out, "0.21")) << "true a2 of dis_paper";

  const json est = read_json("est.json");
  for (const char* scheme : {"dis", "ais"}) {
    ASSERT_TRUE(est.contains(scheme) && est[scheme].is_object()) << est.dump(2);
    const std::vector<std::pair<const char*, std::size_t>> shapes{{"a", 2}, {"b", 2}, {"F", 6}, {"theta", 14}};
    for (const auto& [key, size] : shapes) {
      const json& values = est[scheme][key];
      ASSERT_TRUE(values.is_array()) << scheme << "." << key;
      EXPECT_EQ(values.size(), size) << scheme << "." << key;
      for (const json& v : values) EXPECT_TRUE(v.is_number()) << scheme << "." << key;
    }
  }
  const json truth_a = read_json("cfg.json").at("truth").at("a");
  ASSERT_EQ(truth_a, json({1.0, 0.21}));
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(est["dis"]["a"][i].get<double>(), truth_a[i].get<double>(), 0.05) << "a" << i + 1;
  }
}

TEST_F(Cli, FloatEstimatesMatchDouble) {
  ASSERT_NO_FATAL_FAILURE(simulate(3));
  const Outcome d = run({"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "double.json"});
  ASSERT_EQ(d.exit_code, 0) << d;
  const Outcome f = run({"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "float.json", "--float"});
  ASSERT_EQ(f.exit_code, 0) << f;
  const json in_double = read_json("double.json");
  const json in_float = read_json("float.json");
  for (const char* scheme : {"dis", "ais"}) {
    for (const char* key : {"a", "b", "F", "theta"}) {
      EXPECT_LT(relative_difference(in_float[scheme][key], in_double[scheme][key]), 1e-4) << scheme << "." << key;
    }
  }
}

// Noise-free data still leave a residual: the recording does not fit the model exactly (the double run's residual
// variance is about 4e-5 on dis_paper), and float32 adds its rounding. The float32 estimator's sum of squares
// cancelled to 0 (clamped) and its standard errors with it; the host computes it from the residuals
// (docs/data-format.md). Each must be within a factor 2 of the double run's.
TEST_F(Cli, FloatResidualVarianceOfNoiseFreeDataIsNotZero) {
  const Outcome sim = run({"simulate", "--scenario", "dis_paper", "--noise-variance", "0", "--seed", "1", "--out",
                           "rec.csv", "--config-out", "cfg.json"});
  ASSERT_EQ(sim.exit_code, 0) << sim;
  const Outcome d = run({"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "double.json"});
  ASSERT_EQ(d.exit_code, 0) << d;
  const Outcome f = run({"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "float.json", "--float"});
  ASSERT_EQ(f.exit_code, 0) << f;
  EXPECT_FALSE(Contains(f.out, "residual variance 0,")) << f;
  const json in_double = read_json("double.json");
  const json in_float = read_json("float.json");
  for (const char* scheme : {"dis", "ais"}) {
    const double v_double = in_double[scheme]["noise_variance"].get<double>();
    const double v_float = in_float[scheme]["noise_variance"].get<double>();
    EXPECT_GT(v_double, 0.0) << scheme;
    EXPECT_GT(v_float, 0.5 * v_double) << scheme;
    EXPECT_LT(v_float, 2.0 * v_double) << scheme;
    for (std::size_t k = 0; k < in_float[scheme]["theta_std_error"].size(); ++k) {
      const double se_double = in_double[scheme]["theta_std_error"][k].get<double>();
      const double se_float = in_float[scheme]["theta_std_error"][k].get<double>();
      EXPECT_GT(se_float, 0.5 * se_double) << scheme << " se " << k;
      EXPECT_LT(se_float, 2.0 * se_double) << scheme << " se " << k;
    }
  }
}

TEST_F(Cli, SimulateWritesNeitherFileWhenOneCannotBeWritten) {
  // The recording's directory does not exist: the config must not be left behind alone.
  const Outcome r = run({"simulate", "--scenario", "dis_paper", "--out", "nodir/rec.csv", "--config-out", "cfg.json"});
  EXPECT_NE(r.exit_code, 0) << r;
  EXPECT_TRUE(Contains(r.err, "nodir/rec.csv"));
  EXPECT_TRUE(files_below(work_).empty()) << r;
}

}  // namespace

// --- diagnose -----------------------------------------------------------------------------------------------

// A generated recording with a hidden dead time: the JSON carries the keys, and the hidden delay.
TEST_F(Cli, DiagnoseFindsAHiddenDeadTimeAndWritesTheJson) {
  const std::string csv = (work_ / "dt.csv").string(), cfg = (work_ / "dt.json").string();
  const std::string out = (work_ / "diag.json").string();
  const Outcome gen = run({"hidden-effect", "--cause", "dead_time", "--seed", "11", "--out", csv, "--config-out", cfg});
  ASSERT_EQ(gen.exit_code, 0) << gen;
  EXPECT_EQ(slurp(cfg).find("delay"), std::string::npos) << "the effect must not leak into the config";
  {
    // The config says what the recording holds (its lengths), as simulate's does: counted here from the CSV.
    const json config = parse_json(slurp(cfg));
    std::map<std::string, int> rows;
    std::istringstream lines(slurp(csv));
    for (std::string line; std::getline(lines, line);) {
      if (!line.empty() && line[0] != '#' && line.find(',') != std::string::npos) ++rows[line.substr(0, line.find(','))];
    }
    ASSERT_EQ(rows["step_d"], rows["step_a"]);
    EXPECT_EQ(config.at("step_length").get<int>(), rows["step_d"] - 1);
    EXPECT_EQ(config.at("pulse_length_d").get<int>(), rows["dis"]);
    EXPECT_EQ(config.at("pulse_length_a").get<int>(), rows["ais"]);
    EXPECT_EQ(config.at("val_length").get<int>(), rows["val"]);
    EXPECT_GT(rows["val"], 0);
  }
  const Outcome r = run({"diagnose", "--config", cfg, "--data", csv, "--json", out});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_NE(r.out.find("cause: dead_time"), std::string::npos) << r;
  const json j = parse_json(slurp(out));
  EXPECT_EQ(j.at("cause"), "dead_time");
  // The delay the generator hid (the same case, drawn in-process from the same cause and seed).
  EXPECT_EQ(j.at("parameters").at("delay").get<int>(),
            lashid::sim::generate_hidden_effect_case(lashid::sim::Cause::kDeadTime, 11).effect.delay);
  for (const char* key : {"parameters", "fit_nominal", "fit_extended", "evidence", "models", "findings"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_GT(j.at("fit_extended").get<double>(), j.at("fit_nominal").get<double>());
  EXPECT_TRUE(j.at("models").contains("nominal") && j.at("models").contains("extended"));
}

namespace {

// Issue 14, "no lost data": no command writes over one of its own files, whatever the path looks like.
TEST_F(Cli, NoCommandWritesOverItsOwnInputOrAnotherOutput) {
  ASSERT_EQ(run({"simulate", "--scenario", "dis_paper", "--out", "rec.csv", "--config-out", "cfg.json"}).exit_code, 0);
  const std::string recording = slurp(work_ / "rec.csv");
  const std::string config = slurp(work_ / "cfg.json");
  fs::create_directories(work_ / "sub");
  fs::create_symlink(work_ / "rec.csv", work_ / "link.csv");
  fs::create_hard_link(work_ / "cfg.json", work_ / "hard.json");
  struct Case {
    std::vector<std::string> args;
    std::string output, other;  // the two options the message must name
  };
  const std::vector<Case> cases = {
      {{"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "rec.csv"}, "--json", "--data"},
      {{"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "sub/../rec.csv"}, "--json", "--data"},
      {{"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "link.csv"}, "--json", "--data"},
      {{"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "hard.json"}, "--json", "--config"},
      {{"diagnose", "--config", "cfg.json", "--data", "rec.csv", "--plot", "./cfg.json"}, "--plot", "--config"},
      {{"simulate", "--scenario", "ais_paper", "--out", "new.csv", "--config-out", "new.csv"}, "--out",
       "--config-out"},
      // Two names of one file that does not exist yet (a relative name stayed relative, the other became absolute:
      // both were written, the second over the first).
      {{"simulate", "--scenario", "ais_paper", "--out", "new.csv", "--config-out", "./new.csv"}, "--out",
       "--config-out"},
      {{"diagnose", "--config", "cfg.json", "--data", "rec.csv", "--json", "d.json", "--plot", "sub/../d.json"},
       "--json", "--plot"},
  };
  for (const Case& c : cases) {
    const Outcome r = run(c.args);
    EXPECT_EQ(r.exit_code, 1) << r;
    EXPECT_TRUE(Contains(r.err, "refusing to write over it")) << r;
    EXPECT_TRUE(Contains(r.err, c.output + " ")) << r;
    EXPECT_TRUE(Contains(r.err, c.other + " ")) << r;
  }
  // The inputs are untouched, and the refused simulate wrote nothing.
  EXPECT_EQ(slurp(work_ / "rec.csv"), recording);
  EXPECT_EQ(slurp(work_ / "cfg.json"), config);
  EXPECT_FALSE(fs::exists(work_ / "new.csv"));
  // A different file is fine.
  EXPECT_EQ(run({"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "est.json"}).exit_code, 0);
}

TEST_F(Cli, AFailedRecordingPutsBackTheConfigThatWasThere) {
  // Found by hand (issue 14): simulate wrote --config-out, then the recording failed, and the config that had been
  // there was deleted. A file name whose temporary sibling is too long for the file system makes the second write
  // fail after the first succeeded.
  std::ofstream(work_ / "keep.json") << "{\"mine\": true}\n";
  const std::string long_name = std::string(240, 'r') + ".csv";
  const Outcome r = run({"simulate", "--scenario", "dis_paper", "--out", long_name, "--config-out", "keep.json"});
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(Contains(r.err, "cannot create temporary file")) << r;
  EXPECT_EQ(slurp(work_ / "keep.json"), "{\"mine\": true}\n");
  EXPECT_FALSE(fs::exists(work_ / long_name));
}

}  // namespace
