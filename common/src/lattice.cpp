// Spherical lattices for surfel placement.
//  - Fibonacci and latitude-longitude lattices: P. Fjellstedt, M. Antoniev, "Improving Probe and Surfel
//    Placement for Dynamic Diffuse Global Illumination", master's thesis, Lund University 2024, §2.4,
//    eq. 2.3-2.4 (shared/papers/octree-probe-surfel-placement-ddgi-thesis.txt).
//  - Recursive zonal equal-area partition EQ(2, N): P. Leopardi, "A partition of the unit sphere into
//    regions of equal area and small diameter", ETNA 25 (2006) 309-327, as used for deterministic
//    directions in the layered-depth-maps GI paper §3.2 (shared/papers/layered-depth-maps-gi.txt).
//    The steps mirror Leopardi's EQSP toolbox (polar_colat, num_collars, ideal_region_list,
//    round_to_naturals, cap_colats, circle_offset) restricted to the 2-sphere.
#include "probebake/common/lattice.h"

#include "probebake/common/enum_names.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numeric>

namespace probebake {
namespace {

constexpr double pi = 3.14159265358979323846;
constexpr double sphere_area = 4.0 * pi;

glm::vec3 from_polar(double theta, double phi) {
  const double s = std::sin(theta);
  return glm::vec3(glm::dvec3(s * std::cos(phi), s * std::sin(phi), std::cos(theta)));
}

// ---- Fibonacci (thesis eq. 2.3-2.4) ----

glm::vec3 fibonacci_direction(int i, int n) {
  const double golden_angle = pi * (3.0 - std::sqrt(5.0));
  const double k = static_cast<double>(i) + 0.5; // the thesis's (i - 1/2) with 1-based i
  const double z = 1.0 - (2.0 / static_cast<double>(n)) * k;
  const double phi = golden_angle * k;
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return glm::vec3(glm::dvec3(r * std::cos(phi), r * std::sin(phi), z));
}

// ---- Latitude-longitude ----

int latlong_parallels(int n) {
  return std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(n) / 2.0))));
}

// Rank of parallel j by closeness to the equator, north before south on ties, so the n mod p extra points
// go to the longest rows in north/south pairs (keeps the lattice balanced).
int equator_rank(int j, int parallels) {
  const int twice_distance = std::abs(2 * j - (parallels - 1));
  const int south = (2 * j > parallels - 1) ? 1 : 0;
  return std::max(0, twice_distance - 1 + south);
}

int latlong_row_count(int j, int n) {
  const int parallels = latlong_parallels(n);
  const int extra = equator_rank(j, parallels) < n % parallels ? 1 : 0;
  return n / parallels + extra;
}

glm::vec3 latlong_point(int row, int column, int row_count, int parallels) {
  const double theta = (row + 0.5) * pi / parallels;
  const double phi = (column + 0.5) * 2.0 * pi / row_count;
  return from_polar(theta, phi);
}

glm::vec3 latlong_direction(int i, int n) {
  const int parallels = latlong_parallels(n);
  for (int row = 0; row < parallels; ++row) {
    const int count = latlong_row_count(row, n);
    if (i < count) return latlong_point(row, i, count, parallels);
    i -= count;
  }
  assert(false && "latlong_direction: index out of range");
  return glm::vec3(0.0f, 0.0f, 1.0f);
}

std::vector<glm::vec3> latlong_directions(int n) {
  std::vector<glm::vec3> out;
  out.reserve(static_cast<std::size_t>(n));
  const int parallels = latlong_parallels(n);
  for (int row = 0; row < parallels; ++row) {
    const int count = latlong_row_count(row, n);
    for (int column = 0; column < count; ++column) out.push_back(latlong_point(row, column, count, parallels));
  }
  return out;
}

// ---- Equal-area partition EQ(2, N) ----

double cap_area(double theta) {
  const double s = std::sin(theta / 2.0);
  return sphere_area * s * s;
}

// Polar angle of the cap with the given area; the southern half is computed from the complement so that
// caps near the south pole keep full relative precision.
double cap_colatitude(double area) {
  if (area <= sphere_area / 2.0) return 2.0 * std::asin(std::sqrt(area / sphere_area));
  const double rest = std::max(0.0, sphere_area - area);
  return pi - 2.0 * std::asin(std::sqrt(rest / sphere_area));
}

int collar_count(int n, double polar_cap, double region_area) {
  if (n <= 2) return 0;
  const double ideal_collar_angle = std::sqrt(region_area);
  return std::max(1, static_cast<int>(std::lround((pi - 2.0 * polar_cap) / ideal_collar_angle)));
}

// Leopardi's ideal_region_list + round_to_naturals: regions per zone (caps included), summing to n.
std::vector<int> zone_region_counts(int n, double polar_cap, int collars, double region_area) {
  std::vector<double> ideal(static_cast<std::size_t>(collars) + 2, 1.0);
  const double collar_angle = collars > 0 ? (pi - 2.0 * polar_cap) / collars : 0.0;
  for (int c = 1; c <= collars; ++c) {
    const double top = polar_cap + (c - 1) * collar_angle;
    const double bottom = polar_cap + c * collar_angle;
    ideal[static_cast<std::size_t>(c)] = (cap_area(bottom) - cap_area(top)) / region_area;
  }
  std::vector<int> counts(ideal.size());
  double discrepancy = 0.0;
  for (std::size_t z = 0; z < ideal.size(); ++z) {
    counts[z] = static_cast<int>(std::lround(ideal[z] + discrepancy));
    discrepancy += ideal[z] - counts[z];
  }
  assert(std::accumulate(counts.begin(), counts.end(), 0) == n);
  (void)n;
  return counts;
}

