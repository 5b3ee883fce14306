// The fixtures of the `lashid` executable's end-to-end tests (test_cli.cpp, test_cli_bad_input.cpp): a dis_paper
// recording and config made by the real program, and edits of its rows.
#pragma once

#include <functional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "json_text.hpp"

#include "cli_harness.hpp"

namespace lashid::test {

class Cli : public LashidExeTest {
 protected:
  // dis_paper recording and config with the truth, in work_.
  void simulate(int seed, const std::string& csv = "rec.csv", const std::string& config = "cfg.json") const {
    const Outcome r = run({"simulate", "--scenario", "dis_paper", "--seed", std::to_string(seed), "--out", csv,
                       "--config-out", config});
    ASSERT_EQ(r.exit_code, 0) << r;
  }

  nlohmann::json read_json(const std::string& name) const { return parse_json(slurp(work_ / name)); }
  void write_json(const std::string& name, const nlohmann::json& value) const {
    std::ofstream(work_ / name) << value.dump(2) << "\n";
  }

  // Copies the recording `from` to `to` with `edit` applied to the fields of the first row that starts
  // with `prefix`; returns that row's line number (1-based, as in the reader's messages).
  int edit_row(const std::string& from, const std::string& to, std::string_view prefix,
               const std::function<void(std::vector<std::string>&)>& edit) const {
    std::istringstream in(slurp(work_ / from));
    std::ofstream out(work_ / to, std::ios::binary);
    int edited_line = 0;
    int line_number = 0;
    for (std::string line; std::getline(in, line);) {
      ++line_number;
      if (edited_line == 0 && line.starts_with(prefix)) {
        edited_line = line_number;
        std::vector<std::string> fields;
        std::istringstream row(line);
        for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
        edit(fields);
        line.clear();
        for (std::size_t k = 0; k < fields.size(); ++k) line += (k == 0 ? "" : ",") + fields[k];
      }
      out << line << "\n";
    }
    EXPECT_NE(edited_line, 0) << "no row starting with " << prefix << " in " << from;
    return edited_line;
  }
};

// Bad input: a non-zero exit, and a message that names the file and the line or key (each test starts from a
// dis_paper recording, seed 3).
class CliBadInput : public Cli {
 protected:
  void SetUp() override {
    Cli::SetUp();
    ASSERT_NO_FATAL_FAILURE(simulate(3));
  }
  Outcome identify(const std::string& config, const std::string& data) const {
    return run({"identify", "--config", config, "--data", data});
  }
};

}  // namespace lashid::test
