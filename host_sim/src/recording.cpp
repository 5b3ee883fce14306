#include "lashid/sim/recording.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <random>
#include <system_error>
#include <utility>

namespace lashid::sim {

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kHeader = "phase,t,v,y";
constexpr std::size_t kColumnCount = 4;
constexpr std::array<std::string_view, kPhaseCount> kPhaseNames = {"step_d", "dis", "step_a", "ais", "val"};
// Excel and some editors prepend a UTF-8 byte order mark; it is not part of the header.
constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";
// Long garbage fields are cut in messages so one bad line does not flood the terminal.
constexpr std::size_t kMaxQuotedChars = 40;

std::size_t index_of(Phase phase) { return static_cast<std::size_t>(phase); }

std::string quoted(std::string_view text) {
  if (text.size() <= kMaxQuotedChars) return fmt::format("'{}'", text);
  return fmt::format("'{}...'", text.substr(0, kMaxQuotedChars));
}

bool is_blank(std::string_view line) { return line.find_first_not_of(" \t") == std::string_view::npos; }

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(line.substr(start));
      return fields;
    }
    fields.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
}

std::string errno_message(int error_number) { return std::generic_category().message(error_number); }

// Parses the CSV text line by line; keeps the state needed to explain errors with line numbers.
class RecordingCsvParser {
 public:
  explicit RecordingCsvParser(std::string_view source_name) : source_name_(source_name) {}

  Recording parse(std::string_view text) {
    if (text.empty()) throw DataError(source_name_, "file is empty (expected header 'phase,t,v,y')");
    std::size_t line_number = 0;
    std::size_t header_line = 0;       // 0 = header not seen yet
    std::size_t first_blank_line = 0;  // 0 = no blank line seen yet
    std::string_view rest = text;
    while (!rest.empty()) {
      const std::size_t newline = rest.find('\n');
      std::string_view line = rest.substr(0, newline);
      rest = newline == std::string_view::npos ? std::string_view{} : rest.substr(newline + 1);
      ++line_number;
      if (line_number == 1 && line.starts_with(kUtf8Bom)) line.remove_prefix(kUtf8Bom.size());
      if (line.ends_with('\r')) line.remove_suffix(1);  // CRLF files from Windows tools

      if (line.starts_with('#')) continue;
      if (is_blank(line)) {
        if (first_blank_line == 0) first_blank_line = line_number;
        continue;
      }
      if (first_blank_line != 0) {
        fail(first_blank_line, "blank line before more data; blank lines are only allowed at the end of the file");
      }
      if (header_line == 0) {
        if (line != kHeader) fail(line_number, fmt::format("expected header '{}', got {}", kHeader, quoted(line)));
        header_line = line_number;
        continue;
      }
      parse_data_row(line, line_number);
    }
    if (header_line == 0) {
      throw DataError(source_name_, "no header 'phase,t,v,y' (file holds only comments or blank lines)");
    }
    if (recording_.size() == 0) fail(header_line, "header is not followed by any data rows");
    return std::move(recording_);
  }

 private:
  [[noreturn]] void fail(std::size_t line_number, std::string_view message) const {
    throw DataError(source_name_, line_number, message);
  }

  void parse_data_row(std::string_view line, std::size_t line_number) {
    const std::vector<std::string_view> fields = split_fields(line);
    if (fields.size() != kColumnCount) {
      fail(line_number,
           fmt::format("expected {} comma-separated fields (phase,t,v,y), got {}", kColumnCount, fields.size()));
    }
    const std::optional<Phase> phase = parse_phase(fields[0]);
    if (!phase) {
      fail(line_number, fmt::format("unknown phase {} (expected step_d, dis, step_a, ais or val)", quoted(fields[0])));
    }
    const std::size_t t = parse_time(fields[1], line_number);
    const double v = parse_value(fields[2], "v", line_number);
    const double y = parse_value(fields[3], "y", line_number);

    const bool continues_current_block = !recording_.order().empty() && recording_.order().back() == *phase;
    if (!continues_current_block && recording_.has(*phase)) {
      fail(line_number, fmt::format("phase '{}' appears again after its block ended at line {}; each phase must be "
                                    "one contiguous block",
                                    to_string(*phase), last_line_of_phase_[index_of(*phase)]));
    }
    const std::size_t expected_t = recording_.phase(*phase).size();
    if (t != expected_t) {
      fail(line_number, fmt::format("column t: expected {}, got {} (t counts samples of phase '{}' from 0 without "
                                    "gaps)",
                                    expected_t, t, to_string(*phase)));
    }
    recording_.append(*phase, v, y);
    last_line_of_phase_[index_of(*phase)] = line_number;
  }

