// Files: whole-file reads and atomic writes, with errors that name the file (DataError).
#include "lashid/io/files.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <random>
#include <system_error>
#include <utility>

#include "lashid/io/data_error.hpp"

namespace lashid::sim {

namespace {

namespace fs = std::filesystem;

std::string errno_message(int error_number) { return std::generic_category().message(error_number); }

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
