// Reading and writing .probes files: a ProbeVolume <-> the container of container.h, one section per
// non-empty buffer. The format is specified in docs/FORMAT.md.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "probebake/formats/container.h"
#include "probebake/formats/probe_volume.h"

namespace probebake::formats {

// Encodes the volume as .probes bytes. Only non-empty buffers get a section (volume info and octree
// always do). Deterministic: the same volume gives the same bytes. Does not validate the volume.
// The cell checksums and global checksums are computed from the bytes written. A volume with split tracing
// gets both (format 1.7), except one read from a 1.6 file (cell checksums but no global ones), which is
// written as 1.6 again, byte for byte.
std::vector<std::uint8_t> write_probes(const ProbeVolume& volume);

// The lowest minor version the volume's contents need beyond its section types: kEmitterGroupsMinor when an
// emitter patch names an emitter or material other than 0, kDoubleSidedFlagsMinor when a trace triangle or
// emitter patch sets a flag, else 0. The writer stamps the larger of this and
// what the section types need; the validator checks the same rule (format_version).
std::uint16_t minor_version_for_contents(const ProbeVolume& volume);

// Writes atomically: the bytes go to a temporary file in the same directory, are flushed to disk, and
// the temporary file is renamed over `path`; on any failure it is removed and Error(output) thrown.
void write_probes_file(const std::filesystem::path& path, const ProbeVolume& volume);

// Decodes .probes bytes (untrusted) into a volume. Checks the container (parse_container, checksums
// included) and the sections' element sizes and counts; unknown optional sections are skipped, unknown
// required sections and features refused. It does not check the model's invariants: call validate().
// Throws Error(input, "<name_for_errors>: <place>: <reason>").
ProbeVolume read_probes(std::span<const std::uint8_t> bytes, std::string_view name_for_errors);

// Sections of a parsed container -> volume (no checksum checks: parse_container does those). Used by
// read_probes and by validate_file, which reports checksum mismatches instead of throwing.
// `trace_sections`: leave_in_bytes decodes every section but trace_nodes, trace_faces and trace_vertices,
// which stay empty: read them with tracing_in() (a streaming load, CellFile::open).
enum class TraceSections { decode, leave_in_bytes };
// The three sections leave_in_bytes leaves: trace nodes, faces and vertices (the cells' tracing of format 1.5).
inline constexpr SectionType kInPlaceTraceSections[] = {SectionType::trace_nodes, SectionType::trace_faces,
                                                        SectionType::trace_vertices};
inline constexpr bool is_in_place_trace_section(std::uint32_t type) {
  for (SectionType s : kInPlaceTraceSections)
    if (type == static_cast<std::uint32_t>(s)) return true;
  return false;
}
ProbeVolume decode_probes(const ContainerView& container, std::string_view name_for_errors,
                          TraceSections trace_sections = TraceSections::decode);
// The container's trace nodes, faces and vertices where they lie in its bytes (which must outlive the view),
// element sizes and counts checked as decode_probes checks them; a section the file lacks is empty.
TracingView tracing_in(const ContainerView& container, std::string_view name_for_errors);

// Reads the whole file; Error(input) when it cannot be read.
std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path);
ProbeVolume read_probes_file(const std::filesystem::path& path);

} // namespace probebake::formats
