// Measured force-displacement records (e.g. tests/data/friction_damper/): CSV files with a header row, read by
// column name. The operator input is the displacement column, the output the force column; time must increase.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace lashid::sim {

struct DamperRecord {
  std::string source;     ///< file name, as given (used in reports and errors)
  std::vector<double> t;  ///< time (s), strictly increasing
  std::vector<double> v;  ///< operator input: displacement
  std::vector<double> u;  ///< operator output: force
};

/// Largest magnitude accepted in the time, input and output columns: far beyond any time (s), displacement (in) or
/// force (kip) of a test rig, and small enough that everything computed from a record stays finite: spans
/// (max - min), bin indices of a table over that span, sums of squares, sampling intervals. Without it a file with
/// x_in near +1e308 and -1e308 has a span of inf, and a bin index computed from it is undefined behaviour.
inline constexpr double kDamperValueLimit = 1e12;

struct DamperColumns {
  std::string time = "t_s";
  std::string input = "x_in";
  std::string output = "F_kip";
};

/// Reads a record by column name. Throws DataError "FILE:LINE: message" for: an unreadable or empty file, a header
/// without one of the required columns (listing the columns found), a row whose field count differs from the
/// header's, a required field that is not a number, not finite or beyond kDamperValueLimit in magnitude (naming the
/// column), a time that does not strictly increase, and a file without data rows. Other columns are ignored (not
/// parsed). Blank lines and a trailing '\r' are tolerated.
DamperRecord read_damper_csv(const std::filesystem::path& path, const DamperColumns& columns = {});
/// Same from text in memory; `source_name` stands for the file name in errors.
DamperRecord parse_damper_csv(std::string_view text, std::string_view source_name, const DamperColumns& columns = {});

/// The value rules of the loader for a record made in memory (the fits call it on every record they get): v and u
/// of equal size, finite and within kDamperValueLimit in magnitude. Throws DataError "SOURCE: message" naming the
/// sample. (t is not checked: the fits do not use it.)
void check_damper_values(const DamperRecord& record);

/// Explicit resampling: block means of `factor` consecutive samples (t, v and u alike; a last incomplete block is
/// dropped). factor 1 returns the record unchanged. Throws std::invalid_argument for factor < 1 or a record
/// shorter than one block.
DamperRecord decimate(const DamperRecord& record, int factor);

}  // namespace lashid::sim
