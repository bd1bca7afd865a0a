// Nearest-probe queries for the SVO builder (build.cpp): a uniform bucket grid over the root cube.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "probebake/formats/probe_volume.h"

namespace probebake::probe_index::detail {

// Uniform bucket grid over the root cube for nearest-probe queries.
class ProbeBuckets {
public:
  ProbeBuckets(const formats::ProbeVolume& v, int resolution)
      : volume_(v), n_(resolution), buckets_(std::size_t(n_ * n_ * n_)) {
    for (std::size_t i = 0; i < v.probes.size(); ++i)
      if (v.probes[i].link != 0) buckets_[std::size_t(bucket_index(cell_of(v.probes[i].position)))].push_back(int(i));
  }

  // The k probes nearest to p (ties by index), searching rings of buckets outwards.
  std::vector<int> nearest(glm::vec3 p, int k) const {
    const glm::ivec3 c = cell_of(p);
    std::vector<std::pair<float, int>> found;
    const float cell = volume_.info.root_size / float(n_);
    for (int ring = 0; ring < n_; ++ring) {
      collect_ring(c, ring, p, found);
      if (int(found.size()) >= k) {
        std::sort(found.begin(), found.end());
        if (found[std::size_t(k - 1)].first <= float(ring) * cell * float(ring) * cell) break;
      }
    }
    std::sort(found.begin(), found.end());
    std::vector<int> out;
    for (std::size_t i = 0; i < found.size() && int(i) < k; ++i) out.push_back(found[i].second);
    return out;
  }

private:
  glm::ivec3 cell_of(glm::vec3 p) const {
    const glm::vec3 t = (p - volume_.info.root_min) / volume_.info.root_size * float(n_);
    return glm::clamp(glm::ivec3(glm::floor(t)), glm::ivec3(0), glm::ivec3(n_ - 1));
  }
  int bucket_index(glm::ivec3 c) const { return c.x + n_ * (c.y + n_ * c.z); }

  void collect_ring(glm::ivec3 c, int ring, glm::vec3 p, std::vector<std::pair<float, int>>& found) const {
    for (int z = c.z - ring; z <= c.z + ring; ++z)
      for (int y = c.y - ring; y <= c.y + ring; ++y)
        for (int x = c.x - ring; x <= c.x + ring; ++x) {
          if (std::max({std::abs(x - c.x), std::abs(y - c.y), std::abs(z - c.z)}) != ring) continue;
          if (x < 0 || y < 0 || z < 0 || x >= n_ || y >= n_ || z >= n_) continue;
          for (int probe : buckets_[std::size_t(bucket_index({x, y, z}))]) {
            const glm::vec3 d = volume_.probes[std::size_t(probe)].position - p;
            found.push_back({glm::dot(d, d), probe});
          }
        }
  }

  const formats::ProbeVolume& volume_;
  int n_;
  std::vector<std::vector<int>> buckets_;
};

} // namespace probebake::probe_index::detail
