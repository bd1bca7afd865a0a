// atomic_write_helper TARGET SIZE SEED [STOP_AT]: writes helper_bytes(SIZE, SEED) to TARGET with
// write_file_atomically. With STOP_AT = k it stops at the k-th step of the write (counted from 0): prints
// the step's name on stdout and waits for a signal, so atomic_file_test can kill it at that exact moment.
// Otherwise prints "finished". Exit 3 with the error on stderr when the write fails.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "atomic_write_helper.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"

namespace {

long stop_at = -1;
long steps = 0;

void stop_here(std::string_view step) {
  if (steps++ != stop_at) return;
  std::printf("%.*s\n", static_cast<int>(step.size()), step.data());
  std::fflush(stdout);
  for (;;) ::pause(); // until killed
}

} // namespace

int main(int argc, char** argv) {
  if (argc != 4 && argc != 5) {
    std::fprintf(stderr, "usage: atomic_write_helper TARGET SIZE SEED [STOP_AT]\n");
    return 1;
  }
  if (argc == 5) stop_at = std::atol(argv[4]);
  probebake::set_atomic_write_test_hook(stop_here);
  try {
    probebake::write_file_atomically(argv[1], probebake::test::helper_bytes(std::strtoull(argv[2], nullptr, 10),
                                                                            static_cast<unsigned>(std::atoi(argv[3]))));
  } catch (const probebake::Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return e.exit_code();
  }
  std::printf("finished\n");
  return 0;
}
