// Spherical lattices: the directions in which a probe places its surfels.
//
// All directions are unit vectors in the lattice's own frame, with +Z as the polar axis (polar angle
// theta measured from +Z, azimuth phi from +X towards +Y), as in the thesis's eq. 2.2. The caller rotates
// them into world space if it wants another pole. Pure functions: thread-safe, no allocation beyond the
// returned vectors, deterministic (same n, same bits on the same platform).
#pragma once

#include <glm/vec3.hpp>

#include <optional>
#include <string_view>
#include <vector>

namespace probebake {

enum class Lattice {
  fibonacci,  // golden-angle spiral, thesis eq. 2.3-2.4 (the default)
  latlong,    // parallels x meridians at cell centres, exactly n points (see lattice_directions)
  equal_area, // Leopardi's recursive zonal equal-area partition EQ(2, n), region centres
};

// "fibonacci", "latlong", "equal-area".
std::string_view lattice_name(Lattice lattice);
// Inverse of lattice_name; nullopt for anything else (case-sensitive).
std::optional<Lattice> parse_lattice(std::string_view name);

// Exactly n unit directions for every n >= 1 (an empty vector for n <= 0).
//  - fibonacci: point i (1-based) has z = 1 - (2/n)(i - 1/2), phi = g (i - 1/2), g = pi (3 - sqrt 5).
//  - latlong: p = max(1, round(sqrt(n/2))) parallels at theta_j = (j + 1/2) pi / p; each has floor(n/p)
//    meridians and the n mod p parallels nearest the equator one more, given in north/south pairs (so the
//    rows sum to n and the centroid is off by at most one point's weight, 1/n); points sit at cell
//    centres phi_k = (k + 1/2) 2 pi / m_j. For n = 2 p^2 this is the thesis's grid (e.g. 200 = 10
//    parallels x 20 meridians). Row by row from the north pole.
//  - equal_area: the centres of the regions of equal_area_partition(n), zone by zone from the north pole.
std::vector<glm::vec3> lattice_directions(Lattice lattice, int n);

// Direction i (0-based, 0 <= i < n) of lattice_directions(lattice, n), computed alone: O(1) for fibonacci
// (what a shader does), O(sqrt n) for latlong and equal_area. Precondition: 0 <= i < n.
glm::vec3 lattice_direction(Lattice lattice, int i, int n);

// EQ(2, n): the sphere cut into zones (the two polar caps and the collars between them) by parallels, and
// each zone cut into equal longitude sectors, so that every region has area 4 pi / n (Leopardi 2006).
struct EqualAreaPartition {
  int region_count = 0;
  // Zone z spans polar angles [zone_boundaries[z], zone_boundaries[z + 1]], radians; front is 0, back is pi.
  std::vector<double> zone_boundaries;
  // Regions in zone z (1 for each cap); they sum to region_count.
  std::vector<int> regions_per_zone;
  // Region k of zone z spans azimuths [offset + k * 2 pi / m, offset + (k + 1) * 2 pi / m), radians
  // (mod 2 pi), with offset = zone_longitude_offsets[z] and m = regions_per_zone[z]; its centre is at the
  // middle of both ranges (the poles for the caps).
  std::vector<double> zone_longitude_offsets;
};

// The partition for n >= 1 regions (an empty partition for n <= 0).
EqualAreaPartition equal_area_partition(int n);

} // namespace probebake
