// The probebake CLI on .probes files: `probebake validate` exit codes (0 valid, 1 invalid, 2 unreadable),
// its text (one line per violated invariant, every violation with --verbose) and JSON, and
// run_info_probes (cli/info_probes.cpp, linked in directly).
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "info_probes.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/probes_file.h"
#include "run_cli.h"
#include "sample_volumes.h"
#include "test_bytes.h"

namespace probebake::formats {
namespace {

// `words` then the quoted path, appended piecewise: GCC 12 at -O3 warns falsely (-Wrestrict) on
// "..." + std::string&&.
std::string with_path(const char* words, const std::filesystem::path& path) {
  std::string line = words;
  line += " '";
  line += path.string();
  line += '\'';
  return line;
}

using test::run_cli;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
    lines.push_back(text.substr(start, end - start));
  if (start < text.size()) lines.push_back(text.substr(start));
  return lines;
}

class CliValidate : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("probebake_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path write_bytes(const std::string& name, const std::vector<std::uint8_t>& bytes) const {
    const std::filesystem::path path = dir_ / name;
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    return path;
  }
  std::filesystem::path dir_;
};

TEST_F(CliValidate, GoldenFileIsValid) {
  const std::filesystem::path golden = testing::golden_path(testing::golden_name(testing::Sample::small));
  const test::CliResult json = run_cli(with_path("validate --json", golden));
  EXPECT_EQ(json.exit_code, 0) << json.out;
  EXPECT_TRUE(nlohmann::json::parse(json.out)["valid"].get<bool>());
  const test::CliResult text = run_cli(with_path("validate", golden));
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.out.find(": valid"), std::string::npos) << text.out;
}

TEST_F(CliValidate, BrokenTreeIsInvalidAndNamed) {
  ProbeVolume volume = testing::make_sample(testing::Sample::small);
  volume.octree[12] = 10; // a node pointing at its own ancestor cluster
  const std::filesystem::path path = write_bytes("cycle.probes", write_probes(volume));
  const test::CliResult json = run_cli(with_path("validate --json", path));
  EXPECT_EQ(json.exit_code, 1) << json.out;
  const nlohmann::json report = nlohmann::json::parse(json.out);
  EXPECT_FALSE(report["valid"].get<bool>());
  EXPECT_EQ(report["violations"][0]["invariant"], "octree_cycle");
  const test::CliResult text = run_cli(with_path("validate", path));
  EXPECT_EQ(text.exit_code, 1);
  EXPECT_NE(text.out.find(path.string() + ": invalid: octree_cycle: 1 violation, first: octree[10]: "),
            std::string::npos)
      << text.out;
  EXPECT_EQ(text.out.find("octree[10]: octree_cycle"), std::string::npos) << "details only with --verbose\n"
                                                                          << text.out;
  const test::CliResult verbose = run_cli(with_path("validate --verbose", path));
  EXPECT_EQ(verbose.exit_code, 1);
  EXPECT_NE(verbose.out.find(path.string() + ": octree[10]: octree_cycle: "), std::string::npos) << verbose.out;
}

// Thirty broken probes are one problem: one summary line for it, then the verdict; --verbose adds the
// thirty details, --json keeps them all.
TEST_F(CliValidate, TextIsOneLinePerInvariant) {
  ProbeVolume volume = testing::make_sample(testing::Sample::small);
  for (gpu::Probe& probe : volume.probes) probe.hit_fraction = std::nanf("");
  volume.info.split_low = -0.25f; // a second class, reported first (settings run before probes)
  const std::filesystem::path path = write_bytes("nan.probes", write_probes(volume));
  const std::size_t probes = volume.probes.size();

  const test::CliResult text = run_cli(with_path("validate --max-errors 0", path));
  EXPECT_EQ(text.exit_code, 1);
  const std::vector<std::string> lines = lines_of(text.out);
  ASSERT_EQ(lines.size(), 3u) << text.out;
  const std::string name = path.string();
  EXPECT_EQ(
      lines[0].rfind(name + ": invalid: volume_info: 1 violation, first: volume_info[0]: split thresholds -0.25", 0),
      0u)
      << lines[0];
  EXPECT_EQ(lines[1], name + ": invalid: non_finite: " + std::to_string(probes) +
                          " violations, first: probes[0]: a float is NaN or infinite");
  EXPECT_EQ(lines[2], name + ": invalid: " + std::to_string(probes + 1) + " violations of 2 invariants");

  const test::CliResult verbose = run_cli(with_path("validate --verbose --max-errors 0", path));
  EXPECT_EQ(lines_of(verbose.out).size(), probes + 1 + 3) << verbose.out;
  const nlohmann::json json = nlohmann::json::parse(run_cli(with_path("validate --json --max-errors 0", path)).out);
  EXPECT_EQ(json["violations"].size(), probes + 1);

  const test::CliResult stopped = run_cli(with_path("validate --max-errors 5", path));
  EXPECT_NE(stopped.out.find(": invalid: 5 violations of 2 invariants (stopped at --max-errors)"), std::string::npos)
      << stopped.out;
}

