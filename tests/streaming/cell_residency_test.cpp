// The cell streaming policy (streaming/cell_residency.h) over thousands of random camera moves and budget
// changes, each update checked against an independent statement of the policy; the camera path reader on
// good and hostile text.
#include <algorithm>
#include <cstdio>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include "probebake/formats/error.h"
#include "probebake/streaming/camera_path.h"
#include "probebake/streaming/cell_residency.h"

namespace probebake::test {
namespace {

using streaming::CellFootprint;
using streaming::CellResidency;

// An n^3 grid of unit cubes with bytes between 1 and 1000 (a few cells larger than most budgets).
std::vector<CellFootprint> grid_cells(int n, std::mt19937& rng) {
  std::uniform_int_distribution<int> bytes(1, 1000);
  std::vector<CellFootprint> cells;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const glm::vec3 corner{float(x), float(y), float(z)};
        cells.push_back(
            {x + n * (y + n * z), corner, corner + 1.0f, std::uint64_t(bytes(rng)) * (rng() % 50 == 0 ? 20 : 1)});
      }
  return cells;
}

// The policy restated: a cell within the radius, or resident before and within radius + margin, is wanted
// exactly when its bytes fit beside the wanted cells nearer than it (ties by index); no other cell is, nor
// a refused one.
void expect_policy(const CellResidency& r, glm::vec3 camera, float radius, float margin,
                   const std::vector<std::uint8_t>& before, const std::vector<std::uint8_t>& wanted) {
  const auto cells = r.cells();
  const auto distance = [&](std::size_t k) { return streaming::distance_to_box(camera, cells[k].min, cells[k].max); };
  for (std::size_t k = 0; k < cells.size(); ++k) {
    if (r.refused(k) || (distance(k) > radius && !(before[k] != 0 && distance(k) <= radius + margin))) {
      ASSERT_EQ(wanted[k], 0) << "cell " << k << " is outside the radius";
      continue;
    }
    std::uint64_t nearer = 0;
    for (std::size_t j = 0; j < cells.size(); ++j) {
      const bool closer = distance(j) < distance(k) || (distance(j) == distance(k) && j < k);
      if (closer && wanted[j] != 0) nearer += cells[j].bytes;
    }
    ASSERT_EQ(wanted[k] != 0, nearer + cells[k].bytes <= r.budget()) << "cell " << k;
  }
}

TEST(CellResidency, ThousandsOfRandomMovesKeepTheBudgetAndThePolicy) {
  std::mt19937 rng(15);
  CellResidency residency(grid_cells(6, rng));
  std::uniform_real_distribution<float> step(-0.7f, 0.7f), unit(0.0f, 1.0f);
  glm::vec3 camera(3.0f);
  std::uint64_t largest_resident = 0;
  std::size_t loads = 0, drops = 0, refused = 0;
  for (int frame = 0; frame < 4000; ++frame) {
    camera = glm::clamp(camera + glm::vec3(step(rng), step(rng), step(rng)), glm::vec3(-1.0f), glm::vec3(7.0f));
    if (frame >= 3000 && frame % 40 == 0 && residency.resident_count() > 0) { // a cell found damaged on load
      std::size_t k = rng() % residency.cells().size();
      while (!residency.resident(k)) k = (k + 1) % residency.cells().size();
      residency.refuse(k);
      ++refused;
    }
    if (frame % 97 == 0) residency.set_budget(std::uint64_t(unit(rng) * 12000.0f));
    residency.set_max_load_bytes(frame < 2000 ? 0 : 1500);
    const float margin = frame % 1000 < 500 ? 0.0f : 0.6f;
    residency.set_keep_margin(margin);
    const float radius = 0.5f + 2.5f * unit(rng);
    std::vector<std::uint8_t> before(residency.cells().size());
    for (std::size_t k = 0; k < before.size(); ++k) before[k] = residency.resident(k);
    const streaming::ResidencyChanges changes = residency.update(camera, radius);

    ASSERT_LE(residency.resident_bytes(), residency.budget()) << "frame " << frame;
    // wanted() after the update equals what the update wanted: a kept cell it dropped did not fit, and
    // skipping a cell that does not fit changes nothing for the others.
    std::vector<std::uint8_t> wanted(before.size(), 0);
    for (std::size_t k : residency.wanted(camera, radius)) wanted[k] = 1;
    expect_policy(residency, camera, radius, margin, before, wanted);
    std::uint64_t bytes = 0, loaded = 0;
    std::size_t count = 0;
    for (std::size_t k = 0; k < before.size(); ++k) {
      if (residency.resident(k)) {
        ASSERT_EQ(wanted[k], 1) << "frame " << frame << ": resident cell " << k << " is not wanted";
        bytes += residency.cells()[k].bytes;
        ++count;
      }
    }
    ASSERT_EQ(bytes, residency.resident_bytes());
    ASSERT_EQ(count, residency.resident_count());
    for (std::size_t k : changes.drops) ASSERT_TRUE(before[k] && !residency.resident(k));
    for (std::size_t k : changes.loads) {
      ASSERT_TRUE(!before[k] && residency.resident(k));
      loaded += residency.cells()[k].bytes;
    }
    ASSERT_EQ(loaded, changes.loaded_bytes);
    std::size_t missing = 0;
    for (std::size_t k = 0; k < before.size(); ++k) missing += wanted[k] != 0 && !residency.resident(k);
    ASSERT_EQ(missing, changes.waiting);
    if (frame < 2000) {
      ASSERT_EQ(changes.waiting, 0u) << "without a load limit every wanted cell loads at once";
    } else if (changes.loads.size() > 1) {
      ASSERT_LE(changes.loaded_bytes, 1500u) << "frame " << frame;
    }
    // Loads come nearest first.
    for (std::size_t i = 1; i < changes.loads.size(); ++i) {
      const auto& c = residency.cells();
      ASSERT_LE(streaming::distance_to_box(camera, c[changes.loads[i - 1]].min, c[changes.loads[i - 1]].max),
                streaming::distance_to_box(camera, c[changes.loads[i]].min, c[changes.loads[i]].max));
    }
    largest_resident = std::max(largest_resident, residency.resident_bytes());
    loads += changes.loads.size();
    drops += changes.drops.size();
  }
  std::printf(
      "[residency] 4000 frames, 216 cells: %zu loads, %zu drops, %zu cells refused, largest resident %llu bytes\n",
      loads, drops, refused, static_cast<unsigned long long>(largest_resident));
  EXPECT_GT(refused, 10u);
  EXPECT_GT(loads, 1000u);
  EXPECT_GT(drops, 1000u);
}

TEST(CellResidency, AStillCameraSettlesAndThenChangesNothing) {
  std::mt19937 rng(3);
  CellResidency residency(grid_cells(5, rng));
  residency.set_budget(8000);
  residency.set_max_load_bytes(600);
  const glm::vec3 camera(2.5f);
  int updates = 0;
  while (residency.update(camera, 2.0f).waiting != 0) ASSERT_LT(++updates, 200);
  EXPECT_GT(updates, 1); // the limit spread the loads over several updates
  const std::vector<std::size_t> wanted = residency.wanted(camera, 2.0f);
  EXPECT_EQ(residency.resident_count(), wanted.size());
  for (int i = 0; i < 3; ++i) {
    const auto again = residency.update(camera, 2.0f);
    EXPECT_TRUE(again.loads.empty() && again.drops.empty());
  }
  residency.set_budget(0);
  const auto emptied = residency.update(camera, 2.0f);
  EXPECT_EQ(emptied.drops.size(), wanted.size());
  EXPECT_EQ(residency.resident_bytes(), 0u);
}

// A camera stepping back and forth across the edge of the radius: without a keep margin the cell at the edge
// is dropped and loaded again every step; with one it stays.
TEST(CellResidency, AKeepMarginStopsReloadsAtTheEdgeOfTheRadius) {
  std::vector<CellFootprint> cells;
  for (int x = 0; x < 4; ++x)
    cells.push_back({x, glm::vec3(float(x), 0.0f, 0.0f), glm::vec3(float(x) + 1.0f, 1.0f, 1.0f), 100});
  for (const float margin : {0.0f, 0.5f}) {
    CellResidency residency(cells);
    residency.set_budget(1000);
    residency.set_keep_margin(margin);
    int loads = 0; // after the first step, which loads cells 0 and 1
    for (int step = 0; step < 20; ++step) {
      const glm::vec3 camera(step % 2 == 0 ? 0.9f : 1.1f, 0.5f, 0.5f); // cell 2 starts at x = 2: 1.1 and 0.9 m away
      const auto changes = residency.update(camera, 1.0f);
      if (step > 0) loads += int(changes.loads.size());
    }
    if (margin == 0.0f) {
      EXPECT_EQ(loads, 10) << "cell 2 comes and goes every other step";
    } else {
      EXPECT_EQ(loads, 1) << "cell 2 loads once and is kept within radius + margin";
    }
  }
}

TEST(CellResidency, ACellLargerThanTheBudgetBlocksNothingBehindIt) {
  std::vector<CellFootprint> cells = {{0, glm::vec3(0.0f), glm::vec3(1.0f), 5000},
                                      {1, glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(2.0f, 1.0f, 1.0f), 100}};
  CellResidency residency(cells);
  residency.set_budget(1000);
  const auto changes = residency.update(glm::vec3(0.5f), 10.0f);
  ASSERT_EQ(changes.loads.size(), 1u);
  EXPECT_EQ(changes.loads[0], 1u);
  EXPECT_TRUE(residency.update(glm::vec3(NAN), 10.0f).drops.size() == 1) << "a non-finite camera wants nothing";
}

// A refused cell (its bytes on disk damaged) gives its budget back and is never wanted again; its room goes
// to the next cell in distance order.
TEST(CellResidency, ARefusedCellIsNeverWantedAgainAndGivesItsRoomToTheNext) {
  std::vector<CellFootprint> cells;
  for (int x = 0; x < 3; ++x)
    cells.push_back({x, glm::vec3(float(x), 0.0f, 0.0f), glm::vec3(float(x + 1), 1.0f, 1.0f), 100});
  CellResidency residency(cells);
  residency.set_budget(200);
  const auto first = residency.update(glm::vec3(0.5f), 10.0f);
  ASSERT_EQ(first.loads, (std::vector<std::size_t>{0, 1}));
  residency.refuse(0);
  EXPECT_FALSE(residency.resident(0));
  EXPECT_TRUE(residency.refused(0));
  EXPECT_EQ(residency.resident_bytes(), 100u);
  const auto next = residency.update(glm::vec3(0.5f), 10.0f);
  EXPECT_EQ(next.loads, (std::vector<std::size_t>{2}));
  EXPECT_TRUE(next.drops.empty());
  EXPECT_EQ(residency.wanted(glm::vec3(0.5f), 10.0f), (std::vector<std::size_t>{1, 2}));
  EXPECT_TRUE(residency.update(glm::vec3(0.5f), 10.0f).loads.empty());
}

// most_resident: an analytic case, then random sets against every subset within the budget. The fractional
// knapsack bounds the best whole-cell choice from above, and by less than its largest count.
TEST(CellResidency, MostResidentBoundsEveryChoiceWithinTheBudget) {
  const std::vector<CellFootprint> three{{0, {}, {}, 10}, {1, {}, {}, 20}, {2, {}, {}, 30}, {3, {}, {}, 0}};
  const std::vector<std::uint64_t> counts{5, 30, 9, 7};
  // Densest first: cell 1 (30 in 20 B), cell 0 (5 in 10 B), then 20 of cell 2's 30 B (6 of 9); cell 3 is free.
  EXPECT_EQ(streaming::most_resident(three, counts, 50), 30u + 5u + 6u + 7u);
  EXPECT_EQ(streaming::most_resident(three, counts, 0), 7u);
  EXPECT_EQ(streaming::most_resident(three, counts, 1000), 51u);

  std::mt19937 rng(11);
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 1 + int(rng() % 12);
    std::vector<CellFootprint> cells;
    std::vector<std::uint64_t> c;
    std::uint64_t largest = 0;
    for (int k = 0; k < n; ++k) {
      cells.push_back({k, {}, {}, rng() % 8 == 0 ? 0u : 1u + rng() % 100});
      c.push_back(rng() % 50);
      largest = std::max(largest, c.back());
    }
    const std::uint64_t budget = rng() % 300;
    std::uint64_t best = 0;
    for (std::uint32_t subset = 0; subset < (1u << n); ++subset) {
      std::uint64_t bytes = 0, count = 0;
      for (int k = 0; k < n; ++k)
        if (subset & (1u << k)) bytes += cells[std::size_t(k)].bytes, count += c[std::size_t(k)];
      if (bytes <= budget) best = std::max(best, count);
    }
    const std::uint64_t bound = streaming::most_resident(cells, c, budget);
    ASSERT_GE(bound, best) << "trial " << trial;
    ASSERT_LE(bound, best + largest) << "trial " << trial;
  }
}

