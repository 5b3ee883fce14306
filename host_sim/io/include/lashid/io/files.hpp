// Whole-file reads and atomic writes. Every error is a DataError naming the file.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "lashid/io/data_error.hpp"

namespace lashid::sim {

// Reads a whole file as bytes. Throws DataError naming `path` (not found, a directory, unreadable).
std::string read_file_text(const std::filesystem::path& path);

// Throws DataError when `path` cannot be written as a file: it names a directory or an existing non-regular file
// (a device, a pipe: the atomic rename would replace it), or its directory is missing.
// write_file_atomically() checks this first; a command writing several files checks them all before writing any.
void check_can_write(const std::filesystem::path& path);

// Writes `content` to a temporary file next to `path`, then renames it onto `path`, so readers
// never see a half-written file and a failure leaves `path` untouched and no temporary behind.
// Throws DataError naming `path`.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

// The same atomic replacement for a file written piece by piece while it is produced (a recording made during a
// run): the pieces go to the temporary sibling `.NAME.tmp-XXXXXXXXXXXXXXXX` as they are written and flushed, and
// commit() renames it onto `path`. Until then `path` keeps its previous content; without commit() (an exception,
// discard()) the temporary is removed. A process killed outright leaves the temporary with what was flushed.
// A `path` that is a symbolic link is written through: the file it points to is replaced, the link stays.
// Errors are DataError naming `path`.
class AtomicFileWriter {
 public:
  // Checks the target (check_can_write) and creates the temporary.
  explicit AtomicFileWriter(const std::filesystem::path& path);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  void write(std::string_view text);
  // Hands the buffered bytes to the operating system, so the temporary holds everything written so far.
  void flush();
  // Flushes, closes and renames the temporary onto the target. Nothing may be written after it.
  void commit();
  // Closes and removes the temporary; the target is untouched.
  void discard() noexcept;

  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& temporary() const { return temporary_; }

 private:
  // A write failed (e.g. a full disk): the temporary is removed, the target untouched.
  [[noreturn]] void fail_write();

  std::filesystem::path path_;
  std::filesystem::path target_;  // path_, or the file it links to
  std::filesystem::path temporary_;
  std::ofstream out_;
  bool open_ = false;
};

}  // namespace lashid::sim
