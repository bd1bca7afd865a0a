// Error against probe count for the octree's split rules and the grid (docs/results/placement.md,
// "Error-driven refinement and a probe budget (issue #13, first bullet)"): `probebake eval` on a chosen
// sweep, with the same receivers, reference cache and table.
// Usage: probebake-bench-refine SCENE CONFIG... [--threads N] [--baseline LABEL]
//   eN[:S]  octree, error rule, --probes N (uniform share S, default 0.5), max depth 6
//   sN[:S]  the same with the surface rule
//   hD      octree, hit-fraction rule, --max-depth D
//   gN      grid N^3
#include <cstdio>
#include <cstdlib>
#include <string>

#include <fmt/core.h>

#include "probebake/eval/eval.h"
#include "probebake/formats/error.h"

namespace {

using namespace probebake;

bake::EvalConfig parse_config(const std::string& token) {
  bake::EvalConfig c;
  const int n = std::atoi(token.c_str() + 1);
  if (n <= 0) throw Error(ErrorKind::usage, "bad configuration '" + token + "' (eN[:S], sN[:S], hD or gN)");
  if (token[0] == 'e' || token[0] == 's') {
    c.bake.split_rule = token[0] == 'e' ? bake::SplitRule::error : bake::SplitRule::surface;
    c.bake.probe_budget = n;
    c.bake.max_depth = 6;
    const auto colon = token.find(':');
    if (colon != std::string::npos) c.bake.uniform_share = std::strtof(token.c_str() + colon + 1, nullptr);
    const char* rule = token[0] == 'e' ? "error" : "surface";
    c.label = colon == std::string::npos ? fmt::format("{}-p{}", rule, n)
                                         : fmt::format("{}-p{}-u{}", rule, n, token.substr(colon + 1));
  } else if (token[0] == 'h') {
    c.bake.max_depth = n;
    c.label = fmt::format("octree-d{}", n);
  } else if (token[0] == 'g') {
    c.bake.placement = formats::PlacementKind::grid;
    c.bake.grid_resolution = n;
    c.label = fmt::format("grid-{}", n);
  } else {
    throw Error(ErrorKind::usage, "bad configuration '" + token + "' (eN[:S], sN[:S], hD or gN)");
  }
  return c;
}

} // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 3)
      throw Error(ErrorKind::usage, "usage: probebake-bench-refine SCENE CONFIG... [--threads N] [--baseline LABEL]");
    bake::EvalSettings settings;
    settings.baseline = std::string("-"); // no all-probes row unless --baseline names a configuration
    for (int i = 2; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "--threads" && i + 1 < argc)
        settings.threads = std::atoi(argv[++i]);
      else if (arg == "--baseline" && i + 1 < argc)
        settings.baseline = argv[++i];
      else
        settings.configs.push_back(parse_config(arg));
    }
    bake::check_eval_settings(settings);
    const bake::EvalResult result =
        bake::evaluate(argv[1], settings, [](const std::string& m) { fmt::print(stderr, "{}\n", m); });
    std::puts(bake::eval_markdown_table(result).c_str());
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "probebake-bench-refine: error: {}\n", e.what());
    return 1;
  }
}
