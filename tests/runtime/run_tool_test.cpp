// probebake-run end to end: frames with live validation and the validation layer, CSV output, exit codes.
#include <filesystem>
#include <fstream>
#include <string>

#include "probebake/formats/probes_file.h"
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
  const CliResult r =
      run_cli(shell_path(probes) + " --frames 5 --validate --vk-validation --samples 1000 --compare-all-probes --csv " + shell_path(csv));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("device: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frame 5: probe_index "), std::string::npos) << r.out;
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