// Leopardi's circle_offset (without the extra twist), in whole turns: rotates the next collar so that its
// centres fall between those of the previous one.
double circle_offset(int top_count, int bottom_count) {
  const double top = top_count;
  const double bottom = bottom_count;
  return (1.0 / bottom - 1.0 / top) / 2.0 + std::gcd(top_count, bottom_count) / (2.0 * top * bottom);
}

std::vector<double> zone_offsets(const std::vector<int>& counts) {
  std::vector<double> offsets(counts.size(), 0.0);
  double turns = 0.0;
  for (std::size_t z = 1; z + 1 < counts.size(); ++z) { // collars only; caps have no azimuth
    offsets[z] = 2.0 * pi * turns;
    turns += circle_offset(counts[z], counts[z + 1]);
    turns -= std::floor(turns);
  }
  return offsets;
}

glm::vec3 region_centre(const EqualAreaPartition& partition, std::size_t zone, int k) {
  const std::size_t last = partition.regions_per_zone.size() - 1;
  if (zone == 0) return glm::vec3(0.0f, 0.0f, 1.0f);
  if (zone == last) return glm::vec3(0.0f, 0.0f, -1.0f);
  const double theta = (partition.zone_boundaries[zone] + partition.zone_boundaries[zone + 1]) / 2.0;
  const int m = partition.regions_per_zone[zone];
  const double phi = partition.zone_longitude_offsets[zone] + (k + 0.5) * 2.0 * pi / m;
  return from_polar(theta, phi);
}

glm::vec3 equal_area_direction(int i, int n) {
  const EqualAreaPartition partition = equal_area_partition(n);
  for (std::size_t zone = 0; zone < partition.regions_per_zone.size(); ++zone) {
    const int count = partition.regions_per_zone[zone];
    if (i < count) return region_centre(partition, zone, i);
    i -= count;
  }
  assert(false && "equal_area_direction: index out of range");
  return glm::vec3(0.0f, 0.0f, 1.0f);
}

std::vector<glm::vec3> equal_area_directions(int n) {
  const EqualAreaPartition partition = equal_area_partition(n);
  std::vector<glm::vec3> out;
  out.reserve(static_cast<std::size_t>(n));
  for (std::size_t zone = 0; zone < partition.regions_per_zone.size(); ++zone) {
    for (int k = 0; k < partition.regions_per_zone[zone]; ++k) out.push_back(region_centre(partition, zone, k));
  }
  return out;
}

} // namespace

constexpr EnumName<Lattice> kLatticeNames[] = {
    {Lattice::fibonacci, "fibonacci"},
    {Lattice::latlong, "latlong"},
    {Lattice::equal_area, "equal-area"},
};

std::string_view lattice_name(Lattice lattice) { return name_in(kLatticeNames, lattice, "unknown"); }

std::optional<Lattice> parse_lattice(std::string_view name) { return parse_name_in(kLatticeNames, name); }

EqualAreaPartition equal_area_partition(int n) {
  EqualAreaPartition partition;
  if (n <= 0) return partition;
  partition.region_count = n;
  if (n == 1) {
    partition.zone_boundaries = {0.0, pi};
    partition.regions_per_zone = {1};
    partition.zone_longitude_offsets = {0.0};
    return partition;
  }
  const double region_area = sphere_area / n;
  const double polar_cap = cap_colatitude(region_area);
  const int collars = collar_count(n, polar_cap, region_area);
  partition.regions_per_zone = zone_region_counts(n, polar_cap, collars, region_area);

  // Zone boundaries from the cumulative region counts, so each zone holds exactly its share of the area.
  partition.zone_boundaries = {0.0};
  int regions_above = 0;
  for (std::size_t z = 0; z + 1 < partition.regions_per_zone.size(); ++z) {
    regions_above += partition.regions_per_zone[z];
    partition.zone_boundaries.push_back(cap_colatitude(regions_above * region_area));
  }
  partition.zone_boundaries.push_back(pi);
  partition.zone_longitude_offsets = zone_offsets(partition.regions_per_zone);
  return partition;
}

std::vector<glm::vec3> lattice_directions(Lattice lattice, int n) {
  if (n <= 0) return {};
  switch (lattice) {
  case Lattice::latlong: return latlong_directions(n);
  case Lattice::equal_area: return equal_area_directions(n);
  case Lattice::fibonacci: break;
  }
  std::vector<glm::vec3> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) out.push_back(fibonacci_direction(i, n));
  return out;
}

glm::vec3 lattice_direction(Lattice lattice, int i, int n) {
  assert(i >= 0 && i < n);
  switch (lattice) {
  case Lattice::latlong: return latlong_direction(i, n);
  case Lattice::equal_area: return equal_area_direction(i, n);
  case Lattice::fibonacci: break;
  }
  return fibonacci_direction(i, n);
}

} // namespace probebake
