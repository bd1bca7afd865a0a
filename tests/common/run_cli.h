// Runs a built program (the `probebake` CLI: path in the PROBEBAKE_CLI compile definition) for CLI tests
// and captures its exit code, stdout and stderr. Output goes to files unique to the call: CTest runs the
// tests of one binary as parallel processes, so a fixed capture path is a race between them.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace probebake::test {

struct CliResult {
  int exit_code = -1; // -1 when the process did not exit normally (a crash)
  std::string out;
  std::string err;
};

inline std::string quoted(const std::filesystem::path& path) { return "'" + path.string() + "'"; }

// `arguments` are passed to the shell as they are: quote paths with quoted(). The program runs in
// `working_dir` when one is given.
inline CliResult run_program(const std::filesystem::path& program, const std::string& arguments,
                             const std::filesystem::path& working_dir = {}) {
  static std::atomic<int> counter{0};
  const auto base = std::filesystem::temp_directory_path() /
                    ("probebake-cli-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  const auto out = base.string() + ".out", err = base.string() + ".err";
  const std::string cd = working_dir.empty() ? "" : "cd " + quoted(working_dir) + " && ";
  const std::string command = cd + quoted(program) + " " + arguments + " > '" + out + "' 2> '" + err + "'";
  const int status = std::system(command.c_str());
  auto slurp = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  CliResult result{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return result;
}

#ifdef PROBEBAKE_CLI
inline CliResult run_cli(const std::string& arguments) { return run_program(PROBEBAKE_CLI, arguments); }
#endif

} // namespace probebake::test
