// .probes reading and writing: round trips, only non-empty sections, forward compatibility (unknown
// optional sections, longer headers, newer minors), refusals (unknown required sections and features,
// other majors), one-line errors, atomic file writing.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <sys/wait.h>

#include "probebake/formats/cell_file.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/file_mapping.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "sample_volumes.h"
#include "test_bytes.h"

namespace probebake::formats {
namespace {

using testing::Sample;

// The sections of an existing file plus `extra`, written again.
std::vector<std::uint8_t> with_extra_section(const std::vector<std::uint8_t>& bytes, const SectionPayload& extra) {
  const ContainerView view = parse_container(bytes, "in");
  std::vector<SectionPayload> sections;
  for (std::size_t i = 0; i < view.sections.size(); ++i) {
    const SectionEntry& e = view.sections[i];
    sections.push_back(SectionPayload{e.type, e.flags, e.element_size, e.element_count, view.payloads[i]});
  }
  sections.push_back(extra);
  return write_container(ContainerHeaderFields{view.header.cell_depth, view.header.input_hash}, sections);
}

std::string error_of(const std::vector<std::uint8_t>& bytes) {
  try {
    read_probes(bytes, "test.probes");
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    return e.what();
  }
  return "";
}

TEST(ProbesFile, RoundTripIsByteIdentical) {
  for (Sample sample : testing::kAllSamples) {
    const ProbeVolume volume = testing::make_sample(sample);
    const std::vector<std::uint8_t> bytes = write_probes(volume);
    const ProbeVolume back = read_probes(bytes, "sample");
    EXPECT_EQ(write_probes(back), bytes);
    EXPECT_EQ(back.octree, volume.octree);
    EXPECT_EQ(back.probe_index, volume.probe_index);
    EXPECT_EQ(back.svo_nodes, volume.svo_nodes);
    EXPECT_EQ(back.cell_depth, volume.cell_depth);
    EXPECT_EQ(back.input_hash, volume.input_hash);
    ASSERT_EQ(back.probes.size(), volume.probes.size());
    EXPECT_EQ(std::memcmp(back.probes.data(), volume.probes.data(), volume.probes.size() * sizeof(gpu::Probe)), 0);
    EXPECT_TRUE(validate(back).valid());
  }
}

TEST(ProbesFile, OnlySectionsWithDataAreWritten) {
  const ContainerView full = parse_container(write_probes(testing::make_sample(Sample::small)), "small");
  EXPECT_EQ(full.sections.size(), 10u); // every section type of 1.0
  const std::vector<std::uint8_t> bytes = write_probes(testing::make_sample(Sample::static_set));
  const ContainerView view = parse_container(bytes, "static");
  for (const SectionEntry& entry : view.sections) {
    EXPECT_NE(entry.type, static_cast<std::uint32_t>(SectionType::surfel_batches));
    EXPECT_NE(entry.type, static_cast<std::uint32_t>(SectionType::leaf_entries));
    EXPECT_NE(entry.type, static_cast<std::uint32_t>(SectionType::leaf_queue_header));
    EXPECT_GT(entry.size, 0u);
    EXPECT_EQ(entry.offset % 16, 0u);
  }
  EXPECT_EQ(view.sections.size(), 10u - 3u);
}

// Format 1.1: the six lighting sections are optional (a 1.0 reader skips them), come after the 1.0
// sections, and make the file a 1.1 file; without them the writer still writes 1.0.
TEST(ProbesFile, LightingSectionsAreOptionalAndMakeTheFile1_1) {
  const std::vector<std::uint8_t> bytes = write_probes(testing::make_sample(Sample::lighting));
  const ContainerView view = parse_container(bytes, "lighting");
  EXPECT_EQ(view.header.version_minor, 1);
  ASSERT_EQ(view.sections.size(), 7u + 6u); // the static sample's sections + 6
  for (std::uint32_t k = 0; k < 6; ++k) {
    const SectionEntry& entry = view.sections[7 + k];
    EXPECT_EQ(entry.type, static_cast<std::uint32_t>(SectionType::lighting_info) + k);
    EXPECT_EQ(entry.flags, 0u) << section_name(entry.type);
  }
  EXPECT_EQ(section_name(static_cast<std::uint32_t>(SectionType::emitter_patches)), "emitter_patches");
  EXPECT_EQ(testing::header_of(write_probes(testing::make_sample(Sample::static_set))).version_minor, 0);
}

// Format 1.2: a set double-sided flag makes the file 1.2 and round-trips; the same sections without flags
// stay 1.1, byte for byte the file a 1.1 writer produces (the golden), so flags cost no byte.
TEST(ProbesFile, DoubleSidedFlagsMakeTheFile1_2) {
  const ProbeVolume volume = testing::make_sample(Sample::double_sided);
  const std::vector<std::uint8_t> bytes = write_probes(volume);
  EXPECT_EQ(testing::header_of(bytes).version_minor, kDoubleSidedFlagsMinor);
  EXPECT_EQ(kDoubleSidedFlagsMinor, 2);
  const ProbeVolume back = read_probes(bytes, "double_sided");
  ASSERT_EQ(back.trace_triangles.size(), 6u);
  const std::uint32_t expected[6] = {
      0u, 0u, gpu::TRIANGLE_DOUBLE_SIDED, gpu::TRIANGLE_DOUBLE_SIDED, gpu::TRIANGLE_DOUBLE_SIDED, 0u};
  for (std::size_t t = 0; t < 6; ++t) EXPECT_EQ(back.trace_triangles[t].flags, expected[t]) << t;
  ASSERT_EQ(back.emitter_patches.size(), 2u);
  for (const gpu::EmitterPatch& patch : back.emitter_patches) EXPECT_EQ(patch.flags, gpu::EMITTER_DOUBLE_SIDED);
  EXPECT_EQ(bytes.size(), write_probes(testing::make_sample(Sample::lighting)).size());
  EXPECT_EQ(minor_version_for_contents(testing::make_sample(Sample::lighting)), 0);
  ProbeVolume cleared = back;
  for (gpu::TraceTriangle& t : cleared.trace_triangles) t.flags = 0u;
  for (gpu::EmitterPatch& p : cleared.emitter_patches) p.flags = 0u;
  EXPECT_EQ(write_probes(cleared), read_file_bytes(testing::golden_path("v1_1_lighting.probes")));
}

TEST(ProbesFile, LightingRoundTripKeepsEveryValue) {
  const ProbeVolume volume = testing::make_sample(Sample::lighting);
  const std::vector<std::uint8_t> bytes = write_probes(volume);
  const ProbeVolume back = read_probes(bytes, "lighting");
  EXPECT_EQ(write_probes(back), bytes);
  ASSERT_TRUE(back.lighting.has_value());
  EXPECT_EQ(std::memcmp(&*back.lighting, &*volume.lighting, sizeof(gpu::LightingInfo)), 0);
  EXPECT_EQ(back.lighting->rays, 6);
  EXPECT_EQ(back.lighting->placement_rays, 32);
  EXPECT_EQ(back.lighting->bvh_nodes, 5);
  EXPECT_EQ(back.lighting->triangles, 6);
  EXPECT_EQ(back.lighting->lights, 3);
  EXPECT_EQ(back.lighting->emitter_patches, 2);
  ASSERT_EQ(back.ray_directions.size(), 38u);
  EXPECT_EQ(std::memcmp(back.ray_directions.data(), volume.ray_directions.data(), 38 * sizeof(glm::vec4)), 0);
  ASSERT_EQ(back.bvh_nodes.size(), 5u);
  EXPECT_EQ(std::memcmp(back.bvh_nodes.data(), volume.bvh_nodes.data(), 5 * sizeof(gpu::BvhNode)), 0);
  ASSERT_EQ(back.trace_triangles.size(), 6u);
  EXPECT_EQ(std::memcmp(back.trace_triangles.data(), volume.trace_triangles.data(), 6 * sizeof(gpu::TraceTriangle)), 0);
  ASSERT_EQ(back.punctual_lights.size(), 3u);
  EXPECT_EQ(back.punctual_lights[1].spot_scale, 4.0f);
  ASSERT_EQ(back.emitter_patches.size(), 2u);
  EXPECT_EQ(back.emitter_patches[1].b, glm::vec3(1.5f, 2.0f, 0.5f));
  EXPECT_TRUE(validate(back).valid());
}

// Sections without elements are not written: no lights, no patches -> no such sections, still valid.
TEST(ProbesFile, EmptyLightingSectionsAreLeftOut) {
  ProbeVolume volume = testing::make_sample(Sample::lighting);
  volume.punctual_lights.clear();
  volume.emitter_patches.clear();
  volume.lighting->emissive_as_lights = 0;
  sync_info_counts(volume);
  const ProbeVolume back = read_probes(write_probes(volume), "no lights");
  EXPECT_EQ(parse_container(write_probes(volume), "no lights").sections.size(), 7u + 4u);
  EXPECT_EQ(back.lighting->lights, 0);
  EXPECT_EQ(back.lighting->emissive_as_lights, 0);
  EXPECT_TRUE(validate(back).valid());
}

// A 1.0 file (the golden files) reads without lighting, and a 1.0 reader's rule (skip unknown optional
// sections) applied to a 1.1 file gives the same volume as the file without its lighting sections.
TEST(ProbesFile, Version1_0FileReadsWithoutLighting) {
  const std::vector<std::uint8_t> bytes = read_file_bytes(testing::golden_path("v1_0_static.probes"));
  EXPECT_EQ(testing::header_of(bytes).version_minor, 0);
  const ProbeVolume volume = read_probes(bytes, "v1_0");
  EXPECT_FALSE(volume.lighting.has_value());
  EXPECT_TRUE(volume.ray_directions.empty() && volume.bvh_nodes.empty() && volume.trace_triangles.empty());
  EXPECT_TRUE(volume.punctual_lights.empty() && volume.emitter_patches.empty());
  EXPECT_EQ(write_probes(volume), bytes);
  ProbeVolume stripped = read_probes(write_probes(testing::make_sample(Sample::lighting)), "v1_1");
  stripped.lighting.reset();
  stripped.ray_directions.clear(), stripped.bvh_nodes.clear(), stripped.trace_triangles.clear();
  stripped.punctual_lights.clear(), stripped.emitter_patches.clear();
  EXPECT_EQ(write_probes(stripped), bytes);
}

TEST(ProbesFile, UnknownOptionalSectionIsSkipped) {
  const std::vector<std::uint8_t> original = write_probes(testing::make_sample(Sample::small));
  const std::uint8_t payload[24] = {1, 2, 3};
  const std::vector<std::uint8_t> bytes = with_extra_section(original, SectionPayload{77, 0, 8, 3, payload});
  const ProbeVolume volume = read_probes(bytes, "extra");
  EXPECT_EQ(write_probes(volume), original);
  EXPECT_TRUE(validate_file(bytes, "extra").valid());
}

TEST(ProbesFile, UnknownRequiredSectionIsRefused) {
  const std::uint8_t payload[16] = {};
  const std::vector<std::uint8_t> bytes = with_extra_section(write_probes(testing::make_sample(Sample::small)),
                                                             SectionPayload{77, kSectionRequired, 16, 1, payload});
  EXPECT_NE(error_of(bytes).find("unknown required section"), std::string::npos) << error_of(bytes);
  EXPECT_FALSE(validate_file(bytes, "x").readable);
}

TEST(ProbesFile, UnknownRequiredFeatureIsRefused) {
  std::vector<std::uint8_t> bytes = write_probes(testing::make_sample(Sample::small));
  FileHeader header = testing::header_of(bytes);
  header.required_features = 1u << 4;
  testing::put_header(bytes, header);
  testing::refresh_header_checksum(bytes);
  EXPECT_NE(error_of(bytes).find("unknown required feature"), std::string::npos) << error_of(bytes);
}

TEST(ProbesFile, OtherMajorIsRefusedNewerMinorIsRead) {
  std::vector<std::uint8_t> bytes = write_probes(testing::make_sample(Sample::small));
  FileHeader header = testing::header_of(bytes);
  header.version_minor = 9;
  testing::put_header(bytes, header);
  testing::refresh_header_checksum(bytes);
  EXPECT_NO_THROW(read_probes(bytes, "minor"));
  header.version_major = 2;
  testing::put_header(bytes, header);
  testing::refresh_header_checksum(bytes);
  EXPECT_NE(error_of(bytes).find("unsupported format version 2.9"), std::string::npos) << error_of(bytes);
}

// A later minor version may append header fields: a 1.0 reader skips them (and checksums them).
TEST(ProbesFile, LongerHeaderIsSkipped) {
  const std::vector<std::uint8_t> original = write_probes(testing::make_sample(Sample::small));
  FileHeader header = testing::header_of(original);
  const std::size_t extra = 16;
  std::vector<std::uint8_t> bytes(original.begin(), original.begin() + sizeof(FileHeader));
  for (std::size_t i = 0; i < extra; ++i) bytes.push_back(static_cast<std::uint8_t>(0xA0 + i));
  bytes.insert(bytes.end(), original.begin() + sizeof(FileHeader), original.end());
  header.header_size += extra;
  header.file_size += extra;
  testing::put_header(bytes, header);
  for (std::uint32_t i = 0; i < header.section_count; ++i) {
    SectionEntry entry;
    std::uint8_t* at = bytes.data() + header.header_size + i * sizeof(SectionEntry);
    std::memcpy(&entry, at, sizeof(entry));
    entry.offset += extra;
    std::memcpy(at, &entry, sizeof(entry));
  }
  testing::refresh_header_checksum(bytes);
  EXPECT_EQ(write_probes(read_probes(bytes, "longer")), original);
  bytes[sizeof(FileHeader) + 3] ^= 1; // the appended header bytes are covered by the header checksum
  EXPECT_NE(error_of(bytes).find("header checksum"), std::string::npos);
}

TEST(ProbesFile, MissingVolumeInfoOrWrongElementSizeIsRefused) {
  const std::int32_t octree[1] = {0};
  const std::span<const std::uint8_t> octree_bytes(reinterpret_cast<const std::uint8_t*>(octree), sizeof(octree));
  const SectionPayload only_octree{static_cast<std::uint32_t>(SectionType::octree), kSectionRequired, 4, 1,
                                   octree_bytes};
  EXPECT_NE(error_of(write_container({}, std::span(&only_octree, 1))).find("no volume_info"), std::string::npos);

  const ProbeVolume volume = testing::make_sample(Sample::small);
  const std::span<const std::uint8_t> info_bytes(reinterpret_cast<const std::uint8_t*>(&volume.info),
                                                 sizeof(volume.info));
  const SectionPayload wrong_size[] = {
      {static_cast<std::uint32_t>(SectionType::volume_info), kSectionRequired, 40, 2, info_bytes}};
  EXPECT_NE(error_of(write_container({}, wrong_size)).find("element size 40, expected 80"), std::string::npos);
}

TEST(ProbesFile, ErrorsAreOneLineWithNameAndPlace) {
  const std::vector<std::uint8_t> garbage = {'n', 'o', 't', ' ', 'p', 'r', 'o', 'b', 'e', 's'};
  const std::string message = error_of(garbage);
  EXPECT_EQ(message.rfind("test.probes: header: ", 0), 0u) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
  std::vector<std::uint8_t> truncated = write_probes(testing::make_sample(Sample::small));
  truncated.resize(truncated.size() - 1);
  EXPECT_NE(error_of(truncated).find("truncated"), std::string::npos) << error_of(truncated);
}

class TempDir : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("probebake_formats_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::size_t entries() const {
    return static_cast<std::size_t>(
        std::distance(std::filesystem::directory_iterator(dir_), std::filesystem::directory_iterator()));
  }
  std::filesystem::path dir_;
};

TEST_F(TempDir, AtomicWriteReplacesAndLeavesNoTemporaries) {
  const std::filesystem::path path = dir_ / "scene.probes";
  write_probes_file(path, testing::make_sample(Sample::static_set));
  write_probes_file(path, testing::make_sample(Sample::small)); // replaces
  EXPECT_EQ(entries(), 1u);
  EXPECT_EQ(read_file_bytes(path), write_probes(testing::make_sample(Sample::small)));
  EXPECT_TRUE(validate(read_probes_file(path)).valid());
}

TEST_F(TempDir, FailedWriteThrowsOutputErrorAndCleansUp) {
  const std::filesystem::path target_is_directory = dir_ / "occupied";
  std::filesystem::create_directories(target_is_directory / "child");
  try {
    write_probes_file(target_is_directory, testing::make_sample(Sample::small));
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::output);
    EXPECT_NE(std::string(e.what()).find("occupied"), std::string::npos);
  }
  EXPECT_EQ(entries(), 1u); // only the directory; the temporary file was removed
  EXPECT_THROW(write_probes_file(dir_ / "missing" / "x.probes", testing::make_sample(Sample::small)), Error);
  EXPECT_EQ(entries(), 1u);
}