// A file that streams (cell_tracing, 1.6) has each cell checked on its own. One cell's bytes replaced under
// the checksums written before (every section checksum holds: a patch that swapped one cell's bytes but
// not its checksum) is named, and no other.
TEST_F(CliValidate, EachCellIsCheckedOnItsOwnAndADamagedOneIsNamed) {
  ProbeVolume volume = testing::make_sample(testing::Sample::small);
  volume.cell_tracing.resize(volume.cells.size()); // empty tracing ranges: the sample has no tracing sections
  const std::string cells = std::to_string(volume.cells.size()) + " cells checked on their own, ";
  const std::vector<std::uint8_t> before = write_probes(volume);
  const std::filesystem::path clean = write_bytes("clean.probes", before);
  const test::CliResult ok = run_cli(with_path("validate", clean));
  EXPECT_EQ(ok.exit_code, 0) << ok.out;
  EXPECT_EQ(lines_of(ok.out),
            (std::vector<std::string>{clean.string() + ": " + cells + "0 damaged", clean.string() + ": valid"}));

  std::size_t damaged = 1;
  while (volume.cells[damaged].probes.count == 0) ++damaged;
  volume.probes[volume.cells[damaged].probes.first].irradiance_sh[0] += 1.0f;
  const ContainerView old_view = parse_container(before, "before");
  const auto old_checksums =
      std::find_if(old_view.sections.begin(), old_view.sections.end(), [](const SectionEntry& e) {
        return e.type == static_cast<std::uint32_t>(SectionType::cell_checksums);
      });
  ASSERT_NE(old_checksums, old_view.sections.end());
  const std::vector<std::uint8_t> patched =
      testing::rewrite_sections(write_probes(volume), [&](std::vector<SectionPayload>& sections) {
        for (SectionPayload& section : sections)
          if (section.type == old_checksums->type)
            section.bytes = old_view.payloads[std::size_t(old_checksums - old_view.sections.begin())];
      });
  const std::filesystem::path path = write_bytes("damaged.probes", patched);
  const test::CliResult text = run_cli(with_path("validate", path));
  EXPECT_EQ(text.exit_code, 1) << text.out;
  const std::string name = path.string(), place = "cells[" + std::to_string(damaged) + "]";
  EXPECT_NE(text.out.find(name + ": " + cells + "1 damaged\n" + name + ": damaged: " + place + ": the "),
            std::string::npos)
      << text.out;
  const nlohmann::json json = nlohmann::json::parse(run_cli(with_path("validate --json", path)).out);
  EXPECT_EQ(json["cells_checked"], volume.cells.size());
  ASSERT_EQ(json["violations"].size(), 1u) << json.dump();
  EXPECT_EQ(json["violations"][0]["invariant"], "cell_checksum");
  EXPECT_EQ(json["violations"][0]["index"], damaged);
}

