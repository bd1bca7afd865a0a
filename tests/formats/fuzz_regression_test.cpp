// Every crash, timeout or out-of-memory input the formats fuzzers found (tests/data/fuzz-regressions/
// probes_reader and validator), their seeds (tests/data/fuzz/...) and the golden files, through the same
// entry functions as the libFuzzer targets, so that a fixed bug stays fixed in the ordinary gcc build.
#include "fuzz_entries.h"
#include "fuzz_inputs.h"

namespace probebake::fuzz {
namespace {

const std::filesystem::path kData = PROBEBAKE_TEST_DATA;

std::vector<std::filesystem::path> formats_inputs() {
  return files_in({kData / "golden", kData / "fuzz" / "probes_reader", kData / "fuzz" / "validator",
                   kData / "fuzz-regressions" / "probes_reader", kData / "fuzz-regressions" / "validator"});
}

TEST(FuzzRegression, ProbesReader) {
  EXPECT_GE(replay(formats_inputs(), fuzz_one_probes_reader), 4u); // the golden files at least
}

TEST(FuzzRegression, Validator) { EXPECT_GE(replay(formats_inputs(), fuzz_one_validator), 4u); }

// Short inputs that reach every early exit of the container checks.
TEST(FuzzRegression, PrefixesOfAGoldenFile) {
  const auto golden = files_in({kData / "golden"});
  ASSERT_FALSE(golden.empty());
  std::ifstream in(golden.front(), std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (std::size_t size = 0; size <= std::min<std::size_t>(bytes.size(), 512); ++size) {
    EXPECT_NO_THROW(fuzz_one_probes_reader(bytes.data(), size)) << size;
    EXPECT_NO_THROW(fuzz_one_validator(bytes.data(), size)) << size;
  }
}

} // namespace
} // namespace probebake::fuzz
