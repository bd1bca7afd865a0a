#include "probebake/formats/atomic_file.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "probebake/formats/error.h"

namespace probebake {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kChunkBytes = std::size_t(1) << 20;

std::atomic<AtomicWriteTestHook> test_hook{nullptr};

void step(std::string_view name) {
  if (const AtomicWriteTestHook hook = test_hook.load(std::memory_order_relaxed)) hook(name);
}

std::string errno_text() { return std::strerror(errno); }

[[noreturn]] void refuse(const fs::path& path, const std::string& reason) {
  throw Error(ErrorKind::output, path.string() + ": " + reason);
}

// --- Temporaries registry, read by the signal handler: fixed storage, lock-free atomics, no allocation.

constexpr int kSlots = 64;
constexpr std::size_t kPathBytes = 4096;
constexpr int kFree = 0, kFilling = 1, kReady = 2;
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the registry");

struct Slot {
  std::atomic<int> state{kFree};
  char path[kPathBytes];
};
Slot slots[kSlots];

void remove_temporaries_and_reraise(int signal) {
  for (Slot& slot : slots)
    if (slot.state.load(std::memory_order_acquire) == kReady) ::unlink(slot.path);
  // Default action, then the signal again: it is delivered when this handler returns, so the process
  // ends the way it would have without us (the exit status says which signal).
  struct sigaction action {};
  action.sa_handler = SIG_DFL;
  sigemptyset(&action.sa_mask);
  ::sigaction(signal, &action, nullptr);
  ::raise(signal);
}

// Only where the disposition is still the default: an ignored signal (nohup, `&` in a script) stays
// ignored and a handler installed by the program is not replaced.
void install_signal_handlers() {
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (::sigaction(signal, nullptr, &old) != 0 || (old.sa_flags & SA_SIGINFO) != 0 || old.sa_handler != SIG_DFL)
      continue;
    struct sigaction action {};
    action.sa_handler = remove_temporaries_and_reraise;
    sigemptyset(&action.sa_mask);
    ::sigaction(signal, &action, nullptr);
  }
}

// Registers a temporary path before the file exists (so no signal can leave it behind) and forgets it
// when destroyed. With every slot taken (64 concurrent writes) the write goes on unregistered.
class Registration {
public:
  explicit Registration(const fs::path& temporary) {
    const std::string path = fs::absolute(temporary).string(); // the handler must not depend on the cwd
    if (path.size() >= kPathBytes) return;
    for (Slot& s : slots) {
      int expected = kFree;
      if (!s.state.compare_exchange_strong(expected, kFilling, std::memory_order_acquire)) continue;
      std::memcpy(s.path, path.c_str(), path.size() + 1);
      s.state.store(kReady, std::memory_order_release);
      slot_ = &s;
      return;
    }
  }
  Registration(const Registration&) = delete;
  Registration& operator=(const Registration&) = delete;
  ~Registration() { release(); }
  void release() {
    if (slot_ != nullptr) slot_->state.store(kFree, std::memory_order_release);
    slot_ = nullptr;
  }

private:
  Slot* slot_ = nullptr;
};

// --- Targets

// The file a write replaces: `path` with symbolic links followed (the last one may dangle).
fs::path write_target(const fs::path& path) {
  fs::path target = path;
  for (int hops = 0; hops < 40; ++hops) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(target, ec))) return target;
    const fs::path link = fs::read_symlink(target, ec);
    if (ec) return target;
    target = link.is_absolute() ? link : target.parent_path() / link;
  }
  refuse(path, "too many levels of symbolic links");
}