TEST(CameraPath, ParsesRowsAndRefusesHostileText) {
  const auto path = streaming::parse_camera_path("frame,x,y,z\r\n0, 1.5,2,-3\n\n7,0,0,1e3\n", "p.csv");
  ASSERT_EQ(path.size(), 2u);
  EXPECT_EQ(path[1].frame, 7);
  EXPECT_EQ(path[0].position, glm::vec3(1.5f, 2.0f, -3.0f));
  EXPECT_EQ(path[1].position.z, 1000.0f);
  const std::pair<const char*, const char*> bad[] = {
      {"", "p.csv:0: empty file"},
      {"frame,x,y\n", "p.csv:1: expected 4"},
      {"f,x,y,z\n0,0,0,0\n", "p.csv:1: the header"},
      {"frame,x,y,z\n", "no rows"},
      {"frame,x,y,z\n0,0,0,nan\n", "p.csv:2: coordinate 'nan'"},
      {"frame,x,y,z\n0,0,0,1e39\n", "p.csv:2: coordinate '1e39'"},
      {"frame,x,y,z\n1,0,0,0\n1,0,0,0\n", "p.csv:3: frames must increase"},
      {"frame,x,y,z\n0.5,0,0,0\n", "p.csv:2: frame '0.5'"},
      {"frame,x,y,z\n0,0,0,0,0\n", "p.csv:2: expected 4"},
      {"frame,x,y,z\n0,,0,0\n", "p.csv:2: coordinate ''"},
  };
  for (const auto& [text, message] : bad) {
    try {
      streaming::parse_camera_path(text, "p.csv");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::input);
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
}

} // namespace
} // namespace probebake::test
