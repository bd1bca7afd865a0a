// What a streamed cell's arrival costs on the host (docs/results/streaming.md "A load that reads only the global part"):
// for every cell of a 1.7 .probes file, CellFile::read_cell_tracing with the cell's checks (its stored checksum
// and validate_cell_tracing, as Volume::load sets it up) against the read and checksum alone, median of the runs
// over all cells; and the load's own part (CellFile::open, validate_without_cells).
//
// Usage: probebake-bench-cell-read FILE.probes [--runs N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <vector>

#include "bench_args.h"
#include "probebake/formats/cell_file.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/validate.h"

namespace {

using namespace probebake::formats;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Milliseconds to read every cell with faces once, the median of `runs`.
double read_all_ms(const CellFile& file, std::size_t cells, int runs) {
  std::vector<double> ms;
  for (int r = 0; r < runs; ++r) {
    const auto start = Clock::now();
    for (std::size_t k = 0; k < cells; ++k) (void)file.read_cell_tracing(k);
    ms.push_back(ms_since(start));
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

} // namespace

int main(int argc, char** argv) {
  const std::optional<int> parsed_runs = probebake::bench::parse_runs(argc, argv, 2, 5);
  if (argc < 2 || !parsed_runs)
    return std::fprintf(stderr, "usage: probebake-bench-cell-read FILE.probes [--runs N]\n"), 1;
  const int runs = *parsed_runs;
  try {
    auto start = Clock::now();
    OpenedCellFile opened = CellFile::open(argv[1]);
    const double open_ms = ms_since(start);
    if (!opened.cells_unread) return std::fprintf(stderr, "%s: not a 1.7 file with split tracing\n", argv[1]), 1;
    std::vector<CellEntry> entries;
    start = Clock::now();
    const ValidationReport report = validate_without_cells(opened.volume, opened.tracing(), entries);
    const double global_ms = ms_since(start);
    if (!report.valid())
      return std::fprintf(stderr, "%s: %s\n", argv[1], format_violation(report.violations.front()).c_str()), 1;
    std::uint64_t bytes = 0;
    for (const CellTracing& t : opened.volume.cell_tracing) bytes += cell_tracing_bytes(t);
    const std::size_t cells = opened.volume.cells.size();
    opened.file.expect_unread(opened.volume, {});
    const double plain = read_all_ms(opened.file, cells, runs);
    opened.file.expect_unread(opened.volume, entries);
    const double checked = read_all_ms(opened.file, cells, runs);
    std::printf("open (global part, %.1f MB read): %.1f ms; validate_without_cells: %.1f ms\n",
                double(opened.bytes_read) / 1e6, open_ms, global_ms);
    std::printf("| cells | tracing MB | read + checksum, ms per cell | + validate_cell_tracing, ms per cell | ratio "
                "|\n|--:|--:|--:|--:|--:|\n");
    std::printf("| %zu | %.1f | %.3f | %.3f | %.2f |\n", cells, double(bytes) / 1e6, plain / double(cells),
                checked / double(cells), checked / plain);
  } catch (const probebake::Error& error) {
    return std::fprintf(stderr, "%s\n", error.what()), 2;
  }
  return 0;
}