const char* file_type_name(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

void refuse_non_regular(const fs::path& path, const fs::path& target) {
  struct stat st {};
  if (::stat(target.c_str(), &st) != 0 || S_ISREG(st.st_mode))
    return; // missing: created; other errors: reported by the write
  refuse(path, std::string("is ") + file_type_name(st.st_mode) + ", not a regular file; not replaced");
}

fs::path folder_of(const fs::path& target) { return target.has_parent_path() ? target.parent_path() : fs::path("."); }

fs::path temporary_path_for(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  fs::path temporary = target;
  temporary += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  return temporary;
}

// The pid in "<target name>.tmp.<pid>.<n>", or 0 when `name` is not one of the target's temporaries.
pid_t temporary_owner(const std::string& name, const std::string& prefix) {
  if (!name.starts_with(prefix)) return 0;
  const std::string rest = name.substr(prefix.size());
  const std::size_t dot = rest.find('.');
  if (dot == 0 || dot == std::string::npos || dot + 1 == rest.size() || dot > 9) return 0;
  const auto digits = [](char c) { return c >= '0' && c <= '9'; };
  if (!std::all_of(rest.begin(), rest.end(), [&](char c) { return digits(c) || c == '.'; }) ||
      std::count(rest.begin(), rest.end(), '.') != 1)
    return 0;
  return static_cast<pid_t>(std::stol(rest.substr(0, dot)));
}

// Temporaries of `target` left by a writer killed with SIGKILL (or a crash). Removed only when their
// process is gone and no lock is held on them: a writer holds an flock on its temporary, which also
// protects one in another PID namespace sharing the folder. Best effort: errors are ignored.
void remove_stale_temporaries(const fs::path& target) {
  const std::string prefix = target.filename().string() + ".tmp.";
  std::error_code ec;
  for (fs::directory_iterator it(folder_of(target), ec), end; !ec && it != end; it.increment(ec)) {
    const pid_t pid = temporary_owner(it->path().filename().string(), prefix);
    if (pid <= 0 || pid == ::getpid() || ::kill(pid, 0) == 0 || errno != ESRCH) continue;
    const int fd = ::open(it->path().c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
    if (fd < 0) continue;
    struct stat st {};
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && ::flock(fd, LOCK_EX | LOCK_NB) == 0)
      ::unlink(it->path().c_str());
    ::close(fd);
  }
}

bool write_all(int fd, std::span<const std::uint8_t> bytes) {
  std::size_t written = 0;
  while (written < bytes.size()) {
    const std::size_t chunk_end = std::min(bytes.size(), (written / kChunkBytes + 1) * kChunkBytes);
    const ssize_t n = ::write(fd, bytes.data() + written, chunk_end - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    written += static_cast<std::size_t>(n);
    if (written == chunk_end) step("chunk");
  }
  return true;
}

// The rename is durable once the folder is flushed. Best effort: some file systems refuse fsync on a
// folder, and the target has been replaced either way.
void sync_folder(const fs::path& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

} // namespace

void set_atomic_write_test_hook(AtomicWriteTestHook hook) { test_hook.store(hook); }

void check_output_path(const fs::path& output, std::span<const fs::path> inputs) {
  if (output.empty()) throw Error(ErrorKind::output, "empty output path");
  for (const fs::path& input : inputs) {
    std::error_code ec;
    if (fs::equivalent(output, input, ec) && !ec) {
      refuse(output, output == input ? std::string("is the input; not overwritten")
                                     : "is the input " + input.string() + "; not overwritten");
    }
  }
  const fs::path target = write_target(output);
  refuse_non_regular(output, target);
  std::error_code ec;
  if (!fs::is_directory(folder_of(target), ec)) refuse(output, "no such folder: " + folder_of(target).string());
}

void write_file_atomically(const fs::path& path, std::span<const std::uint8_t> bytes) {
  const fs::path target = write_target(path);
  refuse_non_regular(path, target);
  static const bool handlers_installed = (install_signal_handlers(), true);
  (void)handlers_installed;
  remove_stale_temporaries(target);

  const fs::path temporary = temporary_path_for(target);
  Registration registration(temporary);
  step("registered");
  const auto fail = [&](const char* what, int fd) {
    const std::string reason = errno_text();
    if (fd >= 0) ::close(fd);
    ::unlink(temporary.c_str());
    throw Error(ErrorKind::output, path.string() + ": " + what + ": " + reason);
  };
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) fail("cannot write", -1);
  ::flock(fd, LOCK_EX | LOCK_NB); // marks the temporary as in use (remove_stale_temporaries); advisory
  step("created");
  if (!write_all(fd, bytes) || ::fsync(fd) != 0) fail("cannot write", fd);
  step("synced");
  // Renamed while still open, so the lock covers the temporary until it is gone. After fsync, close
  // has nothing left to report.
  if (::rename(temporary.c_str(), target.c_str()) != 0) fail("cannot replace", fd);
  step("renamed");
  registration.release();
  ::close(fd);
  sync_folder(folder_of(target));
  step("done");
}

void write_file_atomically(const fs::path& path, std::string_view text) {
  write_file_atomically(path, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

} // namespace probebake
