// Bake parts (bake_part.h): round trip, every damaged byte refused, fields checked behind valid
// checksums, and the .probes and part readers each refusing the other's files.
#include <gtest/gtest.h>

#include <string>

#include "probebake/formats/bake_part.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"
#include "sample_volumes.h"

namespace probebake::formats {
namespace {

BakePart sample_part() {
  BakePart part;
  part.input_hash = 0x0123456789abcdefull;
  part.cell_depth = 2;
  part.scene_triangles = 40;
  part.cells = {1, 5, 9, 63};
  part.sealed = {0, 1, 0, 0, 1, 1, 0};
  return part;
}

std::string read_error(std::span<const std::uint8_t> bytes) {
  try {
    (void)read_bake_part(bytes, "part");
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    return e.what();
  }
  return "";
}

void expect_same(const BakePart& a, const BakePart& b) {
  EXPECT_EQ(a.input_hash, b.input_hash);
  EXPECT_EQ(a.cell_depth, b.cell_depth);
  EXPECT_EQ(a.scene_triangles, b.scene_triangles);
  EXPECT_EQ(a.cells, b.cells);
  EXPECT_EQ(a.sealed, b.sealed);
}

TEST(BakePartFile, RoundTripsAndRefusesEveryChangedByte) {
  const std::vector<std::uint8_t> bytes = write_bake_part(sample_part());
  expect_same(read_bake_part(bytes, "part"), sample_part());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    std::vector<std::uint8_t> damaged = bytes;
    damaged[i] ^= 0x10;
    EXPECT_NE(read_error(damaged), "") << "byte " << i;
  }
  for (std::size_t size = 0; size < bytes.size(); size += 7)
    EXPECT_NE(read_error(std::span(bytes).first(size)), "") << "cut at " << size;
}

// Written with valid checksums, so that only the part's own checks can refuse them.
TEST(BakePartFile, RefusesBadFieldsBehindValidChecksums) {
  const auto refused = [](void (*edit)(BakePart&), const char* expected) {
    BakePart part = sample_part();
    edit(part);
    const std::string error = read_error(write_bake_part(part));
    EXPECT_NE(error.find(expected), std::string::npos) << error;
  };
  refused([](BakePart& p) { p.cells = {5, 1}; }, "part_cells[1]: cells do not ascend");
  refused([](BakePart& p) { p.cells = {1, 64}; }, "cell 64 outside [0, 64)");
  refused([](BakePart& p) { p.cells = {-1}; }, "cell -1 outside");
  refused([](BakePart& p) { p.sealed[3] = 2; }, "part_sealed[3]: flag 2 is neither 0 nor 1");
  refused([](BakePart& p) { p.cell_depth = 9; }, "cell depth 9 outside");
  refused([](BakePart& p) { p.scene_triangles = 3; }, "7 tested of 3 triangles");
}

TEST(BakePartFile, NeitherReaderTakesTheOthersFile) {
  const std::string part_error = read_error(write_probes(testing::make_sample(testing::Sample::small)));
  EXPECT_NE(part_error.find("not a probebake bake part (bad magic)"), std::string::npos) << part_error;
  try {
    (void)read_probes(write_bake_part(sample_part()), "part");
    ADD_FAILURE() << "a part read as a .probes file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a .probes file (bad magic)"), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace probebake::formats