// A global part's checksum that does not match (format 1.7): reported for its section, the rest valid.
TEST_F(CliValidate, AGlobalChecksumThatDiffersIsReportedForItsSection) {
  const std::vector<std::uint8_t> bytes = write_probes(testing::make_sample(testing::Sample::cells));
  const std::size_t faces = 4; // kCellSplitSections: probes, batches, SVO leaves, trace nodes, trace faces, ...
  std::vector<std::uint8_t> changed;
  const std::vector<std::uint8_t> patched =
      testing::rewrite_sections(bytes, [&](std::vector<SectionPayload>& sections) {
        for (SectionPayload& section : sections) {
          if (section.type != static_cast<std::uint32_t>(SectionType::cell_global_checksums)) continue;
          ASSERT_EQ(section.element_count, 6u);
          changed.assign(section.bytes.begin(), section.bytes.end());
          changed[faces * 8] ^= 1;
          section.bytes = changed;
        }
      });
  const nlohmann::json json =
      nlohmann::json::parse(run_cli(with_path("validate --json", write_bytes("global.probes", patched))).out);
  ASSERT_EQ(json["violations"].size(), 1u) << json.dump();
  EXPECT_EQ(json["violations"][0]["invariant"], "cell_global_checksum");
  EXPECT_EQ(json["violations"][0]["index"], faces);
  EXPECT_NE(json["violations"][0]["message"].get<std::string>().find("trace_faces"), std::string::npos);
}

// Zero bytes after the last payload: readable (the reader reads the file), but invalid.
TEST_F(CliValidate, TrailingBytesAreInvalidNotUnreadable) {
  std::vector<std::uint8_t> bytes = read_file_bytes(testing::golden_path(testing::golden_name(testing::Sample::small)));
  testing::insert_zeros(bytes, bytes.size(), 32);
  testing::refresh_header_checksum(bytes);
  const test::CliResult text = run_cli(with_path("validate", write_bytes("tail.probes", bytes)));
  EXPECT_EQ(text.exit_code, 1) << text.out;
  EXPECT_NE(text.out.find(": invalid: trailing_bytes: 1 violation, first: container: 32 bytes after the last payload"),
            std::string::npos)
      << text.out;
}

TEST_F(CliValidate, FlippedByteIsAChecksumViolation) {
  std::vector<std::uint8_t> bytes = read_file_bytes(testing::golden_path(testing::golden_name(testing::Sample::small)));
  bytes[bytes.size() - 3] ^= 0x10;
  const test::CliResult json = run_cli(with_path("validate --json", write_bytes("flipped.probes", bytes)));
  EXPECT_EQ(json.exit_code, 1) << json.out;
  EXPECT_EQ(nlohmann::json::parse(json.out)["violations"][0]["invariant"], "checksum");
}

TEST_F(CliValidate, MaxErrorsLimitsTheReport) {
  ProbeVolume volume = testing::make_sample(testing::Sample::small);
  for (gpu::Probe& probe : volume.probes) probe.pad0 = std::nanf("");
  const test::CliResult json =
      run_cli(with_path("validate --json --max-errors 2", write_bytes("nan.probes", write_probes(volume))));
  EXPECT_EQ(json.exit_code, 1);
  const nlohmann::json report = nlohmann::json::parse(json.out);
  EXPECT_EQ(report["violations"].size(), 2u);
  EXPECT_TRUE(report["truncated"].get<bool>());
}

TEST_F(CliValidate, UnreadableFilesExitTwo) {
  std::vector<std::uint8_t> truncated =
      read_file_bytes(testing::golden_path(testing::golden_name(testing::Sample::static_set)));
  truncated.resize(truncated.size() / 2);
  const std::vector<std::uint8_t> garbage = {'g', 'l', 'T', 'F', 2, 0, 0, 0, 1, 2, 3};
  for (const std::filesystem::path& path :
       {write_bytes("truncated.probes", truncated), write_bytes("garbage.probes", garbage), dir_ / "missing.probes"}) {
    const test::CliResult json = run_cli(with_path("validate --json", path));
    EXPECT_EQ(json.exit_code, 2) << path;
    const nlohmann::json report = nlohmann::json::parse(json.out);
    EXPECT_FALSE(report["readable"].get<bool>());
    EXPECT_EQ(report["violations"][0]["invariant"], "container");
    const test::CliResult text = run_cli(with_path("validate", path));
    EXPECT_EQ(text.exit_code, 2);
    ASSERT_EQ(lines_of(text.out).size(), 2u) << text.out; // the reader's one-line reason, then the verdict
    EXPECT_EQ(lines_of(text.out)[1], path.string() + ": unreadable");
  }
  EXPECT_EQ(run_cli("validate").exit_code, 1); // usage error: no file
}

