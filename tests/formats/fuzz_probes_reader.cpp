// libFuzzer target for the .probes reader (untrusted input); the checks are in fuzz_probes_reader_entry.cpp.
// Seeds: tests/data/golden, tests/data/fuzz/probes_reader (scripts/fuzz.sh assembles the corpus).
//   fuzz_probes_reader -dict=tests/formats/fuzz_probes_reader.dict -max_total_time=60 CORPUS tests/data/golden
#include "fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  probebake::fuzz::fuzz_one_probes_reader(data, size);
  return 0;
}
