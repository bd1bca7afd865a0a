// A read-only mapping of a whole file (POSIX mmap): what a streaming load (cell_file.h) and `probebake
// validate` read a .probes file through, so that the process's own memory never holds the world; the
// mapped pages are the kernel's, read in as they are touched and dropped under memory pressure.
//
// A file cut short in place by another process while it is mapped makes a read of a lost page raise
// SIGBUS; files that probebake writes are replaced by a rename, which leaves a mapping intact. A program
// (never a library inside someone else's process) turns that signal into an input error with
// MappedReadGuard.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include <signal.h>

namespace probebake::formats {

class FileMapping {
public:
  FileMapping() = default;
  // Maps `size` bytes of `fd` (an empty mapping for 0). Throws Error(input, "<name>: cannot map: <reason>").
  FileMapping(int fd, std::uint64_t size, const std::string& name);
  // Opens, maps and closes `path` (a regular file). Throws Error(input, "<path>: <reason>").
  static FileMapping of(const std::filesystem::path& path);
  // `size` bytes of zero pages, writable through writable() (cell_file.h reads a file's global part into
  // it). Untouched pages take no memory. Throws Error(input, "<name>: cannot map: <reason>").
  static FileMapping anonymous(std::uint64_t size, const std::string& name);
  FileMapping(FileMapping&& other) noexcept;
  FileMapping& operator=(FileMapping&& other) noexcept;
  FileMapping(const FileMapping&) = delete;
  FileMapping& operator=(const FileMapping&) = delete;
  ~FileMapping() { reset(); }

  std::span<const std::uint8_t> bytes() const { return {static_cast<const std::uint8_t*>(data_), size_}; }
  // The bytes of an anonymous mapping (a file's mapping is read-only: Error(internal)).
  std::span<std::uint8_t> writable();
  void reset();

private:
  void* data_ = nullptr;
  std::size_t size_ = 0;
  bool writable_ = false;
};

// While it lives, a SIGBUS (a mapped file cut short under the reader) ends the program with exit code 2 and
// "<program>: error: <path>: the file was cut short while it was read" on stderr, instead of a crash; the
// previous handler comes back when it is destroyed. One at a time.
class MappedReadGuard {
public:
  MappedReadGuard(const char* program, const std::string& path);
  ~MappedReadGuard();
  MappedReadGuard(const MappedReadGuard&) = delete;
  MappedReadGuard& operator=(const MappedReadGuard&) = delete;

private:
  struct sigaction previous_ {};
};

} // namespace probebake::formats