TEST_F(TempDir, ReadingAMissingFileIsAnInputError) {
  try {
    read_probes_file(dir_ / "absent.probes");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
  }
}

// A 1.7 file's streaming reader (CellFile::open) reads the global part only. A byte changed in a cell's faces
// is not read at the open, and refuses that cell when it is read, the others reading as in the file; a byte
// changed outside the cells (the dynamic object's vertices) refuses the open, naming its global checksum.
TEST_F(TempDir, AStreamingOpenReadsTheGlobalPartOnlyAndEachCellWhenAsked) {
  const ProbeVolume v = testing::make_sample(Sample::cells);
  const std::vector<std::uint8_t> bytes = write_probes(v);
  const ContainerView view = parse_container(bytes, "cells");
  const auto section = [&](SectionType type) {
    for (const SectionEntry& e : view.sections)
      if (e.type == static_cast<std::uint32_t>(type)) return e;
    return SectionEntry{};
  };
  std::size_t k = 0;
  while (v.cell_tracing[k].trace_faces.count == 0) ++k;
  std::uint64_t cells_tracing = 0;
  for (const CellTracing& t : v.cell_tracing) cells_tracing += cell_tracing_bytes(t);
  ASSERT_GT(cells_tracing, 0u);

  std::vector<std::uint8_t> cell_changed = bytes;
  cell_changed[section(SectionType::trace_faces).offset + v.cell_tracing[k].trace_faces.byte_offset] ^= 1;
  const std::filesystem::path a = dir_ / "cell.probes";
  std::ofstream(a, std::ios::binary)
      .write(reinterpret_cast<const char*>(cell_changed.data()), std::streamsize(cell_changed.size()));
  OpenedCellFile opened = CellFile::open(a);
  EXPECT_TRUE(opened.cells_unread);
  EXPECT_EQ(opened.bytes_read, bytes.size() - cells_tracing);
  std::vector<CellEntry> entries;
  ASSERT_TRUE(validate_without_cells(opened.volume, opened.tracing(), entries).valid());
  opened.file.expect_unread(opened.volume, entries);
  for (std::size_t j = 0; j < v.cells.size(); ++j) {
    if (j == k) continue;
    const CellTracingData read = opened.file.read_cell_tracing(j), expected = cell_tracing_data(v, j);
    EXPECT_EQ(read.faces.size(), expected.faces.size());
    EXPECT_TRUE(read.faces.empty() ||
                std::memcmp(read.faces.data(), expected.faces.data(), read.faces.size() * sizeof(read.faces[0])) == 0)
        << j;
  }
  try {
    (void)opened.file.read_cell_tracing(k);
    ADD_FAILURE() << "the changed cell read";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_NE(std::string(e.what()).find("cells[" + std::to_string(k) + "]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("differ from their checksum"), std::string::npos) << e.what();
  }

  std::vector<std::uint8_t> global_changed = bytes;
  const SectionEntry vertices = section(SectionType::trace_vertices);
  ASSERT_GT(vertices.size,
            v.cell_tracing.back().trace_vertices.byte_offset + v.cell_tracing.back().trace_vertices.byte_size);
  global_changed[vertices.offset + vertices.size - 1] ^= 1; // the dynamic object's last vertex
  const std::filesystem::path b = dir_ / "global.probes";
  std::ofstream(b, std::ios::binary)
      .write(reinterpret_cast<const char*>(global_changed.data()), std::streamsize(global_changed.size()));
  try {
    (void)CellFile::open(b);
    ADD_FAILURE() << "the changed global part opened";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_NE(
        std::string(e.what()).find("cell_global_checksums[5]: the bytes of trace_vertices outside the cells differ"),
        std::string::npos)
        << e.what();
  }
}

// A mapped file cut short under the reader raises SIGBUS on the lost page. Outside a guard that kills the
// program; inside MappedReadGuard (what probebake validate/info and probebake-run's load use) it is an input
// error, exit code 2, naming the file. The previous handler is back after the guard.
TEST_F(TempDir, AFileCutShortWhileMappedIsAnInputErrorInsideTheGuard) {
  const std::filesystem::path path = dir_ / "mapped.probes";
  std::ofstream(path, std::ios::binary) << std::string(1 << 16, 'x');
  const FileMapping mapping = FileMapping::of(path);
  ASSERT_EQ(mapping.bytes().size(), std::size_t(1) << 16);
  EXPECT_EQ(mapping.bytes()[40000], 'x');
  const auto cut_and_read = [&] {
    std::filesystem::resize_file(path, 0);
    return static_cast<int>(*static_cast<const volatile std::uint8_t*>(&mapping.bytes()[40000]));
  };
  EXPECT_EXIT(
      {
        const MappedReadGuard guard("probebake", path.string());
        std::_Exit(cut_and_read());
      },
      ::testing::ExitedWithCode(2), "probebake: error: .*mapped.probes: the file was cut short while it was read");
  // Without the guard: the default action, or a sanitizer's report; anything but the guard's exit.
  const auto not_the_guards_exit = [](int status) { return !(WIFEXITED(status) && WEXITSTATUS(status) == 2); };
  EXPECT_EXIT(
      {
        { const MappedReadGuard guard("probebake", path.string()); }
        std::_Exit(cut_and_read());
      },
      not_the_guards_exit, "");
}

} // namespace
} // namespace probebake::formats
