// Spherical lattices: Fibonacci against the thesis's eq. 2.3-2.4, exact counts, equal areas of EQ(2, N).
#include "probebake/common/lattice.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <numeric>

namespace pb = probebake;
using pb::Lattice;

namespace {

constexpr double pi = 3.14159265358979323846;
constexpr Lattice all_lattices[] = {Lattice::fibonacci, Lattice::latlong, Lattice::equal_area};

// Polar angle in [0, pi] and azimuth in [0, 2 pi) of a unit direction (+Z is the pole).
double polar_angle(glm::dvec3 d) { return std::acos(std::clamp(d.z, -1.0, 1.0)); }
double azimuth(glm::dvec3 d) {
  const double phi = std::atan2(d.y, d.x);
  return phi < 0.0 ? phi + 2.0 * pi : phi;
}

// Whether phi lies in [start, start + width] modulo 2 pi, with a small slack for float directions.
bool azimuth_in_sector(double phi, double start, double width, double slack) {
  const double offset = std::fmod(std::fmod(phi - start, 2.0 * pi) + 2.0 * pi, 2.0 * pi);
  return offset <= width + slack || offset >= 2.0 * pi - slack;
}

} // namespace

TEST(Lattice, FibonacciEqualsThesisEquations) {
  const double g = pi * (3.0 - std::sqrt(5.0));
  for (int n : {1, 2, 3, 7, 64, 200, 1000, 4097}) {
    const auto points = pb::lattice_directions(Lattice::fibonacci, n);
    ASSERT_EQ(points.size(), static_cast<std::size_t>(n));
    for (int i = 1; i <= n; ++i) { // 1-based as in eq. 2.3
      const double z = 1.0 - (2.0 / n) * (i - 0.5);
      const double phi = g * (i - 0.5);
      const glm::dvec3 expected(std::sqrt(1.0 - z * z) * std::cos(phi), std::sqrt(1.0 - z * z) * std::sin(phi), z);
      const glm::dvec3 actual(points[static_cast<std::size_t>(i - 1)]);
      EXPECT_LT(glm::length(actual - expected), 1e-6) << "n=" << n << " i=" << i;
    }
  }
}

TEST(Lattice, ExactlyNUnitDirections) {
  for (Lattice lattice : all_lattices) {
    for (int n = 1; n <= 500; ++n) {
      const auto points = pb::lattice_directions(lattice, n);
      ASSERT_EQ(points.size(), static_cast<std::size_t>(n)) << pb::lattice_name(lattice) << " n=" << n;
      for (const glm::vec3& p : points) ASSERT_NEAR(glm::length(p), 1.0f, 1e-6f) << pb::lattice_name(lattice);
    }
  }
}

TEST(Lattice, NonPositiveCountGivesNothing) {
  for (Lattice lattice : all_lattices) {
    EXPECT_TRUE(pb::lattice_directions(lattice, 0).empty());
    EXPECT_TRUE(pb::lattice_directions(lattice, -3).empty());
  }
  EXPECT_EQ(pb::equal_area_partition(0).region_count, 0);
}

TEST(Lattice, SingleDirectionMatchesList) {
  for (Lattice lattice : all_lattices) {
    for (int n : {1, 2, 3, 5, 17, 100, 333}) {
      const auto points = pb::lattice_directions(lattice, n);
      for (int i = 0; i < n; ++i) {
        EXPECT_EQ(pb::lattice_direction(lattice, i, n), points[static_cast<std::size_t>(i)])
            << pb::lattice_name(lattice) << " n=" << n << " i=" << i;
      }
    }
  }
}

TEST(Lattice, Deterministic) {
  for (Lattice lattice : all_lattices) {
    EXPECT_EQ(pb::lattice_directions(lattice, 777), pb::lattice_directions(lattice, 777));
  }
}

// A well-spread lattice has its centroid near the origin. Bound: 1e-3 for n >= 1000. Fibonacci's z is
// symmetric and its x/y sums fall off like 1/n; latlong is off by at most one unpaired point (<= 1/n);
// EQ(2, N) is symmetric up to rounding of the collar counts.
TEST(Lattice, MeanDirectionNearZero) {
  for (Lattice lattice : all_lattices) {
    for (int n : {1000, 1001, 4096, 9999}) {
      const auto points = pb::lattice_directions(lattice, n);
      glm::dvec3 sum(0.0);
      for (const glm::vec3& p : points) sum += glm::dvec3(p);
      EXPECT_LT(glm::length(sum / static_cast<double>(n)), 1e-3) << pb::lattice_name(lattice) << " n=" << n;
    }
  }
}

