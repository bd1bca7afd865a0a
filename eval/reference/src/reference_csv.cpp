// Reference values as CSV: what `probebake reference --csv` writes and `probebake eval` caches, and the
// receivers `probebake reference --at` reads.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string_view>
#include <system_error>

#include <glm/geometric.hpp>

#include <optional>

#include <fmt/core.h>

#include "probebake/eval/reference.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"

namespace probebake::bake {
namespace {

constexpr const char* kHeader = "x,y,z,nx,ny,nz,r,g,b,stderr,direct_r,direct_g,direct_b,indirect_stderr";
constexpr std::string_view kHeaderWithoutDirect = "x,y,z,nx,ny,nz,r,g,b,stderr"; // before the direct part
constexpr int kColumns = 14;

constexpr std::string_view kReceiverHeader = "x,y,z,nx,ny,nz";

float max_channel(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// The comma-separated numbers of one row, or a reason why it is not such a row.
std::optional<std::string> parse_numbers(std::string_view row, std::vector<float>& out) {
  out.clear();
  while (true) {
    const std::size_t comma = row.find(',');
    const std::string_view field = trim(row.substr(0, comma));
    float v = 0.0f;
    const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
    if (field.empty() || ec != std::errc() || end != field.data() + field.size())
      return fmt::format("column {}: '{}' is not a number", out.size() + 1, field.substr(0, 32));
    if (!std::isfinite(v)) return fmt::format("column {}: {} is not finite", out.size() + 1, field.substr(0, 32));
    out.push_back(v);
    if (out.size() > std::size_t(kColumns)) return fmt::format("more than {} columns", kColumns);
    if (comma == std::string_view::npos) return std::nullopt;
    row.remove_prefix(comma + 1);
  }
}

// Checks and reads one receiver row (6 numbers, or the 14 or older 10 of a reference CSV whose values are
// ignored).
SamplePoint receiver_row(std::string_view row, const std::string& where) {
  std::vector<float> v;
  if (const auto problem = parse_numbers(row, v)) throw Error(ErrorKind::input, where + ": " + *problem);
  if (v.size() != 6 && v.size() != 10 && v.size() != std::size_t(kColumns))
    throw Error(ErrorKind::input, fmt::format("{}: {} columns; a row is x,y,z,nx,ny,nz", where, v.size()));
  const glm::vec3 normal(v[3], v[4], v[5]);
  const float length = glm::length(normal);
  if (!(length > 1e-6f) || !std::isfinite(length))
    throw Error(ErrorKind::input, where + ": the normal nx,ny,nz has no direction");
  return {{v[0], v[1], v[2]}, normal / length};
}

} // namespace

void write_reference_csv(const std::filesystem::path& path, std::span<const SamplePoint> points,
                         const ReferenceResult& reference) {
  std::string out = std::string(kHeader) + '\n';
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SamplePoint& p = points[i];
    const glm::vec3& e = reference.irradiance[i];
    const glm::vec3& d = reference.direct.at(i);
    out += fmt::format(
        "{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n",
        p.position.x, p.position.y, p.position.z, p.normal.x, p.normal.y, p.normal.z, e.x, e.y, e.z,
        max_channel(reference.standard_error[i]), d.x, d.y, d.z, max_channel(reference.indirect_standard_error.at(i)));
  }
  write_file_atomically(path, std::string_view(out));
}

bool read_reference_csv(const std::filesystem::path& path, std::vector<SamplePoint>& points,
                        ReferenceResult& reference) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line) || line != kHeader) return false;
  points.clear();
  reference = {};
  while (std::getline(in, line)) {
    std::vector<float> v;
    if (parse_numbers(line, v) || v.size() != std::size_t(kColumns)) return false;
    points.push_back({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}});
    reference.irradiance.emplace_back(v[6], v[7], v[8]);
    reference.standard_error.emplace_back(v[9]);
    reference.direct.emplace_back(v[10], v[11], v[12]);
    reference.indirect_standard_error.emplace_back(v[13]);
  }
  return true;
}

std::vector<SamplePoint> read_receivers_csv(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw_input_error(name, "cannot read: " + ec.message());
  if (size > kMaxReceiverFileBytes)
    throw_input_error(name, fmt::format("{} bytes; receiver files are limited to {}", size, kMaxReceiverFileBytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw_input_error(name, "cannot read");
  std::string text(std::size_t(size), '\0');
  if (!in.read(text.data(), std::streamsize(text.size()))) throw_input_error(name, "cannot read");
  std::vector<SamplePoint> points;
  std::string_view rest(text);
  for (std::size_t line = 1; !rest.empty(); ++line) {
    const std::size_t newline = rest.find('\n');
    const std::string_view row = trim(rest.substr(0, newline));
    rest.remove_prefix(newline == std::string_view::npos ? rest.size() : newline + 1);
    if (row.empty()) continue;
    if (line == 1 && (row == kReceiverHeader || row == kHeader || row == kHeaderWithoutDirect)) continue;
    if (points.size() == kMaxReceivers)
      throw_input_error(name, fmt::format("line {}: more than {} receivers", line, kMaxReceivers));
    points.push_back(receiver_row(row, fmt::format("{}: line {}", name, line)));
  }
  if (points.empty()) throw_input_error(name, "no receivers (rows x,y,z,nx,ny,nz)");
  return points;
}

} // namespace probebake::bake
