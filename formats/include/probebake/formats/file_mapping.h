// A read-only mapping of a whole file (POSIX mmap): what a streaming load (cell_file.h) and `probebake
// validate` read a .probes file through, so that the process's own memory never holds the world; the
// mapped pages are the kernel's, read in as they are touched and dropped under memory pressure.
//
// A file cut short in place by another process while it is mapped makes a read of a lost page raise
// SIGBUS; files that probebake writes are replaced by a rename, which leaves a mapping intact.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace probebake::formats {

class FileMapping {
public:
  FileMapping() = default;
  // Maps `size` bytes of `fd` (an empty mapping for 0). Throws Error(input, "<name>: cannot map: <reason>").
  FileMapping(int fd, std::uint64_t size, const std::string& name);
  // Opens, maps and closes `path` (a regular file). Throws Error(input, "<path>: <reason>").
  static FileMapping of(const std::filesystem::path& path);
  FileMapping(FileMapping&& other) noexcept;
  FileMapping& operator=(FileMapping&& other) noexcept;
  FileMapping(const FileMapping&) = delete;
  FileMapping& operator=(const FileMapping&) = delete;
  ~FileMapping() { reset(); }

  std::span<const std::uint8_t> bytes() const { return {static_cast<const std::uint8_t*>(data_), size_}; }
  void reset();

private:
  void* data_ = nullptr;
  std::size_t size_ = 0;
};

} // namespace probebake::formats
