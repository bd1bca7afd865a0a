// Untrusted bytes (meshoptimizer / NanoVDB style): every strict prefix of a golden file is refused as
// unreadable, and every single-byte change (XOR 0x01 and XOR 0xFF at every offset) is detected by both
// the reader and the validator.
#include <cstdio>
#include <cstring>
#include <random>

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
  std::vector<std::uint8_t> golden() const { return read_file_bytes(testing::golden_path(testing::golden_name(GetParam()))); }
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
                         [](const ::testing::TestParamInfo<Sample>& param) { return testing::sample_name(param.param); });

TEST(CorruptionRandom, GarbageIsUnreadable) {
  std::mt19937 rng(7);
  for (int round = 0; round < 2000; ++round) {
    std::vector<std::uint8_t> bytes(rng() % 512);
    for (std::uint8_t& byte : bytes) byte = static_cast<std::uint8_t>(rng());
    if (round % 2 == 0 && bytes.size() >= 8) std::memcpy(bytes.data(), kProbesMagic, 8);
    EXPECT_TRUE(reader_refuses(bytes));
    EXPECT_FALSE(validate_file(bytes, "garbage").readable);
  }
}

} // namespace
} // namespace probebake::formats
