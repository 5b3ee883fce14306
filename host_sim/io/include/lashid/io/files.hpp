// Whole-file reads and atomic writes. Every error is a DataError naming the file.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "lashid/io/data_error.hpp"

namespace lashid::sim {

// Reads a whole file as bytes. Throws DataError naming `path` (not found, a directory, unreadable).
std::string read_file_text(const std::filesystem::path& path);

// Throws DataError when `path` cannot be written as a file: it names a directory, or its directory is missing.
// write_file_atomically() checks this first; a command writing several files checks them all before writing any.
void check_can_write(const std::filesystem::path& path);

// Writes `content` to a temporary file next to `path`, then renames it onto `path`, so readers
// never see a half-written file and a failure leaves `path` untouched and no temporary behind.
// Throws DataError naming `path`.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

}  // namespace lashid::sim
