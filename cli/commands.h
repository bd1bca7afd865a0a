// Subcommands of the probebake CLI. Each lives in its own cmd_*.cpp, parses into a settings struct and
// calls one library function; main() is the only catch-all that turns errors into exit codes.
#pragma once

#include <functional>
#include <utility>

#include <CLI/CLI.hpp>

namespace probebake::cli {

// A registered subcommand and the function that runs it once parsing succeeded (returns the exit code).
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

Command add_bake_command(CLI::App& root);
Command add_merge_command(CLI::App& root); // joins the parts of a split bake
Command add_info_command(CLI::App& root);
Command add_validate_command(CLI::App& root);
Command add_reference_command(CLI::App& root);
Command add_eval_command(CLI::App& root);
#ifdef PROBEBAKE_HAS_RUNTIME
Command add_run_command(CLI::App& root);    // the Vulkan runtime's run driver
Command add_render_command(CLI::App& root); // pictures through the runtime's lookup
#endif

} // namespace probebake::cli
