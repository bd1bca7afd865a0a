// Golden .probes files, one set per format version (tests/data/golden/v<major>_<minor>_*.probes):
// they read back and re-write byte-identical, validate clean, and the sample builder still produces
// exactly their bytes. Regenerate after an intended change (new version!) with
//   PROBEBAKE_REGENERATE_GOLDEN=1 formats_file_test --gtest_filter='*Golden*'
#include <cstdlib>

#include <gtest/gtest.h>

#include "probebake/formats/format_version.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "sample_volumes.h"
#include "test_bytes.h"

namespace probebake::formats {
namespace {

using testing::Sample;

class Golden : public ::testing::TestWithParam<Sample> {};

TEST_P(Golden, BuilderProducesTheGoldenBytes) {
  const std::filesystem::path path = testing::golden_path(testing::golden_name(GetParam()));
  const std::vector<std::uint8_t> built = write_probes(testing::make_sample(GetParam()));
  if (std::getenv("PROBEBAKE_REGENERATE_GOLDEN") != nullptr) {
    write_probes_file(path, testing::make_sample(GetParam()));
    GTEST_SKIP() << "regenerated " << path;
  }
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  EXPECT_EQ(read_file_bytes(path), built) << "the builder or the writer changed; see the comment at the top";
}

TEST_P(Golden, ReadsBackAndRewritesIdentically) {
  const std::filesystem::path path = testing::golden_path(testing::golden_name(GetParam()));
  const std::vector<std::uint8_t> bytes = read_file_bytes(path);
  const ProbeVolume volume = read_probes(bytes, path.string());
  EXPECT_EQ(write_probes(volume), bytes);
  const ValidationReport report = validate_file(bytes, path.string());
  EXPECT_TRUE(report.valid()) << (report.violations.empty() ? "" : format_violation(report.violations[0]));
}

TEST_P(Golden, FileNameCarriesTheVersion) {
  const std::vector<std::uint8_t> bytes = read_file_bytes(testing::golden_path(testing::golden_name(GetParam())));
  const FileHeader header = testing::header_of(bytes);
  std::string prefix = "v"; // built piecewise: GCC 12 -O3 warns falsely (-Wrestrict) on "v" + std::string&&
  prefix += std::to_string(header.version_major);
  prefix += '_';
  prefix += std::to_string(header.version_minor);
  prefix += '_';
  EXPECT_EQ(std::string(testing::golden_name(GetParam())).rfind(prefix, 0), 0u);
  EXPECT_EQ(header.version_major, kFormatVersionMajor);
}

// Golden files of versions the builder no longer writes (the cells sample is 1.7 now): still read, valid,
// and written back as their own version, byte for byte.
TEST(GoldenOlder, A16CellFileReadsValidatesAndRewritesAs16) {
  const std::filesystem::path path = testing::golden_path("v1_6_cells.probes");
  const std::vector<std::uint8_t> bytes = read_file_bytes(path);
  const ProbeVolume volume = read_probes(bytes, path.string());
  EXPECT_FALSE(volume.cell_checksums.empty());
  EXPECT_TRUE(volume.cell_global_checksums.empty());
  EXPECT_EQ(write_probes(volume), bytes);
  const ValidationReport report = validate_file(bytes, path.string());
  EXPECT_TRUE(report.valid()) << (report.violations.empty() ? "" : format_violation(report.violations[0]));
  EXPECT_EQ(testing::header_of(bytes).version_minor, 6);
}

INSTANTIATE_TEST_SUITE_P(Samples, Golden, ::testing::ValuesIn(testing::kAllSamples),
                         [](const ::testing::TestParamInfo<Sample>& param) {
                           return testing::sample_name(param.param);
                         });

} // namespace
} // namespace probebake::formats
