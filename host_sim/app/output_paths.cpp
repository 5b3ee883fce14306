#include "output_paths.hpp"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

namespace lashid::app {
namespace {

struct NamedPath {
  std::string option;
  std::string path;
};

bool is_output(std::string_view option) {
  for (const char* name : kOutputOptions) {
    if (option == name) return true;
  }
  return false;
}

bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code ec;
  if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec)) {
    const bool same = std::filesystem::equivalent(a, b, ec);
    if (!ec) return same;
  }
  // Absolute first: weakly_canonical leaves a relative path whose file does not exist yet relative ("s2.csv"), while
  // "./s2.csv" became absolute, and the two names of one new file compared unequal (one output lost the other).
  const auto canonical = [&ec](const std::filesystem::path& p) {
    const std::filesystem::path absolute = std::filesystem::absolute(p, ec);
    return ec ? std::filesystem::path{} : std::filesystem::weakly_canonical(absolute, ec).lexically_normal();
  };
  const std::filesystem::path ca = canonical(a);
  if (ec) return false;
  const std::filesystem::path cb = canonical(b);
  return !ec && ca == cb;
}

}  // namespace

void refuse_overwriting_own_files(const CLI::App& command) {
  std::vector<NamedPath> given;
  for (const CLI::Option* option : command.get_options()) {
    if (option->count() == 0 || option->get_expected_min() == 0) continue;  // absent, or a flag
    for (const std::string& value : option->results()) {
      if (!value.empty()) given.push_back({option->get_name(), value});
    }
  }
  for (std::size_t i = 0; i < given.size(); ++i) {
    if (!is_output(given[i].option)) continue;
    for (std::size_t j = 0; j < given.size(); ++j) {
      if (j == i || !same_file(given[i].path, given[j].path)) continue;
      throw std::invalid_argument(fmt::format(
          "{} {} names the same file as {} {}: refusing to write over it (give the output another name)",
          given[i].option, given[i].path, given[j].option, given[j].path));
    }
  }
}

}  // namespace lashid::app