TEST(InfoProbes, JsonHasCountsSectionsAndCells) {
  const std::string golden = testing::golden_path(testing::golden_name(testing::Sample::small)).string();
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(cli::run_info_probes(golden, true), 0);
  const nlohmann::json info = nlohmann::json::parse(::testing::internal::GetCapturedStdout());
  EXPECT_EQ(info["probes"], 25);
  EXPECT_EQ(info["nodes"], 33); // 29 leaves + 4 parents
  EXPECT_EQ(info["max_depth"], 2);
  EXPECT_EQ(info["depth_histogram"], nlohmann::json::array({0, 4, 21}));
  EXPECT_EQ(info["sections"].size(), 10u); // every section type of 1.0
  EXPECT_EQ(info["sections"][0]["name"], "volume_info");
  EXPECT_GE(info["cells"].size(), 2u);
  EXPECT_EQ(info["settings"]["placement"], "octree");

  ::testing::internal::CaptureStdout();
  EXPECT_EQ(cli::run_info_probes(golden, false), 0);
  const std::string text = ::testing::internal::GetCapturedStdout();
  EXPECT_NE(text.find("25 of 30 allocated"), std::string::npos) << text;
}

// A file with split tracing (1.6): what a streaming runtime loads whole and what it reads per cell.
TEST(InfoProbes, SaysWhatStreamingKeepsInHostMemory) {
  const std::string golden = testing::golden_path(testing::golden_name(testing::Sample::cells)).string();
  const ProbeVolume v = read_probes_file(golden);
  std::uint64_t tracing = 0, largest = 0;
  for (const CellTracing& t : v.cell_tracing) {
    const std::uint64_t bytes = cell_tracing_bytes(t);
    tracing += bytes, largest = std::max(largest, bytes);
  }
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(cli::run_info_probes(golden, true), 0);
  const nlohmann::json info = nlohmann::json::parse(::testing::internal::GetCapturedStdout());
  EXPECT_EQ(info["format_version"], "1.7");
  EXPECT_EQ(info["streaming"]["cell_tracing_bytes"], tracing);
  EXPECT_EQ(info["streaming"]["global_bytes"], std::filesystem::file_size(golden) - tracing);
  EXPECT_EQ(info["streaming"]["largest_cell_tracing_bytes"], largest);
  EXPECT_EQ(info["streaming"]["cells_with_faces"], 4);
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(cli::run_info_probes(golden, false), 0);
  EXPECT_NE(::testing::internal::GetCapturedStdout().find("B load whole"), std::string::npos);
  // Without split tracing there is nothing to stream.
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(cli::run_info_probes(testing::golden_path(testing::golden_name(testing::Sample::compact)).string(), true),
            0);
  EXPECT_TRUE(nlohmann::json::parse(::testing::internal::GetCapturedStdout())["streaming"].is_null());
}

// A 1.1 file: the lighting sections are listed by name, as optional, and the version is 1.1.
TEST(InfoProbes, NamesTheLightingSections) {
  const std::string golden = testing::golden_path(testing::golden_name(testing::Sample::lighting)).string();
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(cli::run_info_probes(golden, true), 0);
  const nlohmann::json info = nlohmann::json::parse(::testing::internal::GetCapturedStdout());
  EXPECT_EQ(info["format_version"], "1.1");
  ASSERT_EQ(info["sections"].size(), 13u);
  const char* names[] = {"lighting_info",   "ray_directions",  "bvh_nodes",
                         "trace_triangles", "punctual_lights", "emitter_patches"};
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(info["sections"][7 + k]["name"], names[k]);
    EXPECT_FALSE(info["sections"][7 + k]["required"].get<bool>());
  }
  EXPECT_EQ(info["sections"][9]["elements"], 5); // BVH nodes
}

} // namespace
} // namespace probebake::formats
