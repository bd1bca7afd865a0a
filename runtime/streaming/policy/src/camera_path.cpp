#include "probebake/streaming/camera_path.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>

#include "probebake/formats/error.h"

namespace probebake::streaming {
namespace {

[[noreturn]] void fail(std::string_view name, std::size_t line, const std::string& reason) {
  throw Error(ErrorKind::input, std::string(name) + ":" + std::to_string(line) + ": " + reason);
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// The four comma-separated fields of a row; false when there are not exactly four.
bool split_row(std::string_view row, std::string_view (&fields)[4]) {
  for (int i = 0; i < 4; ++i) {
    const std::size_t comma = row.find(',');
    if ((comma == std::string_view::npos) != (i == 3)) return false;
    fields[i] = trim(row.substr(0, comma));
    if (i < 3) row.remove_prefix(comma + 1);
  }
  return true;
}

template <class T>
bool parse_number(std::string_view text, T& value) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  return ec == std::errc() && ptr == end;
}

} // namespace

std::vector<PathPoint> parse_camera_path(std::string_view text, std::string_view name) {
  std::vector<PathPoint> points;
  std::size_t line = 0;
  bool header = false;
  while (!text.empty()) {
    const std::size_t newline = text.find('\n');
    const std::string_view row = trim(text.substr(0, newline));
    text.remove_prefix(newline == std::string_view::npos ? text.size() : newline + 1);
    ++line;
    if (row.empty()) continue;
    std::string_view f[4];
    if (!split_row(row, f)) fail(name, line, "expected 4 comma-separated fields (frame,x,y,z)");
    if (!header) {
      if (f[0] != "frame" || f[1] != "x" || f[2] != "y" || f[3] != "z")
        fail(name, line, "the header must be frame,x,y,z");
      header = true;
      continue;
    }
    if (points.size() == kMaxPathRows) fail(name, line, "more than " + std::to_string(kMaxPathRows) + " rows");
    PathPoint p;
    if (!parse_number(f[0], p.frame)) fail(name, line, "frame '" + std::string(f[0]) + "' is not an integer");
    if (!points.empty() && p.frame <= points.back().frame) fail(name, line, "frames must increase");
    for (int a = 0; a < 3; ++a)
      if (!parse_number(f[a + 1], p.position[a]) || !std::isfinite(p.position[a]))
        fail(name, line, "coordinate '" + std::string(f[a + 1]) + "' is not a finite number");
    points.push_back(p);
  }
  if (!header) fail(name, line, "empty file: expected the header frame,x,y,z");
  if (points.empty()) fail(name, line, "no rows after the header");
  return points;
}

std::vector<PathPoint> read_camera_path(const std::filesystem::path& path) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw_input_error(path.string(), "cannot read: " + ec.message());
  if (size > kMaxPathFileBytes)
    throw_input_error(path.string(), "larger than " + std::to_string(kMaxPathFileBytes) + " bytes");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw_input_error(path.string(), "cannot open");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw_input_error(path.string(), "read failed");
  return parse_camera_path(text, path.string());
}

} // namespace probebake::streaming
