// The split bake (bake_parts.h): parts baked with any cell lists and thread counts merge into the bytes of
// the single-process bake; a merge refuses parts that miss a cell, bake a cell twice or come from other
// settings.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <string>

#include "bake_test_util.h"
#include "probebake/bake/bake_parts.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

// Four generated rooms (their walls hold sealed triangles) in a grid of 4^3 cells.
const scene::Scene& rooms() {
  static const scene::Scene s = load_generated(samples::rooms({.count = 4, .detail = 3, .seed = 5}), "split_rooms");
  return s;
}

bake::BakeSettings split_settings(int threads) {
  bake::BakeSettings s = test_settings();
  s.cell_depth = 2;
  s.threads = threads;
  return s;
}

// Cells k with k % parts == which, as a part of that many would bake them.
std::vector<std::int32_t> every_nth_cell(int depth, int parts, int which) {
  std::vector<std::int32_t> cells;
  const int n = formats::cells_per_axis(depth);
  for (int c = which; c < n * n * n; c += parts) cells.push_back(c);
  return cells;
}

std::string merge_error(std::span<const formats::BakePart> parts) {
  std::vector<std::string> names;
  for (std::size_t p = 0; p < parts.size(); ++p) names.push_back("part" + std::to_string(p));
  try {
    (void)bake::merge_parts(rooms(), split_settings(2), parts, names);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    return e.what();
  }
  return "";
}

std::vector<formats::BakePart> three_parts() {
  std::vector<formats::BakePart> parts;
  for (int which = 0; which < 3; ++which)
    parts.push_back(bake::bake_part(rooms(), split_settings(1), every_nth_cell(2, 3, which)));
  return parts;
}

TEST(SplitBake, MergedPartsAreTheSingleBakeByteForByte) {
  const bake::BakeResult single = bake::bake(rooms(), split_settings(2));
  ASSERT_GT(single.report.sealed_triangles, 0); // else the parts' work would not show in the file
  std::vector<formats::BakePart> parts;
  std::vector<std::string> names;
  std::size_t tested = 0, sealed = 0;
  for (formats::BakePart part : three_parts()) { // through the file format, as jobs hand them over
    part = formats::read_bake_part(formats::write_bake_part(part), "part");
    tested += part.sealed.size();
    sealed += std::size_t(std::accumulate(part.sealed.begin(), part.sealed.end(), 0));
    EXPECT_GT(part.sealed.size(), 0u);
    names.push_back("part" + std::to_string(parts.size()));
    parts.push_back(std::move(part));
  }
  EXPECT_EQ(tested, rooms().triangles.size());
  EXPECT_EQ(sealed, std::size_t(single.report.sealed_triangles));
  const bake::PrecomputedWork work = bake::merge_parts(rooms(), split_settings(2), parts, names);
  const bake::BakeResult merged = bake::bake(rooms(), split_settings(1), {}, &work);
  EXPECT_TRUE(formats::write_probes(merged.volume) == formats::write_probes(single.volume));
  bake::PrecomputedWork nothing_sealed = work; // the merge bakes with the parts' flags, not its own
  std::fill(nothing_sealed.sealed.begin(), nothing_sealed.sealed.end(), char(0));
  EXPECT_EQ(bake::bake(rooms(), split_settings(2), {}, &nothing_sealed).report.sealed_triangles, 0);
  std::printf("split bake: %zu triangles in 3 parts, %zu sealed; merged file %zu bytes, identical\n", tested, sealed,
              formats::write_probes(merged.volume).size());
}

TEST(SplitBake, MergeRefusesAMissingCellACellBakedTwiceAndAForeignPart) {
  std::vector<formats::BakePart> parts = three_parts();
  const std::string missing = merge_error(std::span(parts).first(2));
  EXPECT_NE(missing.find("no part bakes cell"), std::string::npos) << missing;

  std::vector<formats::BakePart> twice = parts;
  twice.push_back(parts[1]);
  const std::string duplicate = merge_error(twice);
  EXPECT_NE(duplicate.find("part3: cell 1 is also in part1"), std::string::npos) << duplicate;

  bake::BakeSettings other = split_settings(1);
  other.clearance = 0.3f;
  parts[2] = bake::bake_part(rooms(), other, every_nth_cell(2, 3, 2));
  const std::string foreign = merge_error(parts);
  EXPECT_NE(foreign.find("part2: baked from another scene or with other settings"), std::string::npos) << foreign;

  parts[2] = three_parts()[2];
  parts[2].sealed.pop_back();
  const std::string short_part = merge_error(parts);
  EXPECT_NE(short_part.find("part2: "), std::string::npos) << short_part;
}

TEST(SplitBake, ACellOutsideTheGridIsAUsageError) {
  try {
    (void)bake::bake_part(rooms(), split_settings(1), std::vector<std::int32_t>{3, 64});
    ADD_FAILURE() << "cell 64 of a 4^3 grid accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("cell 64 is outside the grid's 64 cells (4^3)"), std::string::npos)
        << e.what();
  }
}

} // namespace
} // namespace probebake::test
