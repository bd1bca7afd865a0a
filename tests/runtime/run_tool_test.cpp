// probebake-run end to end: frames with live validation and the validation layer, CSV output, exit codes.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "probebake/formats/probes_file.h"
#include "probebake/samples/scenes.h"
#include "probebake/sky/sky.h"
#include "run_cli.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using RunToolTest = RuntimeTest;

// The path quoted for the shell (test::quoted, not std::quoted, which ADL would pick for a std::string).
std::string shell_path(const std::string& path) { return test::quoted(std::filesystem::path(path)); }

int count_lines(const std::string& path) {
  std::ifstream in(path);
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  return lines;
}

TEST(RunToolUsage, NoInputIsAUsageError) {
  const CliResult r = run_cli("");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("usage: probebake-run"), std::string::npos) << r.err;
  EXPECT_EQ(run_cli("x.probes --frames 0").exit_code, 1);
  EXPECT_EQ(run_cli("x.probes --bogus").exit_code, 1);
  EXPECT_EQ(run_cli("--help").exit_code, 0);
}

TEST_F(RunToolTest, RunsFramesValidatesAndWritesCsv) {
  const std::string probes = temp_path("tool-cornell.probes"), csv = temp_path("tool-cornell.csv");
  formats::write_probes_file(probes, baked_cornell_full());
  const CliResult r = run_cli(
      shell_path(probes) +
      " --frames 5 --verbose --validate --vk-validation --samples 1000 --compare-all-probes --csv " + shell_path(csv));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("device: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frame 5: probe_index "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| light_gather | all | 5 |"), std::string::npos) << r.out; // the summary table
  EXPECT_NE(r.out.find("live state valid after every frame"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("samples (SVO probe index): 1000 lookups"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("samples (all probes, thesis 3.2.4): 1000 lookups"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("compare: all-probe loop / SVO = "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("validation messages: 0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("light_gather "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("traced "), std::string::npos) << r.out; // L1 statistics of frame 1
  // header + per frame the probe index build, gather and resolve, + the trace of frame 1
  EXPECT_EQ(count_lines(csv), 1 + 5 * 3 + 1);
}

// --depth-cycle turns the memory update on: max depth 3, 2, 3 every two frames, every leaf re-measured then.
TEST_F(RunToolTest, DepthCycleReshapesTheTree) {
  const std::string probes = temp_path("tool-cycle.probes"), csv = temp_path("tool-cycle.csv");
  formats::write_probes_file(probes, baked_cornell_full());
  const CliResult r = run_cli(shell_path(probes) + " --frames 6 --verbose --depth-cycle 2:3:2 --vk-validation --csv " +
                              shell_path(csv));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("validation messages: 0"), std::string::npos) << r.out;
  int merges = 0, splits = 0;
  for (std::size_t at = r.out.find("memory: "); at != std::string::npos; at = r.out.find("memory: ", at + 1)) {
    int s = 0, m = 0;
    if (std::sscanf(r.out.c_str() + at, "memory: %d splits, %d merges", &s, &m) == 2) splits += s, merges += m;
  }
  EXPECT_GT(merges, 0) << r.out; // depth 2 merges the bake's depth-3 leaves
  EXPECT_GT(splits, 0) << r.out; // and depth 3 splits them again
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_NE(header.find(",splits,merges,failed_allocations,free_probes"), std::string::npos) << header;
  // header + per frame: memory_update, probe_index, light_transitions, light_trace, light_gather, light_resolve
  EXPECT_EQ(count_lines(csv), 1 + 6 * 6);
  // The pool line: the depth cycle's peak use within the default pool (as many free slots as in use, at
  // least 512); with --pool-probes 3 the pool is that much larger than the tree in use, not 512.
  const auto pool_line = [](const std::string& out, int& in_use, int& slots, int& failed) {
    const std::size_t at = out.find("memory update pools: ");
    return at != std::string::npos &&
           std::sscanf(out.c_str() + at, "memory update pools: at most %d of %d probe slots in use, %d failed", &in_use,
                       &slots, &failed) == 3;
  };
  int in_use = 0, slots = 0, failed = 0;
  ASSERT_TRUE(pool_line(r.out, in_use, slots, failed)) << r.out;
  const formats::ProbeVolume file = baked_cornell_full();
  const int used =
      int(std::count_if(file.probes.begin(), file.probes.end(), [](const gpu::Probe& p) { return p.link != 0; }));
  EXPECT_GE(slots, used + 512);
  EXPECT_GT(in_use, 0);
  EXPECT_LE(in_use, slots);
  const CliResult small = run_cli(shell_path(probes) + " --memory-update --pool-probes 3");
  ASSERT_EQ(small.exit_code, 0) << small.out << small.err;
  ASSERT_TRUE(pool_line(small.out, in_use, slots, failed)) << small.out;
  EXPECT_GE(slots, used + 3);
  EXPECT_LT(slots, used + 512);
  EXPECT_EQ(run_cli(shell_path(probes) + " --memory-update --pool-probes -1").exit_code, 1);
  EXPECT_EQ(run_cli(shell_path(probes) + " --depth-cycle 2:3").exit_code, 1);
  EXPECT_EQ(run_cli(shell_path(probes) + " --depth-cycle 2:13:4").exit_code, 1);
}

// --animate: the file's two blocks turn (revolution: a turn in 150 frames), the memory update follows; one
// CSV row per frame, the summary table by phase, three SVG plots, the live state valid, the layer silent.
TEST_F(RunToolTest, AnimatesDynamicObjectsWithFramesTablePlotsAndSummary) {
  const std::string probes = temp_path("tool-animate.probes"), csv = temp_path("tool-animate.csv"),
                    plots = temp_path("tool-animate-plots");
  formats::write_probes_file(probes, baked_cornell_dynamic());
  const CliResult r =
      run_cli(shell_path(probes) + " --animate revolution --frames 24 --validate --vk-validation --csv " +
              shell_path(csv) + " --plots " + shell_path(plots));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("animation: revolution over 24 frames, 2 dynamic object(s), memory update on"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("| memory_update | all | 24 |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| gpu total | all | 24 |"), std::string::npos) << r.out; // one phase: no "turning" rows
  EXPECT_NE(r.out.find("live state valid after every frame"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("validation messages: 0"), std::string::npos) << r.out;
  EXPECT_EQ(count_lines(csv), 1 + 24);
  std::ifstream in(csv);
  std::string header, first, second;
  std::getline(in, header), std::getline(in, first), std::getline(in, second);
  EXPECT_NE(header.find(",surfel_hit_fraction,"), std::string::npos) << header;
  // Column moved_objects: frame 0 is the rest pose (nothing sent), frame 1 has both blocks turned.
  const auto fields = [](const std::string& line) {
    std::vector<std::string> out(1);
    for (char c : line) {
      if (c == ',')
        out.emplace_back();
      else
        out.back().push_back(c);
    }
    return out;
  };
  const auto column = [&](const std::string& row, const std::string& name) {
    const std::vector<std::string> names = fields(header), values = fields(row);
    const auto at = std::find(names.begin(), names.end(), name);
    return at == names.end() ? std::string("?") : values.at(std::size_t(at - names.begin()));
  };
  EXPECT_EQ(column(first, "moved_objects"), "0") << first;
  EXPECT_EQ(column(second, "moved_objects"), "2") << second;
  for (const char* file : {"frame_times.svg", "probes.svg", "leaf_states.svg"}) {
    std::ifstream svg(std::filesystem::path(plots) / file);
    std::string text((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("<polyline"), std::string::npos) << file;
  }
  EXPECT_EQ(run_cli(shell_path(probes) + " --animate spin").exit_code, 1);
  EXPECT_EQ(run_cli(shell_path(probes) + " --limits 4").exit_code, 1);
}

// --animate on a file without dynamic objects would run frames of nothing: a one-line usage error naming it.
TEST_F(RunToolTest, AnimateWithoutDynamicObjectsIsRefused) {
  const std::string probes = temp_path("tool-animate-static.probes");
  formats::write_probes_file(probes, baked_cornell_octree());
  const CliResult r = run_cli(shell_path(probes) + " --animate thesis");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find(probes + ": --animate: the file has no dynamic objects to move"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// --trace-budget with --load-focus: the load trace in windows of 8 slots nearest a point, the live state valid
// and the layer silent throughout.
TEST_F(RunToolTest, TraceBudgetSpreadsTheLoadTrace) {
  const std::string probes = temp_path("tool-trace-budget.probes");
  formats::write_probes_file(probes, baked_cornell_octree());
  const CliResult r =
      run_cli(shell_path(probes) + " --trace-budget 8 --load-focus 0,0.3,0 --frames 12 --validate --vk-validation");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("validation messages: 0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("load trace done in frame"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("load trace done in frame 0\n"), std::string::npos) << r.out; // in windows, not at once
  EXPECT_EQ(run_cli(shell_path(probes) + " --trace-budget -1").exit_code, 1);
  EXPECT_EQ(run_cli(shell_path(probes) + " --load-focus 0,nan,0").exit_code, 1);
  EXPECT_EQ(run_cli(shell_path(probes) + " --load-focus 0,1").exit_code, 1);
}

// The last two CSV columns of each light_gather row: hour and emitters_on.
std::vector<std::string> lighting_columns(const std::string& csv) {
  std::ifstream in(csv);
  std::vector<std::string> columns;
  for (std::string line; std::getline(in, line);) {
    if (line.find(",light_gather,") == std::string::npos) continue;
    const std::size_t last = line.rfind(','), hour = line.rfind(',', last - 1);
    columns.push_back(line.substr(hour + 1));
  }
  return columns;
}

// --switch-emitters 2: the Cornell light off in frames 2-3 and on again from frame 4, relit in those two frames.
TEST_F(RunToolTest, SwitchesEmittersOffAndOn) {
  const std::string probes = temp_path("tool-switch.probes"), csv = temp_path("tool-switch.csv");
  formats::write_probes_file(probes, baked_cornell_octree());
  const CliResult r =
      run_cli(shell_path(probes) + " --frames 6 --switch-emitters 2 --validate --csv " + shell_path(csv));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("emitters: 1 switched off and on every 2 frames"), std::string::npos) << r.out;
  EXPECT_EQ(lighting_columns(csv), (std::vector<std::string>{",1", ",1", ",0", ",0", ",1", ",1"}));
  std::ifstream in(csv);
  int relit = 0;
  for (std::string line; std::getline(in, line);) relit += line.find(",light_relight,") != std::string::npos ? 1 : 0;
  EXPECT_EQ(relit, 2);
  EXPECT_EQ(run_cli(shell_path(probes) + " --switch-emitters 0").exit_code, 1);
}

// --day-cycle 0.1 (6 frames a day): the hours 6, 10 and 14 in the CSV, the sky relit in every frame after the first.
TEST_F(RunToolTest, RunsADay) {
  bake::BakeSettings settings = small_bake_settings();
  settings.lighting.rays = 16;
  settings.placement = bake::Placement::grid;
  settings.grid_resolution = 3;
  const Baked b = bake_generated(samples::plane_light(), "tool-day", settings,
                                 sky::physical_sky({sky::direction_from_angles(30.0f, 90.0f), 2.5f}));
  const std::string probes = temp_path("tool-day.probes"), csv = temp_path("tool-day.csv");
  formats::write_probes_file(probes, b.volume);
  const CliResult r = run_cli(shell_path(probes) + " --frames 3 --day-cycle 0.1 --validate --csv " + shell_path(csv));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("day cycle: a day in 0.1 s (6 frames), sun from 6:00"), std::string::npos) << r.out;
  EXPECT_EQ(lighting_columns(csv), (std::vector<std::string>{"6.000000,", "10.000000,", "14.000000,"}));
}

// --day-cycle needs a physical sky with a sun; --switch-emitters needs emitters.
TEST_F(RunToolTest, LightingChangesTheFileCannotTakeAreRefused) {
  const std::string probes = temp_path("tool-no-sky.probes");
  formats::ProbeVolume dark = baked_cornell_octree();
  dark.emitter_patches.clear();
  dark.lighting->emitter_patches = 0;
  formats::write_probes_file(probes, dark);
  for (const char* option : {"--day-cycle 10", "--switch-emitters 5"}) {
    const CliResult r = run_cli(shell_path(probes) + " " + option);
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_NE(r.err.find(probes + ": " + std::string(option).substr(0, std::string(option).find(' '))),
              std::string::npos)
        << r.err;
  }
}

TEST_F(RunToolTest, BadInputExitsWithTwo) {
  EXPECT_EQ(run_cli(shell_path(temp_path("missing.probes"))).exit_code, 2);
  formats::ProbeVolume broken = baked_cornell_octree();
  broken.probe_index[0] = 999;
  const std::string path = temp_path("tool-invalid.probes");
  formats::write_probes_file(path, broken);
  const CliResult r = run_cli(shell_path(path));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("probe_index_list"), std::string::npos) << r.err;
}

} // namespace
} // namespace probebake::test
