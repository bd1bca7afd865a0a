// Output paths of probebake (bake, reference, eval) and make-scene: an output that is an input (however
// spelled) or an existing non-regular file is refused with exit code 3 and one error line, before any
// work, and nothing is touched; SIGTERM at any moment of a bake leaves the old output or the complete new
// one, and no temporary file.
#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "probebake/samples/scenes.h"
#include "run_cli.h"

extern char** environ;

namespace probebake::test {
namespace {

namespace fs = std::filesystem;

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::vector<std::string> entries(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(folder)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

fs::path fresh_folder(const std::string& name) {
  const fs::path dir = fs::path(PROBEBAKE_BINARY_DIR) / "test-tmp" / "output-cli" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

bool is_refusal(const CliResult& r, const std::string& program, const fs::path& output, const std::string& reason) {
  const std::string start = program + ": error: " + output.string() + ": " + reason;
  return r.exit_code == 3 && r.err.rfind(start, 0) == 0 && r.err.find('\n') == r.err.size() - 1 && r.out.empty();
}

// A scene and the same file under other names: another spelling, symbolic links, a hard link.
struct SceneNames {
  fs::path scene;
  std::vector<fs::path> aliases;
};

SceneNames scene_with_aliases(const fs::path& dir) {
  SceneNames names{dir / "scene.glb", {}};
  samples::triangle().write_glb(names.scene);
  fs::create_directories(dir / "sub");
  fs::create_symlink(names.scene, dir / "link.glb");
  fs::create_symlink("scene.glb", dir / "relative-link.glb");
  fs::create_hard_link(names.scene, dir / "hard.glb");
  names.aliases = {names.scene, dir / "sub" / ".." / "scene.glb", dir / "link.glb", dir / "relative-link.glb",
                   dir / "hard.glb"};
  return names;
}

TEST(OutputCli, AnOutputThatIsTheSceneIsRefusedAndTheSceneKept) {
  const fs::path dir = fresh_folder("is-input");
  const SceneNames names = scene_with_aliases(dir);
  const std::string scene_bytes = read_bytes(names.scene);
  const std::vector<std::string> before = entries(dir);
  const std::string scene = quoted(names.scene);
  for (const fs::path& output : names.aliases) {
    const std::string o = quoted(output);
    for (const std::string& args :
         {"bake " + scene + " --no-lighting -o " + o, scene + " --output " + o,
          "reference " + scene + " --points 4 --samples 4 --csv " + o,
          "reference " + scene + " --points 0 --image " + o + " --camera 0,1,3 --look-at 0,0,0 --size 8x8",
          "eval " + scene + " --quick --no-cache --csv " + o, "eval " + scene + " --quick --no-cache --plot " + o}) {
      const CliResult r = run_cli(args);
      EXPECT_TRUE(is_refusal(r, "probebake", output, "is the input")) << args << "\n" << r.exit_code << " " << r.err;
    }
  }
  EXPECT_EQ(read_bytes(names.scene), scene_bytes);
  EXPECT_EQ(entries(dir), before);
}

TEST(OutputCli, NonRegularOutputsAreRefusedAndLeftAsTheyWere) {
  const fs::path dir = fresh_folder("non-regular");
  samples::triangle().write_glb(dir / "scene.glb");
  fs::create_directories(dir / "folder" / "child");
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0644), 0);
  fs::create_symlink(dir / "fifo", dir / "link-to-fifo");
  const std::vector<std::string> before = entries(dir);
  const std::string scene = quoted(dir / "scene.glb");
  struct Case {
    fs::path output;
    std::string what;
  };
  for (const Case& c : {Case{"/dev/null", "a character device"}, Case{dir / "fifo", "a FIFO"},
                        Case{dir / "link-to-fifo", "a FIFO"}, Case{dir / "folder", "a directory"}}) {
    const std::string o = quoted(c.output);
    for (const std::string& args : {"bake " + scene + " -o " + o, "reference " + scene + " --points 4 --csv " + o,
                                    "eval " + scene + " --quick --no-cache --plot " + o}) {
      const CliResult r = run_cli(args);
      EXPECT_TRUE(is_refusal(r, "probebake", c.output, "is " + c.what + ", not a regular file"))
          << args << "\n"
          << r.exit_code << " " << r.err;
    }
  }
  EXPECT_EQ(entries(dir), before);
  EXPECT_TRUE(fs::is_fifo(dir / "fifo"));
  EXPECT_TRUE(fs::is_directory(dir / "folder" / "child"));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  const CliResult maps = run_cli("eval " + scene + " --quick --no-cache --error-map " + quoted(dir / "scene.glb") +
                                 " --camera 0,1,3 --look-at 0,0,0 --size 8x8");
  EXPECT_EQ(maps.exit_code, 3) << maps.err;
  const CliResult missing = run_cli("bake " + scene + " -o " + quoted(dir / "no" / "x.probes"));
  EXPECT_TRUE(is_refusal(missing, "probebake", dir / "no" / "x.probes", "no such folder")) << missing.err;
}

TEST(OutputCli, AnOutputLinkIsWrittenThrough) {
  const fs::path dir = fresh_folder("link");
  samples::triangle().write_glb(dir / "scene.glb");
  fs::create_directories(dir / "real");
  std::ofstream(dir / "real" / "out.probes") << "old";
  fs::create_symlink("real/out.probes", dir / "out.probes");
  const CliResult r =
      run_cli(quoted(dir / "scene.glb") + " --no-lighting --placement grid --grid 2 -o " + quoted(dir / "out.probes"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(dir / "out.probes"));
  EXPECT_EQ(run_cli("validate " + quoted(dir / "real" / "out.probes")).exit_code, 0);
  EXPECT_EQ(entries(dir / "real"), std::vector<std::string>{"out.probes"});
}

TEST(OutputCli, MakeSceneRefusesToOverwriteItsModel) {
  const fs::path dir = fresh_folder("make-scene");
  samples::triangle().write_glb(dir / "model.glb");
  fs::create_symlink("model.glb", dir / "link.glb");
  const std::string bytes = read_bytes(dir / "model.glb");
  const fs::path logs = fresh_folder("make-scene-logs");
  const auto make_scene = [&](const std::string& args) { return run_program(MAKE_SCENE_EXE, args, logs); };
  for (const fs::path& output : {dir / "model.glb", dir / "link.glb"}) {
    const CliResult r = make_scene("cornell --with " + quoted(dir / "model.glb") + " -o " + quoted(output));
    EXPECT_TRUE(is_refusal(r, "make-scene", output, "is the input")) << r.exit_code << " " << r.err;
  }
  const CliResult null = make_scene("triangle -o /dev/null");
  EXPECT_TRUE(is_refusal(null, "make-scene", "/dev/null", "is a character device")) << null.err;
  EXPECT_EQ(read_bytes(dir / "model.glb"), bytes);
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"link.glb", "model.glb"}));
}

