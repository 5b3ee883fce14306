#include "lashid/io/damper_data.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>

#include <fmt/format.h>

#include "lashid/io/files.hpp"
#include "lashid/io/recording.hpp"

namespace lashid::sim {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_trimmed_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

// What a value of each column must be, for the error when it is beyond kDamperValueLimit.
constexpr std::array<std::string_view, 3> kWhat{"a time in seconds", "a displacement in inches", "a force in kip"};

std::string beyond_limit(std::string_view column, double value, std::string_view what) {
  return fmt::format("column '{}': {:g} is beyond {:g} in magnitude (the limit that keeps its span, max - min, and "
                     "everything computed from it within the double range): not {}",
                     column, value, kDamperValueLimit, what);
}

}  // namespace

DamperRecord parse_damper_csv(std::string_view text, std::string_view source_name, const DamperColumns& columns) {
  DamperRecord record;
  record.source = std::string(source_name);
  const std::array<const std::string*, 3> wanted{&columns.time, &columns.input, &columns.output};
  std::array<std::size_t, 3> index{};
  std::size_t field_count = 0;
  bool have_header = false;
  std::size_t line_number = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t end = text.find('\n', pos);
    const std::string_view raw = text.substr(pos, end == std::string_view::npos ? std::string_view::npos : end - pos);
    pos = end == std::string_view::npos ? text.size() : end + 1;
    ++line_number;
    const std::string_view line = trim(raw);
    if (line.empty()) continue;
    const std::vector<std::string_view> fields = split_trimmed_fields(line);
    if (!have_header) {
      have_header = true;
      field_count = fields.size();
      std::string found;
      for (const auto f : fields) found += (found.empty() ? "'" : ", '") + std::string(f) + "'";
      for (std::size_t k = 0; k < wanted.size(); ++k) {
        std::optional<std::size_t> at;
        for (std::size_t i = 0; i < fields.size(); ++i) {
          if (fields[i] != *wanted[k]) continue;
          // Two columns of one name: which one holds the data is not known; neither is guessed.
          if (at) {
            throw DataError(source_name, line_number,
                            fmt::format("column '{}' appears twice in the header (fields {} and {})", *wanted[k],
                                        *at + 1, i + 1));
          }
          at = i;
        }
        if (!at) {
          throw DataError(source_name, line_number,
                          fmt::format("no column '{}' in the header (columns: {})", *wanted[k], found));
        }
        index[k] = *at;
      }
      continue;
    }
    if (fields.size() != field_count) {
      throw DataError(source_name, line_number,
                      fmt::format("{} fields, but the header has {}", fields.size(), field_count));
    }
    std::array<double, 3> value{};
    for (std::size_t k = 0; k < wanted.size(); ++k) {
      const std::string_view field = fields[index[k]];
      const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), value[k]);
      if (field.empty() || ec != std::errc() || ptr != field.data() + field.size()) {
        throw DataError(source_name, line_number,
                        fmt::format("column '{}': '{}' is not a number", *wanted[k], field));
      }
      if (!std::isfinite(value[k])) {
        throw DataError(source_name, line_number, fmt::format("column '{}': '{}' is not finite", *wanted[k], field));
      }
      if (!(std::fabs(value[k]) <= kDamperValueLimit)) {
        throw DataError(source_name, line_number, beyond_limit(*wanted[k], value[k], kWhat[k]));
      }
    }
    if (!record.t.empty() && !(value[0] > record.t.back())) {
      throw DataError(source_name, line_number,
                      fmt::format("column '{}': {} does not increase (previous row: {})", columns.time, value[0],
                                  record.t.back()));
    }
    record.t.push_back(value[0]);
    record.v.push_back(value[1]);
    record.u.push_back(value[2]);
  }
  if (!have_header) throw DataError(source_name, "empty file: no header row");
  if (record.t.empty()) throw DataError(source_name, "no data rows after the header");
  return record;
}

void check_damper_values(const DamperRecord& record) {
  if (record.v.size() != record.u.size()) {
    throw DataError(record.source, fmt::format("v and u must have the same size (got {} and {})", record.v.size(),
                                               record.u.size()));
  }
  const std::array<const std::vector<double>*, 2> columns{&record.v, &record.u};
  for (std::size_t k = 0; k < columns.size(); ++k) {
    for (std::size_t i = 0; i < columns[k]->size(); ++i) {
      const double x = (*columns[k])[i];
      if (!(std::fabs(x) <= kDamperValueLimit)) {  // also NaN
        throw DataError(record.source,
                        fmt::format("sample {}: {}", i, beyond_limit(k == 0 ? "v" : "u", x, kWhat[k + 1])));
      }
    }
  }
}

DamperRecord read_damper_csv(const std::filesystem::path& path, const DamperColumns& columns) {
  return parse_damper_csv(read_file_text(path), path.string(), columns);
}

DamperRecord decimate(const DamperRecord& record, int factor) {
  if (factor < 1) throw std::invalid_argument(fmt::format("decimation factor must be >= 1, got {}", factor));
  if (factor == 1) return record;
  const auto k = static_cast<std::size_t>(factor);
  if (record.t.size() < k) {
    throw std::invalid_argument(fmt::format("{}: {} samples, fewer than one block of {}", record.source,
                                            record.t.size(), factor));
  }
  DamperRecord out;
  out.source = record.source;
  const auto mean = [k](const std::vector<double>& x, std::size_t start) {
    double sum = 0;
    for (std::size_t i = start; i < start + k; ++i) sum += x[i];
    return sum / static_cast<double>(k);
  };
  for (std::size_t start = 0; start + k <= record.t.size(); start += k) {
    out.t.push_back(mean(record.t, start));
    out.v.push_back(mean(record.v, start));
    out.u.push_back(mean(record.u, start));
  }
  return out;
}

}  // namespace lashid::sim
