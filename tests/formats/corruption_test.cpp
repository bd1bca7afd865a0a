// Untrusted bytes (meshoptimizer / NanoVDB style): every strict prefix of a golden file is refused as
// unreadable, and every single-byte change (XOR 0x01 and XOR 0xFF at every offset) is detected by both
// the reader and the validator. Files that the reader reads but the format does not allow (gaps, trailing
// zero bytes, wrong flags, versions, a leaf header without entries) are refused by the validator only.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "sample_volumes.h"
#include "test_bytes.h"

namespace probebake::formats {
namespace {

using testing::Sample;

bool reader_refuses(std::span<const std::uint8_t> bytes) {
  try {
    read_probes(bytes, "corrupt");
  } catch (const Error& e) {
    return e.kind() == ErrorKind::input;
  }
  return false;
}

class Corruption : public ::testing::TestWithParam<Sample> {
protected:
  std::vector<std::uint8_t> golden() const {
    return read_file_bytes(testing::golden_path(testing::golden_name(GetParam())));
  }
};

TEST_P(Corruption, EveryPrefixIsUnreadable) {
  const std::vector<std::uint8_t> bytes = golden();
  ASSERT_FALSE(bytes.empty());
  for (std::size_t size = 0; size < bytes.size(); ++size) {
    const std::span<const std::uint8_t> prefix(bytes.data(), size);
    ASSERT_TRUE(reader_refuses(prefix)) << "prefix of " << size << " bytes";
    const ValidationReport report = validate_file(prefix, "prefix");
    ASSERT_FALSE(report.valid()) << size;
    ASSERT_FALSE(report.readable) << size;
    ASSERT_EQ(report.violations.front().invariant, "container");
  }
}

TEST_P(Corruption, EverySingleByteChangeIsDetected) {
  std::vector<std::uint8_t> bytes = golden();
  std::size_t changes = 0, by_reader = 0, by_validator = 0;
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    for (std::uint8_t mask : {std::uint8_t{0x01}, std::uint8_t{0xFF}}) {
      bytes[at] ^= mask;
      ++changes;
      by_reader += reader_refuses(bytes);
      by_validator += !validate_file(bytes, "flipped", ValidateOptions{1}).valid();
      bytes[at] ^= mask;
    }
  }
  const double rate = 100.0 * static_cast<double>(std::min(by_reader, by_validator)) / static_cast<double>(changes);
  std::printf("[ %s ] %zu single-byte changes: reader refused %zu, validator flagged %zu: detection %.2f%%\n",
              testing::golden_name(GetParam()), changes, by_reader, by_validator, rate);
  EXPECT_EQ(by_reader, changes);
  EXPECT_EQ(by_validator, changes);
}

// The verdict (unreadable: exit 2, invalid: exit 1) and the first violations do not depend on
// --max-errors; `truncated` says that something was left out, never only that the limit was reached.
TEST_P(Corruption, VerdictDoesNotDependOnMaxErrors) {
  std::vector<std::uint8_t> bytes = golden();
  for (std::size_t at = 0; at < bytes.size(); at += 3) {
    bytes[at] ^= 0xFF;
    const ValidationReport all = validate_file(bytes, "flipped", ValidateOptions{0});
    const ValidationReport one = validate_file(bytes, "flipped", ValidateOptions{1});
    bytes[at] ^= 0xFF;
    ASSERT_EQ(all.readable, one.readable) << "byte " << at;
    ASSERT_FALSE(one.violations.empty()) << "byte " << at;
    EXPECT_EQ(one.violations[0].invariant, all.violations[0].invariant) << "byte " << at;
    EXPECT_EQ(one.truncated, all.violations.size() > 1) << "byte " << at;
  }
}

TEST_P(Corruption, PayloadChangeIsAChecksumViolationNotUnreadable) {
  std::vector<std::uint8_t> bytes = golden();
  const ContainerView view = parse_container(bytes, "golden");
  bytes[view.sections[1].offset + 1] ^= 0x40; // inside the octree section
  const ValidationReport report = validate_file(bytes, "flipped");
  EXPECT_TRUE(report.readable);
  ASSERT_FALSE(report.violations.empty());
  EXPECT_EQ(report.violations.front().invariant, "checksum");
  EXPECT_EQ(report.violations.front().section, "octree");
}

INSTANTIATE_TEST_SUITE_P(Golden, Corruption, ::testing::ValuesIn(testing::kAllSamples),
                         [](const ::testing::TestParamInfo<Sample>& param) {
                           return testing::sample_name(param.param);
                         });

std::vector<std::uint8_t> golden_bytes(Sample sample) {
  return read_file_bytes(testing::golden_path(testing::golden_name(sample)));
}

// The golden file with its header's minor version (and header checksum) changed.
std::vector<std::uint8_t> golden_with_minor(Sample sample, std::uint16_t minor) {
  std::vector<std::uint8_t> bytes = golden_bytes(sample);
  FileHeader header = testing::header_of(bytes);
  header.version_minor = minor;
  testing::put_header(bytes, header);
  testing::refresh_header_checksum(bytes);
  return bytes;
}

std::uint32_t type_id(SectionType type) { return static_cast<std::uint32_t>(type); }

void drop_section(std::vector<SectionPayload>& sections, SectionType type) {
  std::erase_if(sections, [&](const SectionPayload& s) { return s.type == type_id(type); });
}

void set_flags(std::vector<SectionPayload>& sections, SectionType type, std::uint32_t flags) {
  for (SectionPayload& s : sections) {
    if (s.type == type_id(type)) s.flags = flags;
  }
}

std::uint64_t section_offset(const std::vector<std::uint8_t>& bytes, SectionType type) {
  const ContainerView view = parse_container(bytes, "offset");
  for (const SectionEntry& entry : view.sections) {
    if (entry.type == type_id(type)) return entry.offset;
  }
  ADD_FAILURE() << "no section " << section_name(type_id(type));
  return 0;
}

struct FileCase {
  const char* invariant;
  const char* what;
  std::function<std::vector<std::uint8_t>()> bytes;
};

const std::vector<FileCase>& file_cases() {
  static const std::vector<FileCase> cases = {
      {"trailing_bytes", "16 zero bytes after the last payload",
       [] {
         std::vector<std::uint8_t> bytes = golden_bytes(Sample::small);
         testing::insert_zeros(bytes, bytes.size(), 16);
         testing::refresh_header_checksum(bytes);
         return bytes;
       }},
      {"section_layout", "16 zero bytes before the last payload",
       [] {
         std::vector<std::uint8_t> bytes = golden_bytes(Sample::small);
         testing::insert_zeros(bytes, section_offset(bytes, SectionType::cells), 16);
         testing::refresh_header_checksum(bytes);
         return bytes;
       }},
      {"section_layout", "a surfel_batches section without elements",
       [] {
         return testing::rewrite_sections(golden_bytes(Sample::static_set), [](std::vector<SectionPayload>& sections) {
           sections.push_back(
               SectionPayload{type_id(SectionType::surfel_batches), kSectionRequired, sizeof(gpu::SurfelBatch), 0, {}});
         });
       }},
      {"section_flags", "probes not REQUIRED",
       [] {
         return testing::rewrite_sections(golden_bytes(Sample::small),
                                          [](std::vector<SectionPayload>& s) { set_flags(s, SectionType::probes, 0); });
       }},
      {"section_flags", "lighting_info REQUIRED",
       [] {
         return testing::rewrite_sections(golden_bytes(Sample::lighting), [](std::vector<SectionPayload>& s) {
           set_flags(s, SectionType::lighting_info, kSectionRequired);
         });
       }},
      {"section_flags", "a reserved flag bit",
       [] {
         return testing::rewrite_sections(golden_bytes(Sample::small),
                                          [](std::vector<SectionPayload>& s) { set_flags(s, SectionType::cells, 2); });
       }},
      {"format_version", "lighting sections in a 1.0 file", [] { return golden_with_minor(Sample::lighting, 0); }},
      {"format_version", "double-sided flags in a 1.1 file", [] { return golden_with_minor(Sample::double_sided, 1); }},
      {"format_version", "dynamic objects in a 1.2 file", [] { return golden_with_minor(Sample::dynamic, 2); }},
      {"format_version", "a 1.0 header of 80 bytes",
       [] {
         std::vector<std::uint8_t> bytes = golden_bytes(Sample::small);
         testing::insert_zeros(bytes, sizeof(FileHeader), 16);
         FileHeader header = testing::header_of(bytes);
         header.header_size += 16;
         testing::put_header(bytes, header);
         testing::refresh_header_checksum(bytes);
         return bytes;
       }},
      {"section_dependency", "leaf_queue_header without leaf_entries",
       [] {
         return testing::rewrite_sections(golden_bytes(Sample::small), [](std::vector<SectionPayload>& s) {
           drop_section(s, SectionType::leaf_entries);
         });
       }},
      {"section_dependency", "leaf_entries without leaf_queue_header",
       [] {
         return testing::rewrite_sections(golden_bytes(Sample::small), [](std::vector<SectionPayload>& s) {
           drop_section(s, SectionType::leaf_queue_header);
         });
       }},
  };
  return cases;
}

// The reader reads these files (nothing in them can be misread); the validator names what is wrong, as
// its first violation, and still calls the file readable (exit code 1, not 2).
TEST(FileLevel, ReadableButInvalidFilesNameTheirInvariant) {
  for (const FileCase& c : file_cases()) {
    const std::vector<std::uint8_t> bytes = c.bytes();
    EXPECT_NO_THROW(read_probes(bytes, c.what)) << c.what;
    const ValidationReport report = validate_file(bytes, c.what);
    EXPECT_TRUE(report.readable) << c.what;
    ASSERT_FALSE(report.violations.empty()) << c.what;
    EXPECT_EQ(report.violations.front().invariant, c.invariant)
        << c.what << ": " << format_violation(report.violations.front());
    if (std::getenv("PROBEBAKE_VERBOSE")) {
      std::printf("%s:\n", c.what);
      for (const Violation& v : report.violations) std::printf("  %s\n", format_violation(v).c_str());
    }
  }
}

TEST(FileLevel, EveryFileLevelInvariantHasACase) {
  std::set<std::string> covered;
  for (const FileCase& c : file_cases()) covered.insert(c.invariant);
  for (const char* id : {"format_version", "section_flags", "section_layout", "trailing_bytes", "section_dependency"}) {
    EXPECT_TRUE(covered.count(id)) << id;
  }
}

// The same trailing bytes, but not zero: the reader refuses them, naming where they are.
TEST(FileLevel, NonZeroTrailingBytesAreUnreadable) {
  std::vector<std::uint8_t> bytes = golden_bytes(Sample::static_set);
  testing::insert_zeros(bytes, bytes.size(), 16);
  bytes[bytes.size() - 5] = 0x2a;
  testing::refresh_header_checksum(bytes);
  EXPECT_TRUE(reader_refuses(bytes));
  const ValidationReport report = validate_file(bytes, "tail");
  EXPECT_FALSE(report.readable);
  ASSERT_EQ(report.violations.size(), 1u);
  EXPECT_NE(report.violations[0].message.find("after the last payload"), std::string::npos)
      << report.violations[0].message;
}

TEST(CorruptionRandom, GarbageIsUnreadable) {
  std::mt19937 rng(7);
  for (int round = 0; round < 2000; ++round) {
    std::vector<std::uint8_t> bytes(rng() % 512);
    for (std::uint8_t& byte : bytes) byte = static_cast<std::uint8_t>(rng());
    if (round % 2 == 0 && bytes.size() >= 8) std::memcpy(bytes.data(), kProbesContainer.magic, 8);
    EXPECT_TRUE(reader_refuses(bytes));
    EXPECT_FALSE(validate_file(bytes, "garbage").readable);
  }
}

} // namespace
} // namespace probebake::formats
