// Running the real `lashid` executable (LASHID_EXE, defined per test target in tests/CMakeLists.txt) from tests:
// the program runs through the shell with stdout and stderr captured, so argument parsing, exit codes, the files
// written and the error messages a user sees are all covered. Shared by test_cli and test_cli_operator_fit.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace lashid::test {

namespace fs = std::filesystem;

inline ::testing::AssertionResult Contains(std::string_view text, std::string_view part) {
  if (text.find(part) != std::string_view::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

inline std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Single quotes make the shell pass every byte through unchanged; a ' inside becomes '\''.
inline std::string shell_quote(std::string_view word) {
  std::string quoted = "'";
  for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

struct Outcome {
  int exit_code = -1;  // -1: killed by a signal (e.g. a sanitizer abort) or could not be started
  std::string out;
  std::string err;
};

inline std::ostream& operator<<(std::ostream& os, const Outcome& run) {
  return os << "exit code " << run.exit_code << "\n--- stdout ---\n" << run.out << "--- stderr ---\n" << run.err;
}

// Every file below the directory, relative to it, to show that a failing command created nothing.
inline std::set<std::string> files_below(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) names.insert(fs::relative(entry, dir).string());
  return names;
}

// Per-test directories: ctest runs the tests in parallel processes. The program runs in work_ (so relative
// paths in its arguments land there); its captured output goes beside work_.
class LashidExeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // One clear message instead of every check failing with the shell's "not found" (exit code 127).
    ASSERT_TRUE(fs::is_regular_file(LASHID_EXE)) << LASHID_EXE << " does not exist: build the lashid target";
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("lashid_test_") + info->test_suite_name() + "_" + info->name() +
                                        "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    work_ = dir_ / "work";
    fs::create_directories(work_);
  }
  // Kept after a failure, for a look at the files involved.
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }

  // `shell_before` runs in the shell first (e.g. "ulimit -v 1000 && ").
  Outcome run(const std::vector<std::string>& args, std::string_view shell_before = {}) const {
    // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) about "literal" + std::string&&.
    std::string command = "cd ";
    command.append(shell_quote(work_.string())).append(" && ").append(shell_before).append("exec ");
    command.append(shell_quote(LASHID_EXE));
    for (const auto& arg : args) command.append(" ").append(shell_quote(arg));
    command.append(" >").append(shell_quote((dir_ / "stdout.txt").string()));
    command.append(" 2>").append(shell_quote((dir_ / "stderr.txt").string())).append(" </dev/null");
    const int status = std::system(command.c_str());
    Outcome result;
    if (status != -1 && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
    result.out = slurp(dir_ / "stdout.txt");
    result.err = slurp(dir_ / "stderr.txt");
    return result;
  }

  fs::path dir_;
  fs::path work_;
};

}  // namespace lashid::test
