// The validator on untrusted bytes. validate_file() and validate() report, they never throw (an Error
// escaping them would turn `probebake validate`'s verdict into "unreadable"). Properties checked beyond
// "no crash, no sanitizer report":
//  - every reported id is one of invariants(); "container" is reported exactly when the file is unreadable;
//  - the report of max_errors = N is the first N violations of the full one (at most 1000, as the CLI);
//  - the JSON report (`validate --json`) serializes;
//  - with the checksums recomputed (so that mutations of the payload reach the model checks), no
//    "checksum" violation remains and the rest of the report is unchanged;
//  - a valid file (as given, or with its checksums recomputed) reads, validates as a volume, and is
//    written by write_probes as a valid file.
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "fuzz_check.h"
#include "fuzz_entries.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "test_bytes.h"

namespace probebake::fuzz {
namespace {

using namespace probebake::formats;

constexpr std::size_t kMaxErrors = 1000; // as `probebake validate`: the report of a hostile file stays short

ValidationReport validate_bytes(std::span<const std::uint8_t> bytes, std::size_t max_errors) {
  try {
    return validate_file(bytes, "fuzz", ValidateOptions{max_errors});
  } catch (const Error& error) {
    check(false, std::string("validate_file threw probebake::Error: ") + error.what());
    throw; // unreachable
  }
}

bool same(const Violation& a, const Violation& b) {
  return a.invariant == b.invariant && a.section == b.section && a.index == b.index && a.message == b.message;
}

bool known_invariant(const std::string& id) {
  static const std::set<std::string_view> known = [] {
    std::set<std::string_view> ids;
    for (const InvariantInfo& info : invariants()) ids.insert(info.id);
    return ids;
  }();
  return known.count(id) != 0;
}

// `serialize`: also the text and JSON forms (`probebake validate`), once per input: with up to 1000
// violations they cost more under ASan than the validation itself.
void check_report(const ValidationReport& report, bool serialize = false) {
  for (const Violation& v : report.violations)
    check(known_invariant(v.invariant), "unknown invariant id '" + v.invariant + "'");
  // An unreadable file's report is its one container violation (checksums are reported only after decoding).
  const auto containers = std::count_if(report.violations.begin(), report.violations.end(),
                                        [](const Violation& v) { return v.invariant == "container"; });
  if (!report.readable) {
    check(containers == 1 && report.violations.size() == 1, "an unreadable file's report is one container violation");
  } else {
    check(containers == 0, "a readable file has no container violation");
  }
  if (!serialize) return;
  (void)report_to_json(report).dump();
  for (const Violation& v : report.violations) (void)format_violation(v);
}

// The bytes with every section checksum and the header checksum recomputed, or empty when the container
// cannot be parsed even with mismatches ignored.
std::vector<std::uint8_t> with_checksums_fixed(std::span<const std::uint8_t> bytes) {
  ContainerView container;
  try {
    container = parse_container(bytes, "fuzz", [](const std::string&, long long, const std::string&) {});
  } catch (const Error&) {
    return {};
  }
  std::vector<std::uint8_t> fixed(bytes.begin(), bytes.end());
  const FileHeader& header = container.header;
  const std::size_t table = header.header_size;
  for (std::size_t i = 0; i < container.sections.size(); ++i) {
    const std::uint64_t sum = checksum64(container.payloads[i]);
    std::memcpy(fixed.data() + table + i * header.section_entry_size + offsetof(SectionEntry, checksum), &sum,
                sizeof sum);
  }
  formats::testing::refresh_header_checksum(fixed); // covers the table just written
  return fixed;
}

std::vector<Violation> without_checksum(const std::vector<Violation>& violations) {
  std::vector<Violation> rest;
  std::copy_if(violations.begin(), violations.end(), std::back_inserter(rest),
               [](const Violation& v) { return v.invariant != "checksum"; });
  return rest;
}

// A file the validator accepts: the reader reads it, validate() accepts the volume, and write_probes
// writes it as a valid file.
void check_valid_file(std::span<const std::uint8_t> bytes) {
  ProbeVolume volume;
  try {
    volume = read_probes(bytes, "fuzz");
  } catch (const Error& error) {
    check(false, std::string("read_probes refuses a valid file: ") + error.what());
  }
  check(validate(volume, ValidateOptions{kMaxErrors}).valid(), "validate() accepts what validate_file() accepts");
  const ValidationReport written = validate_bytes(write_probes(volume), kMaxErrors);
  check(written.valid(), "a valid volume is written as a valid file; first violation: " +
                             (written.violations.empty() ? std::string() : format_violation(written.violations[0])));
}

} // namespace

void fuzz_one_validator(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  const ValidationReport full = validate_bytes(bytes, kMaxErrors);
  check_report(full, true);

  // Cut at a few violations (only where there are that many: below, the run is the same as the full one).
  constexpr std::size_t limit = 3;
  if (full.violations.size() >= limit) {
    const ValidationReport cut = validate_bytes(bytes, limit);
    check_report(cut);
    // The validator stops at the first violation past N, and decodes before reporting checksums.
    check(cut.readable == full.readable, "max_errors does not change readability");
    check(cut.violations.size() == limit, "max_errors keeps N violations");
    for (std::size_t i = 0; i < limit; ++i)
      check(same(cut.violations[i], full.violations[i]), "the max_errors report is a prefix of the full one");
    check(cut.truncated == (full.violations.size() > limit), "truncated exactly when violations were left out");
  }

  // Without checksum violations the recomputed checksums are the file's own: nothing to compare.
  const bool checksum_violations = std::any_of(full.violations.begin(), full.violations.end(),
                                               [](const Violation& v) { return v.invariant == "checksum"; });
  if (!checksum_violations || full.truncated) {
    if (full.valid()) check_valid_file(bytes);
    return;
  }
  const std::vector<std::uint8_t> fixed = with_checksums_fixed(bytes);
  check(!fixed.empty(), "a file with checksum violations has a parseable container");
  const ValidationReport refixed = validate_bytes(fixed, kMaxErrors);
  check_report(refixed);
  const std::vector<Violation> expected = without_checksum(full.violations);
  check(refixed.violations.size() == expected.size() &&
            std::equal(expected.begin(), expected.end(), refixed.violations.begin(), same),
        "recomputed checksums remove exactly the checksum violations");
  if (refixed.valid()) check_valid_file(fixed);
}

} // namespace probebake::fuzz
