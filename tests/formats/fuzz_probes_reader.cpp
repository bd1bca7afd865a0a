// libFuzzer target for the .probes reader and the validator (untrusted input). Seeds: tests/data/golden.
//   fuzz_probes_reader -dict=tests/formats/fuzz_probes_reader.dict -max_total_time=60 CORPUS tests/data/golden
// Properties checked beyond "no crash, no sanitizer report":
//  - read_probes and validate_file agree: what the reader refuses is never a valid file;
//  - checksums aside (so that mutations reach the model checks), a decoded volume that validates clean
//    writes, reads back and re-writes to the same bytes, and stays valid after arrange_cells.
#include <cstdint>
#include <cstdlib>
#include <span>

#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "probebake/formats/volume_stats.h"

namespace {

using namespace probebake;
using namespace probebake::formats;

void check(bool condition) {
  if (!condition) std::abort();
}

// The model behind the checksums: decode with mismatches ignored, then validate and round-trip.
void fuzz_model(std::span<const std::uint8_t> bytes) {
  ProbeVolume volume;
  try {
    const ContainerView container = parse_container(bytes, "fuzz", [](const std::string&, long long, const std::string&) {});
    volume = decode_probes(container, "fuzz");
  } catch (const Error&) {
    return;
  }
  const ValidationReport report = validate(volume, ValidateOptions{0});
  try {
    (void)compute_stats(volume); // what `probebake info` runs on unvalidated files
  } catch (const Error&) {
  }
  if (!report.valid()) return;
  const std::vector<std::uint8_t> written = write_probes(volume);
  check(write_probes(read_probes(written, "rewrite")) == written);
  const int depth = volume.cell_depth >= 0 && volume.cell_depth <= kMaxCellDepth ? volume.cell_depth : 0;
  arrange_cells(volume, depth);
  check(validate(volume).valid());
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  bool readable = true;
  try {
    (void)read_probes(bytes, "fuzz");
  } catch (const Error&) {
    readable = false;
  }
  const ValidationReport report = validate_file(bytes, "fuzz", ValidateOptions{16});
  check(readable || !report.valid());
  fuzz_model(bytes);
  return 0;
}
