// probebake command line: argument parsing and exit codes only; the work is done by the libraries.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "commands.h"
#include "probebake/formats/error.h"
#include "probebake/formats/format_version.h"
#include "probebake/version.h"

namespace {

std::string version_text() {
  return fmt::format("probebake {} (.probes format {}.{})", PROBEBAKE_VERSION_STRING,
                     probebake::formats::kFormatVersionMajor, probebake::formats::kFormatVersionMinor);
}

} // namespace

int main(int argc, char** argv) {
  using namespace probebake;
  CLI::App app{"probebake: adaptive light probes for real-time diffuse global illumination"};
  app.set_version_flag("--version", version_text());
  app.require_subcommand(1);
  std::vector<cli::Command> commands = {
      cli::add_bake_command(app),     cli::add_merge_command(app),     cli::add_info_command(app),
      cli::add_validate_command(app), cli::add_reference_command(app), cli::add_eval_command(app),
#ifdef PROBEBAKE_HAS_RUNTIME
      cli::add_run_command(app),      cli::add_render_command(app),
#endif
  };

  // `probebake scene.gltf` is short for `probebake bake scene.gltf`.
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && !args[0].starts_with("-") &&
      app.get_subcommands([&](CLI::App* s) { return s->get_name() == args[0]; }).empty())
    args.insert(args.begin(), "bake");
  std::reverse(args.begin(), args.end()); // CLI11 takes the arguments as a reversed vector
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : static_cast<int>(ErrorKind::usage);
  }

  try {
    for (const cli::Command& command : commands) {
      if (command.app->parsed()) return command.run();
    }
    return static_cast<int>(ErrorKind::usage);
  } catch (const Error& e) {
    std::fprintf(stderr, "probebake: error: %s\n", e.what());
    return e.exit_code();
  } catch (const std::bad_alloc&) { // an allocation past --max-memory that no earlier check foresaw
    std::fprintf(stderr, "probebake: error: out of memory: the input needs more than the memory budget "
                         "(--max-memory) or the machine has\n");
    return static_cast<int>(ErrorKind::input);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "probebake: internal error: %s\n", e.what());
    return static_cast<int>(ErrorKind::internal);
  }
}