// --- SIGTERM during a bake, at moments spread over its run. The moment a signal lands varies from run to
// run; what is checked holds at every moment (formats_atomic_file_test stops the writer at each step).

pid_t spawn_cli(const std::vector<std::string>& args) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t defaults, none;
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGTERM);
  sigemptyset(&none);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
  std::vector<std::string> all = {PROBEBAKE_CLI};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  EXPECT_EQ(posix_spawn(&pid, PROBEBAKE_CLI, &actions, &attributes, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  return pid;
}

TEST(OutputCli, SigtermDuringABakeLeavesTheOldOutputOrTheNewOneAndNoTemporary) {
  const fs::path dir = fresh_folder("sigterm");
  samples::cornell().write_glb(dir / "scene.glb");
  const fs::path output = dir / "scene.probes";
  const std::vector<std::string> args = {
      (dir / "scene.glb").string(), "--max-depth", "3", "--svo-depth", "4", "--no-lighting", "-o", output.string()};
  // The new bytes (bakes are byte-identical) and the time a bake takes.
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  ASSERT_EQ(::waitpid(spawn_cli(args), &status, 0) > 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0, true);
  const auto duration = std::chrono::steady_clock::now() - start;
  const std::string new_bytes = read_bytes(output);
  ASSERT_FALSE(new_bytes.empty());
  int killed = 0;
  for (int i = 0; i <= 6; ++i) {
    { std::ofstream(output, std::ios::binary | std::ios::trunc) << "old"; }
    const pid_t pid = spawn_cli(args);
    std::this_thread::sleep_for(duration * i / 5);
    ::kill(pid, SIGTERM);
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE((WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) || (WIFEXITED(status) && WEXITSTATUS(status) == 0))
        << status;
    killed += WIFSIGNALED(status) ? 1 : 0;
    const std::string bytes = read_bytes(output);
    EXPECT_TRUE(bytes == "old" || bytes == new_bytes) << "after " << i << "/5 of a bake: " << bytes.size() << " bytes";
    EXPECT_EQ(entries(dir), (std::vector<std::string>{"scene.glb", "scene.probes"})) << i;
  }
  EXPECT_GT(killed, 0);
}

} // namespace
} // namespace probebake::test
