// The recording CSV format of docs/data-format.md: parser with line-numbered errors, and the writer.
#include "lashid/io/recording.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <stdexcept>
#include <utility>

#include "lashid/io/data_error.hpp"
#include "lashid/io/files.hpp"

namespace lashid::sim {

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kHeader = "phase,t,v,y";
constexpr std::size_t kColumnCount = 4;
// Excel and some editors prepend a UTF-8 byte order mark; it is not part of the header.
constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";
// Long garbage fields are cut in messages so one bad line does not flood the terminal.
constexpr std::size_t kMaxQuotedChars = 40;

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
                                    to_string(*phase), last_line_of_phase_[phase_index(*phase)]));
    }
    const std::size_t expected_t = recording_.phase(*phase).size();
    if (t != expected_t) {
      fail(line_number, fmt::format("column t: expected {}, got {} (t counts samples of phase '{}' from 0 without "
                                    "gaps)",
                                    expected_t, t, to_string(*phase)));
    }
    recording_.append(*phase, v, y);
    last_line_of_phase_[phase_index(*phase)] = line_number;
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

}  // namespace

Recording parse_recording_csv(std::string_view text, std::string_view source_name) {
  return RecordingCsvParser(source_name).parse(text);
}

Recording read_recording_csv(const fs::path& path) { return parse_recording_csv(read_file_text(path), path.string()); }

void write_recording_csv(const fs::path& path, const Recording& recording,
                         const std::vector<std::string>& comment_lines) {
  // Refuse what read_recording_csv would reject, so every file we write can be read back.
  if (recording.size() == 0) throw DataError(path.string(), "refusing to write an empty recording");
  RecordingCsvStream out(path, comment_lines);
  for (const Phase phase : recording.order()) {
    for (const Sample& sample : recording.phase(phase)) out.append(phase, sample.v, sample.y);
  }
  out.finish();
}

RecordingCsvStream::RecordingCsvStream(const fs::path& path, const std::vector<std::string>& comment_lines)
    : file_(path) {
  for (const std::string& line : comment_lines) comment(line);
  fmt::format_to(std::back_inserter(buffer_), "{}\n", kHeader);
}

void RecordingCsvStream::comment(std::string_view text) {
  auto out = std::back_inserter(buffer_);
  for (;;) {  // each embedded line gets its own '#', otherwise it would be read as data
    const std::size_t newline = text.find('\n');
    const std::string_view piece = text.substr(0, newline);
    if (piece.empty()) {
      fmt::format_to(out, "#\n");
    } else {
      fmt::format_to(out, "# {}\n", piece);
    }
    if (newline == std::string_view::npos) break;
    text.remove_prefix(newline + 1);
  }
}

void RecordingCsvStream::append(Phase phase, double v, double y) {
  const std::size_t index = phase_index(phase);
  if (current_ != phase) {
    if (closed_[index]) {
      throw std::invalid_argument(fmt::format("recording: phase '{}' appended again after its block ended",
                                              to_string(phase)));
    }
    if (current_) {
      closed_[phase_index(*current_)] = true;
      flush();  // a phase change: what was measured so far is in the file
    }
    current_ = phase;
  }
  const std::size_t t = count_[index];
  if (!std::isfinite(v) || !std::isfinite(y)) {
    throw DataError(file_.path().string(),
                    fmt::format("refusing to write non-finite sample v = {}, y = {} at phase '{}' t = {}", v, y,
                                to_string(phase), t));
  }
  // "{}" is fmt's shortest representation that parses back to the same double.
  fmt::format_to(std::back_inserter(buffer_), "{},{},{},{}\n", to_string(phase), t, v, y);
  ++count_[index];
  ++rows_;
  if (++rows_since_flush_ >= kFlushRows) flush();
}

void RecordingCsvStream::flush() {
  file_.write(buffer_);
  buffer_.clear();
  file_.flush();
  rows_since_flush_ = 0;
}

void RecordingCsvStream::finish() {
  if (rows_ == 0) {
    file_.discard();
    throw DataError(file_.path().string(), "refusing to write an empty recording");
  }
  file_.write(buffer_);
  buffer_.clear();
  file_.commit();
}

}  // namespace lashid::sim