  std::size_t parse_time(std::string_view field, std::size_t line_number) const {
    unsigned long long t = 0;
    const char* const end = field.data() + field.size();
    const auto [stop, error] = std::from_chars(field.data(), end, t);
    if (field.empty() || error != std::errc{} || stop != end) {
      fail(line_number, fmt::format("column t: {} is not a non-negative integer", quoted(field)));
    }
    return static_cast<std::size_t>(t);
  }

  double parse_value(std::string_view field, std::string_view column, std::size_t line_number) const {
    double value = 0.0;
    const char* const end = field.data() + field.size();
    const auto [stop, error] = std::from_chars(field.data(), end, value);
    if (field.empty() || error == std::errc::invalid_argument) {
      fail(line_number, fmt::format("column {}: {} is not a number", column, quoted(field)));
    }
    if (error == std::errc::result_out_of_range) {
      fail(line_number, fmt::format("column {}: {} is out of the range of a double", column, quoted(field)));
    }
    if (stop != end) {
      fail(line_number,
           fmt::format("column {}: trailing characters {} after the number in {}", column,
                       quoted(std::string_view(stop, static_cast<std::size_t>(end - stop))), quoted(field)));
    }
    // from_chars accepts "nan" and "inf"; the estimator cannot use them, so they are format errors.
    if (!std::isfinite(value)) {
      fail(line_number, fmt::format("column {}: non-finite value {} (v and y must be finite)", column, quoted(field)));
    }
    return value;
  }

  std::string_view source_name_;
  Recording recording_;
  std::array<std::size_t, kPhaseCount> last_line_of_phase_{};
};

// Removes the temporary file on every exit path until the rename has succeeded.
class TemporaryFileGuard {
 public:
  explicit TemporaryFileGuard(fs::path path) : path_(std::move(path)) {}
  TemporaryFileGuard(const TemporaryFileGuard&) = delete;
  TemporaryFileGuard& operator=(const TemporaryFileGuard&) = delete;
  ~TemporaryFileGuard() {
    if (!released_) {
      std::error_code ignored;
      fs::remove(path_, ignored);
    }
  }
  void release() { released_ = true; }

 private:
  fs::path path_;
  bool released_ = false;
};

fs::path temporary_sibling(const fs::path& target) {
  // A random suffix keeps concurrent writers of the same target from sharing a temporary file.
  std::random_device entropy;
  const std::uint64_t suffix = (std::uint64_t{entropy()} << 32U) | std::uint64_t{entropy()};
  return target.parent_path() / fmt::format(".{}.tmp-{:016x}", target.filename().string(), suffix);
}

}  // namespace

std::string_view to_string(Phase phase) { return kPhaseNames.at(index_of(phase)); }

std::optional<Phase> parse_phase(std::string_view name) {
  for (const Phase phase : kAllPhases) {
    if (to_string(phase) == name) return phase;
  }
  return std::nullopt;
}

void Recording::append(Phase phase, double v, double y) {
  if (order_.empty() || order_.back() != phase) {
    if (has(phase)) {
      throw std::invalid_argument(
          fmt::format("Recording::append: phase '{}' already has an earlier block", to_string(phase)));
    }
    order_.push_back(phase);
  }
  samples_by_phase_[index_of(phase)].push_back(Sample{v, y});
}

bool Recording::has(Phase phase) const { return !samples_by_phase_[index_of(phase)].empty(); }

std::span<const Sample> Recording::phase(Phase phase) const { return samples_by_phase_[index_of(phase)]; }

const std::vector<Phase>& Recording::order() const { return order_; }

std::size_t Recording::size() const {
  std::size_t total = 0;
  for (const auto& samples : samples_by_phase_) total += samples.size();
  return total;
}

