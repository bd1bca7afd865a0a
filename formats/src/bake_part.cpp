// Bake parts (bake_part.h): written and read through the .probes container with their own kind.
#include "probebake/formats/bake_part.h"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <string>

#include "text.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"

namespace probebake::formats {
namespace {

template <class T>
SectionPayload payload(PartSectionType type, std::span<const T> elements) {
  return {static_cast<std::uint32_t>(type),
          kSectionRequired,
          sizeof(T),
          elements.size(),
          {reinterpret_cast<const std::uint8_t*>(elements.data()), elements.size_bytes()}};
}

class PartReader {
public:
  PartReader(std::span<const std::uint8_t> bytes, std::string_view name)
      : name_(name), view_(parse_container(bytes, name, {}, kPartContainer)) {}

  BakePart read() {
    BakePart part;
    part.input_hash = view_.header.input_hash;
    if (view_.header.cell_depth > std::uint32_t(kMaxCellDepth))
      fail("header", detail::concat("cell depth ", view_.header.cell_depth, " outside [0, ", kMaxCellDepth, "]"));
    part.cell_depth = int(view_.header.cell_depth);
    const std::vector<PartInfo> info = elements<PartInfo>(PartSectionType::part_info);
    if (info.size() != 1) fail("part_info", detail::concat(info.size(), " records, expected 1"));
    if (info[0].reserved != 0) fail("part_info", "reserved field is not zero");
    part.scene_triangles = info[0].scene_triangles;
    part.cells = elements<std::int32_t>(PartSectionType::part_cells);
    part.sealed = elements<std::uint8_t>(PartSectionType::part_sealed);
    check(part, info[0]);
    return part;
  }

private:
  [[noreturn]] void fail(const std::string& place, const std::string& reason) const {
    throw Error(ErrorKind::input, detail::concat(name_, ": ", place, ": ", reason));
  }

  // The section's elements; a missing section or another element size is an error.
  template <class T>
  std::vector<T> elements(PartSectionType type) const {
    const auto wanted = static_cast<std::uint32_t>(type);
    for (std::size_t i = 0; i < view_.sections.size(); ++i) {
      if (view_.sections[i].type != wanted) continue;
      if (view_.sections[i].element_size != sizeof(T))
        fail(part_section_name(wanted),
             detail::concat("element size ", view_.sections[i].element_size, ", expected ", sizeof(T)));
      std::vector<T> out(view_.sections[i].element_count); // checked against the file's size by parse_container
      if (!out.empty()) std::memcpy(out.data(), view_.payloads[i].data(), view_.payloads[i].size());
      return out;
    }
    fail(part_section_name(wanted), "missing");
  }

  void check(const BakePart& part, const PartInfo& info) const {
    if (part.cells.size() != info.cell_count)
      fail("part_cells", detail::concat(part.cells.size(), " cells, part_info says ", info.cell_count));
    if (part.sealed.size() != info.tested_triangles)
      fail("part_sealed", detail::concat(part.sealed.size(), " flags, part_info says ", info.tested_triangles));
    if (info.tested_triangles > info.scene_triangles)
      fail("part_info", detail::concat(info.tested_triangles, " tested of ", info.scene_triangles, " triangles"));
    const int grid = cell_count(part.cell_depth); // the depth is at most kMaxCellDepth
    for (std::size_t k = 0; k < part.cells.size(); ++k) {
      if (part.cells[k] < 0 || part.cells[k] >= grid)
        fail(detail::concat("part_cells[", k, "]"), detail::concat("cell ", part.cells[k], " outside [0, ", grid, ")"));
      if (k > 0 && part.cells[k] <= part.cells[k - 1])
        fail(detail::concat("part_cells[", k, "]"), "cells do not ascend");
    }
    const auto bad = std::find_if(part.sealed.begin(), part.sealed.end(), [](std::uint8_t f) { return f > 1; });
    if (bad != part.sealed.end())
      fail(detail::concat("part_sealed[", bad - part.sealed.begin(), "]"),
           detail::concat("flag ", int(*bad), " is neither 0 nor 1"));
  }

  std::string_view name_;
  ContainerView view_;
};

} // namespace

std::string part_section_name(std::uint32_t type) {
  static constexpr const char* kNames[] = {"part_info", "part_cells", "part_sealed"};
  static_assert(std::size(kNames) == kPartSectionTypeCount);
  if (is_known_part_section_type(type)) return kNames[type - 1];
  return "section_" + std::to_string(type);
}

std::vector<std::uint8_t> write_bake_part(const BakePart& part) {
  const PartInfo info{part.scene_triangles, std::uint32_t(part.cells.size()), std::uint32_t(part.sealed.size()), 0};
  const SectionPayload sections[] = {payload(PartSectionType::part_info, std::span(&info, 1)),
                                     payload(PartSectionType::part_cells, std::span(part.cells)),
                                     payload(PartSectionType::part_sealed, std::span(part.sealed))};
  return write_container({std::uint32_t(part.cell_depth), part.input_hash}, sections, kPartContainer);
}

BakePart read_bake_part(std::span<const std::uint8_t> bytes, std::string_view name) {
  return PartReader(bytes, name).read();
}

BakePart read_bake_part_file(const std::filesystem::path& path) {
  return read_bake_part(read_file_bytes(path), path.string());
}

} // namespace probebake::formats
