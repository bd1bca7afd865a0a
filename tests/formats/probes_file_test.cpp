// .probes reading and writing: round trips, only non-empty sections, forward compatibility (unknown
// optional sections, longer headers, newer minors), refusals (unknown required sections and features,
// other majors), one-line errors, atomic file writing.
#include <cstring>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "probebake/formats/error.h"
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
  for (Sample sample : {Sample::small, Sample::static_set, Sample::grid}) {
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
  EXPECT_EQ(full.sections.size(), kSectionTypeCount);
  const std::vector<std::uint8_t> bytes = write_probes(testing::make_sample(Sample::static_set));
  const ContainerView view = parse_container(bytes, "static");
  for (const SectionEntry& entry : view.sections) {
    EXPECT_NE(entry.type, static_cast<std::uint32_t>(SectionType::surfel_batches));
    EXPECT_NE(entry.type, static_cast<std::uint32_t>(SectionType::leaf_entries));
    EXPECT_NE(entry.type, static_cast<std::uint32_t>(SectionType::leaf_queue_header));
    EXPECT_GT(entry.size, 0u);
    EXPECT_EQ(entry.offset % 16, 0u);
  }
  EXPECT_EQ(view.sections.size(), kSectionTypeCount - 3);
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
  const std::vector<std::uint8_t> bytes =
      with_extra_section(write_probes(testing::make_sample(Sample::small)), SectionPayload{77, kSectionRequired, 16, 1, payload});
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
  const SectionPayload only_octree{static_cast<std::uint32_t>(SectionType::octree), kSectionRequired, 4, 1, octree_bytes};
  EXPECT_NE(error_of(write_container({}, std::span(&only_octree, 1))).find("no volume_info"), std::string::npos);

  const ProbeVolume volume = testing::make_sample(Sample::small);
  const std::span<const std::uint8_t> info_bytes(reinterpret_cast<const std::uint8_t*>(&volume.info), sizeof(volume.info));
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
    return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(dir_), std::filesystem::directory_iterator()));
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

} // namespace
} // namespace probebake::formats
