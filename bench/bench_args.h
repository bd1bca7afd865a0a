// The benchmarks' one option, `--runs N`, shared by those that take it.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <optional>

namespace probebake::bench {

// `--runs N` (at least 1) among argv[first..argc), else `runs`; nullopt when anything else is there.
inline std::optional<int> parse_runs(int argc, char** argv, int first, int runs) {
  for (int i = first; i < argc; ++i) {
    if (std::strcmp(argv[i], "--runs") == 0 && i + 1 < argc)
      runs = std::max(1, std::atoi(argv[++i]));
    else
      return std::nullopt;
  }
  return runs;
}

} // namespace probebake::bench