TEST(Lattice, LatlongIsTheThesisGridWhenItCan) {
  const auto points = pb::lattice_directions(Lattice::latlong, 200); // 10 parallels x 20 meridians
  for (int row = 0; row < 10; ++row) {
    for (int column = 0; column < 20; ++column) {
      const glm::dvec3 p(points[static_cast<std::size_t>(row * 20 + column)]);
      EXPECT_NEAR(polar_angle(p), (row + 0.5) * pi / 10.0, 1e-6);
      EXPECT_NEAR(azimuth(p), (column + 0.5) * 2.0 * pi / 20.0, 1e-6);
    }
  }
}

TEST(Lattice, NamesRoundTrip) {
  for (Lattice lattice : all_lattices) EXPECT_EQ(pb::parse_lattice(pb::lattice_name(lattice)), lattice);
  EXPECT_EQ(pb::lattice_name(Lattice::equal_area), "equal-area");
  EXPECT_FALSE(pb::parse_lattice("equal_area").has_value());
  EXPECT_FALSE(pb::parse_lattice("").has_value());
  EXPECT_FALSE(pb::parse_lattice("Fibonacci").has_value());
}

TEST(EqualAreaPartition, StructureIsConsistent) {
  for (int n = 1; n <= 2000; ++n) {
    const pb::EqualAreaPartition partition = pb::equal_area_partition(n);
    const auto& counts = partition.regions_per_zone;
    ASSERT_EQ(partition.region_count, n);
    ASSERT_EQ(partition.zone_boundaries.size(), counts.size() + 1);
    ASSERT_EQ(partition.zone_longitude_offsets.size(), counts.size());
    EXPECT_EQ(std::accumulate(counts.begin(), counts.end(), 0), n);
    EXPECT_EQ(counts.front(), 1);
    EXPECT_EQ(counts.back(), 1);
    EXPECT_EQ(partition.zone_boundaries.front(), 0.0);
    EXPECT_EQ(partition.zone_boundaries.back(), pi);
    for (std::size_t z = 0; z + 1 < partition.zone_boundaries.size(); ++z) {
      EXPECT_LT(partition.zone_boundaries[z], partition.zone_boundaries[z + 1]) << "n=" << n;
    }
  }
}

TEST(EqualAreaPartition, EveryRegionHasAreaFourPiOverN) {
  for (int n = 1; n <= 2000; ++n) {
    const pb::EqualAreaPartition partition = pb::equal_area_partition(n);
    const double expected = 4.0 * pi / n;
    for (std::size_t z = 0; z < partition.regions_per_zone.size(); ++z) {
      const double top = partition.zone_boundaries[z];
      const double bottom = partition.zone_boundaries[z + 1];
      const double zone_area = 2.0 * pi * (std::cos(top) - std::cos(bottom));
      const double region_area = zone_area / partition.regions_per_zone[z];
      ASSERT_NEAR(region_area, expected, 1e-9) << "n=" << n << " zone=" << z;
    }
  }
}

TEST(EqualAreaPartition, CentresLieInsideTheirRegions) {
  for (int n : {1, 2, 3, 4, 5, 6, 10, 31, 128, 500, 1999, 2000}) {
    const pb::EqualAreaPartition partition = pb::equal_area_partition(n);
    const auto centres = pb::lattice_directions(Lattice::equal_area, n);
    std::size_t index = 0;
    for (std::size_t z = 0; z < partition.regions_per_zone.size(); ++z) {
      const int m = partition.regions_per_zone[z];
      for (int k = 0; k < m; ++k, ++index) {
        const glm::dvec3 c(centres[index]);
        const double theta = polar_angle(c);
        EXPECT_GE(theta, partition.zone_boundaries[z] - 1e-6) << "n=" << n << " zone=" << z;
        EXPECT_LE(theta, partition.zone_boundaries[z + 1] + 1e-6) << "n=" << n << " zone=" << z;
        const bool is_cap = (z == 0 || z + 1 == partition.regions_per_zone.size());
        if (is_cap) continue; // a cap has no azimuth range; its centre is the pole
        const double width = 2.0 * pi / m;
        const double start = partition.zone_longitude_offsets[z] + k * width;
        EXPECT_TRUE(azimuth_in_sector(azimuth(c), start, width, 1e-6)) << "n=" << n << " zone=" << z << " k=" << k;
      }
    }
    EXPECT_EQ(index, static_cast<std::size_t>(n));
  }
}
