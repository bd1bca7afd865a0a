// probebake-run: the run driver (run_driver.h) as a program that links only the runtime, formats and the
// C++ runtime, for GPU machines that have nothing but a Vulkan loader. `probebake run` is the same driver.
#include <cstdio>
#include <exception>
#include <string>

#include "run_driver.h"
#include "run_options.h"

int main(int argc, char** argv) {
  std::string message;
  int exit_code = 0;
  const auto options = probebake::run::parse_run_options(argc, argv, message, exit_code);
  if (!options) {
    std::fputs(message.c_str(), exit_code == 0 ? stdout : stderr);
    return exit_code;
  }
  try {
    return probebake::run::run_volume(*options);
  } catch (const std::exception& e) { // the runtime does not throw; this covers the driver's own I/O
    std::fprintf(stderr, "probebake-run: internal error: %s\n", e.what());
    return 4;
  }
}
