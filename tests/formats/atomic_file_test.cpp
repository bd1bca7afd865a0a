// write_file_atomically and check_output_path: refusals (an input, however spelled; an existing file that
// is not a regular one), symbolic links written through, and kills at every step of a write (the helper
// program stops at a chosen step; SIGTERM, SIGINT, SIGHUP and SIGKILL are sent there), which must leave
// the old target or the complete new one, and no temporary file.
#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "atomic_write_helper.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"

extern char** environ;

namespace probebake::test {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void write_bytes(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

std::vector<std::string> entries(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(folder)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

class AtomicFile : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("probebake-atomic-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The Error(output) message of `f`, or "" when it does not throw one.
  template <class F>
  static std::string output_error(F f) {
    try {
      f();
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::output) << e.what();
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

void check(const fs::path& output, std::initializer_list<fs::path> inputs) {
  const std::vector<fs::path> list(inputs);
  check_output_path(output, list);
}

TEST_F(AtomicFile, OutputThatIsTheInputIsRefusedHoweverSpelled) {
  const fs::path scene = dir_ / "scene.glb";
  write_bytes(scene, {1, 2, 3});
  fs::create_directories(dir_ / "sub");
  fs::create_symlink(scene, dir_ / "link.glb");
  fs::create_symlink("scene.glb", dir_ / "relative-link.glb");
  fs::create_hard_link(scene, dir_ / "hard.glb");
  for (const fs::path& output : {scene, dir_ / "sub" / ".." / "scene.glb", dir_ / "." / "scene.glb", dir_ / "link.glb",
                                 dir_ / "relative-link.glb", dir_ / "hard.glb"}) {
    const std::string message = output_error([&] { check(output, {scene}); });
    EXPECT_EQ(message.rfind(output.string() + ": is the input", 0), 0u) << output << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
  // The input given through a link, the output as the file itself.
  EXPECT_NE(output_error([&] { check(scene, {dir_ / "link.glb"}); }), "");
  EXPECT_EQ(read_bytes(scene), (std::vector<std::uint8_t>{1, 2, 3}));
}

TEST_F(AtomicFile, OtherOutputsPass) {
  const fs::path scene = dir_ / "scene.glb";
  write_bytes(scene, {1});
  write_bytes(dir_ / "old.probes", {2});
  check(dir_ / "new.probes", {scene});
  check(dir_ / "old.probes", {scene});
  check(dir_ / "new.probes", {dir_ / "missing.glb"}); // a missing input is the loader's error, not ours
  check(dir_ / "new.probes", {});
  EXPECT_NE(output_error([&] { check(dir_ / "no" / "folder.probes", {scene}); }).find("no such folder"),
            std::string::npos);
  EXPECT_EQ(output_error([&] { check("", {scene}); }), "empty output path");
}

TEST_F(AtomicFile, NonRegularTargetsAreRefusedAndLeftAsTheyWere) {
  fs::create_directories(dir_ / "folder" / "child");
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0644), 0) << std::strerror(errno);
  fs::create_symlink(dir_ / "fifo", dir_ / "link-to-fifo");
  fs::create_symlink(dir_ / "folder", dir_ / "link-to-folder");
  const std::vector<std::string> before = entries(dir_);
  const std::vector<std::uint8_t> bytes = {1, 2, 3};
  struct Case {
    fs::path path;
    const char* what;
  };
  for (const Case& c :
       {Case{dir_ / "folder", "a directory"}, Case{dir_ / "fifo", "a FIFO"}, Case{dir_ / "link-to-fifo", "a FIFO"},
        Case{dir_ / "link-to-folder", "a directory"}, Case{"/dev/null", "a character device"}}) {
    if (c.path == "/dev/null" && !fs::is_character_file("/dev/null")) continue;
    for (const bool early : {true, false}) {
      const std::string message = early ? output_error([&] { check(c.path, {}); })
                                        : output_error([&] { write_file_atomically(c.path, bytes); });
      EXPECT_EQ(message, c.path.string() + ": is " + c.what + ", not a regular file; not replaced") << early;
    }
  }
  EXPECT_EQ(entries(dir_), before); // nothing replaced, no temporary left
  EXPECT_TRUE(fs::is_fifo(dir_ / "fifo"));
  EXPECT_TRUE(fs::is_directory(dir_ / "folder" / "child"));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

TEST_F(AtomicFile, SymbolicLinksAreWrittenThrough) {
  fs::create_directories(dir_ / "real");
  write_bytes(dir_ / "real" / "out.csv", {9, 9});
  fs::create_symlink("real/out.csv", dir_ / "link.csv");
  write_file_atomically(dir_ / "link.csv", std::string_view("new"));
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.csv"));
  EXPECT_EQ(read_bytes(dir_ / "real" / "out.csv"), (std::vector<std::uint8_t>{'n', 'e', 'w'}));
  EXPECT_EQ(entries(dir_ / "real"), std::vector<std::string>{"out.csv"});
  // A dangling link: the file it names is created.
  fs::create_symlink("real/later.csv", dir_ / "dangling.csv");
  write_file_atomically(dir_ / "dangling.csv", std::string_view("x"));
  EXPECT_TRUE(fs::is_symlink(dir_ / "dangling.csv"));
  EXPECT_EQ(read_bytes(dir_ / "real" / "later.csv"), (std::vector<std::uint8_t>{'x'}));
  EXPECT_EQ(entries(dir_), (std::vector<std::string>{"dangling.csv", "link.csv", "real"}));
}

// --- Kills during a write, through the helper program.

struct Stopped {
  pid_t pid = -1;
  std::optional<std::string> step; // empty: the helper finished without stopping
};

// Starts the helper with the default action for the signals and none blocked (ctest or a shell may have
// set either; with `ignore_sighup`, SIGHUP ignored as under nohup), and reads the step it stopped at.
Stopped start_helper(const fs::path& target, std::size_t size, unsigned seed, std::optional<long> stop_at,
                     bool ignore_sighup = false) {
  int pipe_fds[2];
  EXPECT_EQ(::pipe(pipe_fds), 0);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t defaults, none;
  sigemptyset(&defaults);
  for (const int s : {SIGINT, SIGTERM, SIGHUP})
    if (s != SIGHUP || !ignore_sighup) sigaddset(&defaults, s);
  sigemptyset(&none);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
  std::vector<std::string> args = {ATOMIC_WRITE_HELPER, target.string(), std::to_string(size), std::to_string(seed)};
  if (stop_at) args.push_back(std::to_string(*stop_at));
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  Stopped s;
  struct sigaction ignore {
  }, old{};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  if (ignore_sighup) ::sigaction(SIGHUP, &ignore, &old); // inherited by the helper
  EXPECT_EQ(posix_spawn(&s.pid, ATOMIC_WRITE_HELPER, &actions, &attributes, argv.data(), environ), 0);
  if (ignore_sighup) ::sigaction(SIGHUP, &old, nullptr);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  ::close(pipe_fds[1]);
  std::string line;
  char c;
  pollfd p{pipe_fds[0], POLLIN, 0};
  while (::poll(&p, 1, 60'000) == 1 && ::read(pipe_fds[0], &c, 1) == 1 && c != '\n') line += c;
  ::close(pipe_fds[0]);
  if (line != "finished") s.step = line;
  return s;
}

// The wait status, killing the helper if it does not end within a minute (a test failure, not a hang).
int wait_for(pid_t pid) {
  int status = 0;
  for (int i = 0; i < 6000; ++i) {
    if (::waitpid(pid, &status, WNOHANG) == pid) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ADD_FAILURE() << "the helper did not end";
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return status;
}

constexpr std::size_t kNewSize = (std::size_t(7) << 19) + 123; // 3.5 MiB: four chunks
constexpr std::size_t kOldSize = 1000;

// Kills the helper at each step in turn; returns the steps seen.
std::vector<std::string> kill_at_every_step(const fs::path& dir, int signal) {
  const fs::path target = dir / "out.probes";
  const std::vector<std::uint8_t> old_bytes = helper_bytes(kOldSize, 1), new_bytes = helper_bytes(kNewSize, 2);
  std::vector<std::string> steps;
  for (long k = 0; k < 100; ++k) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    write_bytes(target, old_bytes);
    const Stopped s = start_helper(target, kNewSize, 2, k);
    if (!s.step) {
      EXPECT_TRUE(WIFEXITED(wait_for(s.pid)));
      break;
    }
    steps.push_back(*s.step);
    ::kill(s.pid, signal);
    const int status = wait_for(s.pid);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal) << *s.step << ": status " << status;
    const bool replaced = *s.step == "renamed" || *s.step == "done";
    EXPECT_EQ(read_bytes(target), replaced ? new_bytes : old_bytes) << "killed at " << *s.step;
    if (signal != SIGKILL) {
      EXPECT_EQ(entries(dir), std::vector<std::string>{"out.probes"}) << "killed at " << *s.step;
      continue;
    }
    // SIGKILL: a temporary may remain; the next write of the target removes it.
    const Stopped next = start_helper(target, kOldSize, 3, std::nullopt);
    EXPECT_FALSE(next.step.has_value());
    EXPECT_TRUE(WIFEXITED(wait_for(next.pid)));
    EXPECT_EQ(read_bytes(target), helper_bytes(kOldSize, 3));
    EXPECT_EQ(entries(dir), std::vector<std::string>{"out.probes"}) << "killed at " << *s.step;
  }
  return steps;
}

const std::vector<std::string> kSteps = {"registered", "created", "chunk",   "chunk", "chunk",
                                         "chunk",      "synced",  "renamed", "done"};

TEST_F(AtomicFile, KilledBySigtermAtEveryStepLeavesOldOrNewAndNoTemporary) {
  EXPECT_EQ(kill_at_every_step(dir_, SIGTERM), kSteps);
}

TEST_F(AtomicFile, KilledBySigintOrSighupAtEveryStepLeavesOldOrNewAndNoTemporary) {
  EXPECT_EQ(kill_at_every_step(dir_, SIGINT), kSteps);
  EXPECT_EQ(kill_at_every_step(dir_, SIGHUP), kSteps);
}

TEST_F(AtomicFile, KilledBySigkillLeavesOldOrNewAndTheNextWriteRemovesTheTemporary) {
  EXPECT_EQ(kill_at_every_step(dir_, SIGKILL), kSteps);
}

TEST_F(AtomicFile, TemporariesOfLiveWritersAndOtherFilesAreKept) {
  const pid_t dead = ::fork(); // a pid with no process once reaped
  if (dead == 0) ::_exit(0);
  ASSERT_GT(dead, 0);
  ::waitpid(dead, nullptr, 0);
  const std::string live = std::to_string(::getpid()), gone = std::to_string(dead);
  const std::vector<std::string> kept = {"out.probes.tmp." + live + ".5", "out.probes.tmp.x.1",
                                         "out.probes.tmp." + gone, "other.probes.tmp." + gone + ".0",
                                         "out.probes.tmp." + gone + ".1.2"};
  for (const std::string& name : kept) write_bytes(dir_ / name, {7});
  write_bytes(dir_ / ("out.probes.tmp." + gone + ".0"), {7}); // stale: removed
  const Stopped s = start_helper(dir_ / "out.probes", 10, 4, std::nullopt);
  EXPECT_FALSE(s.step.has_value());
  EXPECT_TRUE(WIFEXITED(wait_for(s.pid)));
  std::vector<std::string> expected = kept;
  expected.push_back("out.probes");
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(entries(dir_), expected);
}

TEST_F(AtomicFile, AnIgnoredSignalStaysIgnored) {
  // Under nohup: SIGHUP, discarded when sent to a process that ignores it, does not end the write.
  const fs::path target = dir_ / "out.probes";
  write_bytes(target, helper_bytes(kOldSize, 1));
  const Stopped s = start_helper(target, kNewSize, 2, 3, /*ignore_sighup=*/true);
  ASSERT_EQ(s.step, "chunk");
  ::kill(s.pid, SIGHUP);
  ::kill(s.pid, SIGTERM);
  const int status = wait_for(s.pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_EQ(read_bytes(target), helper_bytes(kOldSize, 1));
  EXPECT_EQ(entries(dir_), std::vector<std::string>{"out.probes"});
}

} // namespace
} // namespace probebake::test
