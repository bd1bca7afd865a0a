#include "probebake/formats/file_mapping.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>
#include <utility>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "probebake/formats/error.h"

namespace probebake::formats {
namespace {

// The guard's message, written by the handler with write(2): nothing else is async-signal-safe.
char g_sigbus_message[4096];
std::size_t g_sigbus_length = 0;

void exit_on_sigbus(int) {
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, g_sigbus_message, g_sigbus_length);
  ::_exit(2);
}

} // namespace

MappedReadGuard::MappedReadGuard(const char* program, const std::string& path) {
  const std::string message =
      std::string(program) + ": error: " + path + ": the file was cut short while it was read\n";
  g_sigbus_length = std::min(message.size(), sizeof(g_sigbus_message));
  std::memcpy(g_sigbus_message, message.data(), g_sigbus_length);
  struct sigaction action {};
  action.sa_handler = exit_on_sigbus;
  sigemptyset(&action.sa_mask);
  ::sigaction(SIGBUS, &action, &previous_);
}

MappedReadGuard::~MappedReadGuard() { ::sigaction(SIGBUS, &previous_, nullptr); }

FileMapping::FileMapping(int fd, std::uint64_t size, const std::string& name) {
  if (size == 0) return;
  if (size > std::numeric_limits<std::size_t>::max())
    throw_input_error(name, "cannot map: larger than the address space");
  void* data = ::mmap(nullptr, std::size_t(size), PROT_READ, MAP_PRIVATE, fd, 0);
  if (data == MAP_FAILED) throw_input_error(name, std::string("cannot map: ") + std::strerror(errno));
  data_ = data, size_ = std::size_t(size);
}

FileMapping FileMapping::anonymous(std::uint64_t size, const std::string& name) {
  FileMapping mapping;
  if (size == 0) return mapping;
  if (size > std::numeric_limits<std::size_t>::max())
    throw_input_error(name, "cannot map: larger than the address space");
  void* data =
      ::mmap(nullptr, std::size_t(size), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (data == MAP_FAILED) throw_input_error(name, std::string("cannot map: ") + std::strerror(errno));
  mapping.data_ = data, mapping.size_ = std::size_t(size), mapping.writable_ = true;
  return mapping;
}

std::span<std::uint8_t> FileMapping::writable() {
  if (!writable_ && size_ != 0)
    throw Error(ErrorKind::internal, "FileMapping::writable: a file's mapping is read-only");
  return {static_cast<std::uint8_t*>(data_), size_};
}

FileMapping FileMapping::of(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw_input_error(path.string(), std::string("cannot open: ") + std::strerror(errno));
  struct stat info {};
  const int stat_error = ::fstat(fd, &info) == 0 ? 0 : errno;
  FileMapping mapping;
  try {
    if (stat_error != 0) throw_input_error(path.string(), std::string("cannot stat: ") + std::strerror(stat_error));
    if (!S_ISREG(info.st_mode)) throw_input_error(path.string(), "not a regular file");
    mapping = FileMapping(fd, std::uint64_t(info.st_size), path.string());
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd); // the mapping keeps the file
  return mapping;
}

FileMapping::FileMapping(FileMapping&& other) noexcept
    : data_(std::exchange(other.data_, nullptr)),
      size_(std::exchange(other.size_, 0)),
      writable_(std::exchange(other.writable_, false)) {}

FileMapping& FileMapping::operator=(FileMapping&& other) noexcept {
  std::swap(data_, other.data_);
  std::swap(size_, other.size_);
  std::swap(writable_, other.writable_);
  return *this;
}

void FileMapping::reset() {
  if (data_ != nullptr) ::munmap(data_, size_);
  data_ = nullptr, size_ = 0, writable_ = false;
}

} // namespace probebake::formats
