// The .probes reader on untrusted bytes. Properties checked beyond "no crash, no sanitizer report":
//  - read_probes and validate_file agree: what the reader refuses is never a valid file;
//  - checksums aside (so that mutations reach the model checks), the streaming load's validation of the trace
//    sections in place reports what the decoded volume's does;
//  - a 1.7 streaming load's checks (the global part without the cells, then each cell alone) find a volume
//    valid exactly when validate() does;
//  - a decoded volume that validates clean
//    writes, reads back and re-writes to the same bytes, and stays valid after arrange_cells;
//  - the same bytes as a file (a memfd) through the streaming reader (CellFile::open, then each cell): a
//    1.7 file that validate_file finds valid streams whole, and one that streams whole has no violation but
//    file-level ones;
//  - the same bytes as a bake part (bake_part.h, the same container): a part that reads writes and reads
//    back to the same part.
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "fuzz_check.h"
#include "fuzz_entries.h"
#include "probebake/formats/bake_part.h"
#include "probebake/formats/cell_file.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "probebake/formats/volume_stats.h"

#include <sys/mman.h>
#include <unistd.h>

namespace probebake::fuzz {
namespace {

using namespace probebake::formats;

std::vector<std::string> violation_lines(const ValidationReport& report) {
  std::vector<std::string> lines;
  for (const Violation& violation : report.violations) lines.push_back(format_violation(violation));
  return lines;
}

// validate_without_cells, then validate_cell_tracing for each cell (a 1.7 streaming load's checks); a volume
// without one cell_tracing record per cell has nothing to stream and takes validate()'s verdict.
bool split_checks_valid(const ProbeVolume& volume) {
  if (volume.cell_tracing.empty() || volume.cell_tracing.size() != volume.cells.size())
    return validate(volume, ValidateOptions{1}).valid();
  std::vector<CellEntry> entries;
  if (!validate_without_cells(volume, tracing_view(volume), entries, ValidateOptions{1}).valid()) return false;
  for (std::size_t k = 0; k < volume.cell_tracing.size(); ++k) {
    const CellTracingData data = cell_tracing_data(volume, k); // the ranges passed the check above
    if (!validate_cell_tracing(volume, entries, k, {data.nodes, data.faces, data.vertices}, ValidateOptions{1}).valid())
      return false;
  }
  return true;
}

// The model behind the checksums: decode with mismatches ignored, then validate and round-trip; and the
// streaming load's way (CellFile::open), the trace nodes, faces and vertices read in place, gets the same report.
void fuzz_model(std::span<const std::uint8_t> input) {
  const std::vector<std::uint8_t> bytes(input.begin(), input.end()); // aligned as a file's mapping is, for tracing_in
  ProbeVolume volume, in_place;
  TracingView in_bytes;
  try {
    const ContainerView container =
        parse_container(bytes, "fuzz", [](const std::string&, long long, const std::string&) {});
    volume = decode_probes(container, "fuzz");
    in_place = decode_probes(container, "fuzz", TraceSections::leave_in_bytes);
    in_bytes = tracing_in(container, "fuzz");
  } catch (const Error&) {
    return;
  }
  const ValidationReport report = validate(volume, ValidateOptions{0});
  check(violation_lines(validate(in_place, in_bytes, ValidateOptions{0})) == violation_lines(report),
        "the trace sections read in place are validated as the decoded ones");
  check(split_checks_valid(volume) == report.valid(),
        "the checks without the cells and of each cell agree with validate()");
  try {
    (void)compute_stats(volume); // what `probebake info` runs on unvalidated files
  } catch (const Error&) {
  }
  if (!report.valid()) return;
  const std::vector<std::uint8_t> written = write_probes(volume);
  check(write_probes(read_probes(written, "rewrite")) == written, "a valid volume re-writes to the same bytes");
  const int depth = volume.cell_depth >= 0 && volume.cell_depth <= kMaxCellDepth ? volume.cell_depth : 0;
  arrange_cells(volume, depth);
  check(validate(volume).valid(), "a valid volume stays valid after arrange_cells");
}

// Whether the streaming reader takes the file at `path` and every cell of it; nullopt when it is not a 1.7
// file that streams (CellFile::open reads it whole, or refuses it before it knows).
std::optional<bool> streams_whole(const std::string& path) {
  try {
    OpenedCellFile opened = CellFile::open(path);
    if (!opened.cells_unread) return std::nullopt;
    std::vector<CellEntry> entries;
    if (!validate_without_cells(opened.volume, opened.tracing(), entries, ValidateOptions{1}).valid()) return false;
    opened.file.expect_unread(opened.volume, entries);
    for (std::size_t k = 0; k < opened.volume.cells.size(); ++k) (void)opened.file.read_cell_tracing(k);
    return true;
  } catch (const Error&) {
    return false;
  }
}

void fuzz_cell_file(std::span<const std::uint8_t> bytes, const ValidationReport& report) {
  const int fd = ::memfd_create("fuzz", MFD_CLOEXEC);
  if (fd < 0) return;
  bool written = true;
  for (std::size_t done = 0; written && done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    written = n > 0, done += n > 0 ? std::size_t(n) : 0;
  }
  const std::optional<bool> whole = written ? streams_whole("/proc/self/fd/" + std::to_string(fd)) : std::nullopt;
  ::close(fd);
  bool streams_as_1_7 = false; // validate_file's volume has global checksums
  try {
    streams_as_1_7 = !read_probes(bytes, "fuzz").cell_global_checksums.empty();
  } catch (const Error&) {
  }
  if (report.valid() && streams_as_1_7) check(whole == true, "a valid 1.7 file streams, every cell");
  if (whole == true) {
    const std::set<std::string> file_level = {"format_version", "section_flags", "section_layout", "trailing_bytes"};
    for (const Violation& v : report.violations)
      check(file_level.count(v.invariant) == 1, "a file that streams whole breaks no model invariant");
  }
}

void fuzz_bake_part(std::span<const std::uint8_t> bytes) {
  BakePart part;
  try {
    part = read_bake_part(bytes, "fuzz");
  } catch (const Error&) {
    return;
  }
  const BakePart again = read_bake_part(write_bake_part(part), "rewrite");
  check(again.input_hash == part.input_hash && again.cell_depth == part.cell_depth &&
            again.scene_triangles == part.scene_triangles && again.cells == part.cells && again.sealed == part.sealed,
        "a bake part that reads writes and reads back the same");
}

} // namespace

void fuzz_one_probes_reader(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  bool readable = true;
  try {
    (void)read_probes(bytes, "fuzz");
  } catch (const Error&) {
    readable = false;
  }
  const ValidationReport report = validate_file(bytes, "fuzz", ValidateOptions{16});
  check(readable || !report.valid(), "what read_probes refuses is not a valid file");
  fuzz_cell_file(bytes, report);
  fuzz_model(bytes);
  fuzz_bake_part(bytes);
}

} // namespace probebake::fuzz
