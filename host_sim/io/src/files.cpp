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
  // The content is renamed onto the target: a device or pipe (`--out /dev/null`) would be replaced by a plain file.
  if (fs::exists(path, ignored) && !fs::is_regular_file(path, ignored)) {
    throw DataError(name, "cannot write: it exists and is not a regular file (a device or a pipe would be replaced)");
  }
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
  AtomicFileWriter file(path);
  file.write(content);
  file.commit();
}

AtomicFileWriter::AtomicFileWriter(const fs::path& path) : path_(path) {
  check_can_write(path);
  // A symbolic link is written through: its target is replaced, the link stays a link (renaming onto the link
  // itself would turn it into a plain file and leave the file it pointed to unchanged).
  std::error_code ignored;
  target_ = fs::is_symlink(path, ignored) ? fs::weakly_canonical(path, ignored) : path;
  if (target_.empty()) target_ = path;
  temporary_ = temporary_sibling(target_);
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    throw DataError(path.string(),
                    fmt::format("cannot create temporary file '{}': {}", temporary_.string(), errno_message(errno)));
  }
  open_ = true;
}

AtomicFileWriter::~AtomicFileWriter() { discard(); }

void AtomicFileWriter::write(std::string_view text) {
  if (!open_) throw DataError(path_.string(), "write after the file was committed or discarded");
  out_.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out_) fail_write();
}

void AtomicFileWriter::flush() {
  if (!open_) return;
  out_.flush();
  if (!out_) fail_write();
}

void AtomicFileWriter::commit() {
  const std::string name = path_.string();
  if (!open_) throw DataError(name, "commit after the file was committed or discarded");
  out_.close();  // flushes; a full disk shows up here
  if (!out_) fail_write();
  std::error_code error;
  fs::rename(temporary_, target_, error);
  if (error) {
    discard();
    throw DataError(name, fmt::format("cannot replace file: {}", error.message()));
  }
  open_ = false;
}

void AtomicFileWriter::fail_write() {
  const std::string temporary = temporary_.string();
  discard();
  throw DataError(path_.string(), fmt::format("error while writing temporary file '{}'", temporary));
}

void AtomicFileWriter::discard() noexcept {
  if (!open_) return;
  open_ = false;
  out_.close();
  std::error_code ignored;
  fs::remove(temporary_, ignored);
}

}  // namespace lashid::sim