DataError::DataError(std::string_view source, std::string_view message)
    : std::runtime_error(fmt::format("{}: {}", source, message)) {}

DataError::DataError(std::string_view source, std::size_t line, std::string_view message)
    : std::runtime_error(fmt::format("{}:{}: {}", source, line, message)), line_(line) {}

Recording parse_recording_csv(std::string_view text, std::string_view source_name) {
  return RecordingCsvParser(source_name).parse(text);
}

Recording read_recording_csv(const fs::path& path) { return parse_recording_csv(read_file_text(path), path.string()); }

std::string read_file_text(const fs::path& path) {
  const std::string name = path.string();
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (status.type() == fs::file_type::not_found) throw DataError(name, "file not found");
  if (error) throw DataError(name, fmt::format("cannot access file: {}", error.message()));
  if (fs::is_directory(status)) throw DataError(name, "is a directory, not a file");

  std::ifstream in(path, std::ios::binary);
  if (!in) throw DataError(name, fmt::format("cannot open for reading: {}", errno_message(errno)));
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw DataError(name, "read error");
  return text;
}

void write_recording_csv(const fs::path& path, const Recording& recording,
                         const std::vector<std::string>& comment_lines) {
  const std::string name = path.string();
  // Refuse what read_recording_csv would reject, so every file we write can be read back.
  if (recording.size() == 0) throw DataError(name, "refusing to write an empty recording");

  std::string content;
  auto out = std::back_inserter(content);
  for (const std::string& comment : comment_lines) {
    std::string_view rest = comment;
    for (;;) {  // each embedded line gets its own '#', otherwise it would be read as data
      const std::size_t newline = rest.find('\n');
      const std::string_view piece = rest.substr(0, newline);
      fmt::format_to(out, "{}\n", piece.empty() ? std::string("#") : fmt::format("# {}", piece));
      if (newline == std::string_view::npos) break;
      rest.remove_prefix(newline + 1);
    }
  }
  fmt::format_to(out, "{}\n", kHeader);
  for (const Phase phase : recording.order()) {
    const std::span<const Sample> samples = recording.phase(phase);
    for (std::size_t t = 0; t < samples.size(); ++t) {
      const Sample& sample = samples[t];
      if (!std::isfinite(sample.v) || !std::isfinite(sample.y)) {
        throw DataError(name, fmt::format("refusing to write non-finite sample v = {}, y = {} at phase '{}' t = {}",
                                          sample.v, sample.y, to_string(phase), t));
      }
      // "{}" is fmt's shortest representation that parses back to the same double.
      fmt::format_to(out, "{},{},{},{}\n", to_string(phase), t, sample.v, sample.y);
    }
  }
  write_file_atomically(path, content);
}

void check_can_write(const fs::path& path) {
  const std::string name = path.string();
  if (!path.has_filename()) throw DataError(name, "cannot write: the path names a directory, not a file");
  std::error_code ignored;
  if (fs::is_directory(path, ignored)) throw DataError(name, "cannot write: it is a directory, not a file");
  const fs::path directory = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code error;
  const fs::file_status directory_status = fs::status(directory, error);
  if (directory_status.type() == fs::file_type::not_found) {
    throw DataError(name, fmt::format("cannot write: directory '{}' does not exist", directory.string()));
  }
  if (!fs::is_directory(directory_status)) {
    throw DataError(name, fmt::format("cannot write: '{}' is not a directory", directory.string()));
  }
}

void write_file_atomically(const fs::path& path, std::string_view content) {
  check_can_write(path);
  const std::string name = path.string();
  std::error_code error;
  const fs::path temporary = temporary_sibling(path);
  TemporaryFileGuard guard(temporary);
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw DataError(name,
                      fmt::format("cannot create temporary file '{}': {}", temporary.string(), errno_message(errno)));
    }
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.close();  // flushes; a full disk shows up here
    if (!out) throw DataError(name, fmt::format("error while writing temporary file '{}'", temporary.string()));
  }
  fs::rename(temporary, path, error);
  if (error) throw DataError(name, fmt::format("cannot replace file: {}", error.message()));
  guard.release();
}

}  // namespace lashid::sim
