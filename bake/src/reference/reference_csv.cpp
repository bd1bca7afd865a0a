// Reference values as CSV: what `probebake reference --csv` writes and `probebake eval` caches.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <system_error>

#include <fmt/core.h>

#include "probebake/bake/reference.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"

namespace probebake::bake {
namespace {

constexpr const char* kHeader = "x,y,z,nx,ny,nz,r,g,b,stderr";

float max_channel(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

} // namespace

void write_reference_csv(const std::filesystem::path& path, std::span<const SamplePoint> points,
                         const ReferenceResult& reference) {
  std::string out = std::string(kHeader) + '\n';
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SamplePoint& p = points[i];
    const glm::vec3& e = reference.irradiance[i];
    out += fmt::format("{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", p.position.x,
                       p.position.y, p.position.z, p.normal.x, p.normal.y, p.normal.z, e.x, e.y, e.z,
                       max_channel(reference.standard_error[i]));
  }
  write_file_atomically(path, std::string_view(out));
}

bool read_reference_csv(const std::filesystem::path& path, std::vector<SamplePoint>& points, ReferenceResult& reference) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line) || line != kHeader) return false;
  points.clear();
  reference = {};
  while (std::getline(in, line)) {
    float v[10];
    char end = 0;
    if (std::sscanf(line.c_str(), "%g,%g,%g,%g,%g,%g,%g,%g,%g,%g%c", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6],
                    &v[7], &v[8], &v[9], &end) != 10)
      return false;
    points.push_back({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}});
    reference.irradiance.emplace_back(v[6], v[7], v[8]);
    reference.standard_error.emplace_back(v[9]);
  }
  return true;
}

} // namespace probebake::bake
