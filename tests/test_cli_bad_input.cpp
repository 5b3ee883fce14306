// End-to-end tests of bad input to the `lashid` executable: a non-zero exit, a message that names the file and the
// line or key, and nothing written (the fixtures in cli_fixture.hpp).
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_fixture.hpp"
#include "cli_harness.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace lashid::test;


TEST_F(CliBadInput, RecordingRowErrorsNameFileAndLine) {
  struct Case {
    const char* what;
    std::function<void(std::vector<std::string>&)> edit;
    const char* message;
  };
  const std::vector<Case> cases{
      {"NaN in y", [](auto& f) { f[3] = "nan"; }, "non-finite value 'nan'"},
      {"non-numeric v", [](auto& f) { f[2] = "abc"; }, "column v: 'abc' is not a number"},
      {"three columns", [](auto& f) { f.pop_back(); }, "expected 4 comma-separated fields"},
      {"unknown phase", [](auto& f) { f[0] = "DIS"; }, "unknown phase 'DIS'"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const int line = edit_row("rec.csv", "bad.csv", "dis,5,", c.edit);
    const Outcome r = identify("cfg.json", "bad.csv");
    EXPECT_NE(r.exit_code, 0) << r;
    EXPECT_TRUE(Contains(r.err, std::string("bad.csv:") + std::to_string(line) + ":"));
    EXPECT_TRUE(Contains(r.err, c.message));
  }
}

TEST_F(CliBadInput, ConfigWithUnknownKey) {
  json config = read_json("cfg.json");
  config["v_mx"] = 4;
  write_json("bad.json", config);
  const Outcome r = identify("bad.json", "rec.csv");
  EXPECT_NE(r.exit_code, 0) << r;
  EXPECT_TRUE(Contains(r.err, "bad.json"));
  EXPECT_TRUE(Contains(r.err, "unknown key 'v_mx'"));
}

TEST_F(CliBadInput, ConfigLevelsThatDoNotMatchTheData) {
  // V_d = [-3, -2, -1, 1, 2, 3]: move the level 1 to 0.5, so the first dis sample at v = 1 is off-design.
  json config = read_json("cfg.json");
  ASSERT_EQ(config.at("V_d").at(3), 1.0);
  config["V_d"][3] = 0.5;
  write_json("bad.json", config);
  int first_off_design_t = -1;
  std::istringstream rows(slurp(work_ / "rec.csv"));
  for (std::string line; first_off_design_t < 0 && std::getline(rows, line);) {
    if (!line.starts_with("dis,")) continue;
    const auto t_end = line.find(',', 4);
    const auto v_end = line.find(',', t_end + 1);
    if (line.substr(t_end + 1, v_end - t_end - 1) == "1") first_off_design_t = std::stoi(line.substr(4, t_end - 4));
  }
  ASSERT_GE(first_off_design_t, 0) << "the dis phase never applies v = 1";

  const Outcome r = identify("bad.json", "rec.csv");
  EXPECT_NE(r.exit_code, 0) << r;
  EXPECT_TRUE(Contains(r.err, "rec.csv"));
  EXPECT_TRUE(Contains(r.err, std::string("phase 'dis' t = ") + std::to_string(first_off_design_t) + ":"));
  EXPECT_TRUE(Contains(r.err, "v = 1 "));
}

TEST_F(CliBadInput, MissingFiles) {
  const Outcome no_data = identify("cfg.json", "missing.csv");
  EXPECT_NE(no_data.exit_code, 0) << no_data;
  EXPECT_TRUE(Contains(no_data.err, "missing.csv"));
  const Outcome no_config = identify("missing.json", "rec.csv");
  EXPECT_NE(no_config.exit_code, 0) << no_config;
  EXPECT_TRUE(Contains(no_config.err, "missing.json"));
}

TEST_F(CliBadInput, JsonIntoMissingDirectoryFailsAndWritesNothing) {
  const auto before = files_below(work_);
  const Outcome r = run({"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "nodir/est.json"});
  EXPECT_NE(r.exit_code, 0) << r;
  EXPECT_TRUE(Contains(r.err, "nodir/est.json"));
  // The estimates may have been printed already; the JSON must not exist, not even in part, nor any
  // temporary file or the directory itself.
  EXPECT_EQ(files_below(work_), before);
  EXPECT_FALSE(fs::exists(work_ / "nodir"));
}

TEST_F(CliBadInput, JsonOntoADirectoryIsRefusedClearly) {
  fs::create_directories(work_ / "est.json");
  const Outcome r = run({"identify", "--config", "cfg.json", "--data", "rec.csv", "--json", "est.json"});
  EXPECT_NE(r.exit_code, 0) << r;
  EXPECT_TRUE(Contains(r.err, "est.json"));
  EXPECT_TRUE(Contains(r.err, "is a directory")) << r;
}

TEST_F(CliBadInput, DiagnoseNamesTheMissingPhaseAndWritesNothing) {
  // A simulated paper scenario without its val phase: cut the recording before the first val row.
  ASSERT_NO_FATAL_FAILURE(simulate(5, "rec.csv", "cfg.json"));
  const std::string text = slurp(work_ / "rec.csv");
  const auto cut = text.find("\nval,");
  ASSERT_NE(cut, std::string::npos);
  std::ofstream(work_ / "noval.csv") << text.substr(0, cut + 1);
  const auto before = files_below(work_);
  const Outcome r = run({"diagnose", "--config", (work_ / "cfg.json").string(), "--data",
                         (work_ / "noval.csv").string(), "--json", (work_ / "d.json").string()});
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_NE(r.err.find("noval.csv: diagnose needs all five phases; 'val' is missing"), std::string::npos) << r;
  EXPECT_EQ(files_below(work_), before);
  // A val phase whose y never changes (a stuck sensor) is named with the file, not as fit_percent's zero variance.
  std::string stuck;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.starts_with("val,")) line = line.substr(0, line.rfind(',')) + ",1.5";
    stuck += line + "\n";
  }
  std::ofstream(work_ / "stuck.csv") << stuck;
  const Outcome flat = run({"diagnose", "--config", (work_ / "cfg.json").string(), "--data",
                            (work_ / "stuck.csv").string()});
  EXPECT_EQ(flat.exit_code, 1) << flat;
  EXPECT_TRUE(Contains(flat.err, "stuck.csv: phase 'val' has the same y (1.5) in all its")) << flat;
  // A val input that never moves, and one val y too large for the sums: named, not a statistics function's message.
  std::string still, huge;
  {
    std::istringstream again(text);
    bool first_val = true;
    for (std::string line; std::getline(again, line);) {
      std::string s = line, h = line;
      if (line.starts_with("val,")) {
        const auto v_at = line.find(',', line.find(',') + 1) + 1;  // phase,t,v,y
        const auto y_at = line.rfind(',') + 1;
        s = line.substr(0, v_at) + "0.5" + line.substr(y_at - 1);
        if (first_val) h = line.substr(0, y_at) + "1e160";
        first_val = false;
      }
      still += s + "\n";
      huge += h + "\n";
    }
  }
  std::ofstream(work_ / "still.csv") << still;
  std::ofstream(work_ / "huge.csv") << huge;
  const Outcome moveless = run({"diagnose", "--config", (work_ / "cfg.json").string(), "--data",
                                (work_ / "still.csv").string()});
  EXPECT_EQ(moveless.exit_code, 1) << moveless;
  EXPECT_TRUE(Contains(moveless.err, "still.csv: phase 'val' holds v = 0.5 in all its")) << moveless;
  const Outcome big = run({"diagnose", "--config", (work_ / "cfg.json").string(), "--data",
                           (work_ / "huge.csv").string()});
  EXPECT_EQ(big.exit_code, 1) << big;
  EXPECT_TRUE(Contains(big.err, "huge.csv: phase val t = 0: y = 1e+160 is too large for the model's sums")) << big;
}

}  // namespace
