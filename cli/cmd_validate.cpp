// `probebake validate FILE.probes [--verbose] [--json] [--max-errors N]`: checks the container and every
// invariant of the model (formats/validate.h). Text: one summary line per violated invariant, for files
// that stream the count of cells checked on their own and each damaged one, then a verdict; --verbose adds
// every violation, --json gives them all. Exit 0 valid, 1 invalid, 2 unreadable.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "probebake/formats/error.h"
#include "probebake/formats/file_mapping.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"

namespace probebake::cli {
namespace {

constexpr int kExitValid = 0;
constexpr int kExitInvalid = 1;
constexpr int kExitUnreadable = static_cast<int>(ErrorKind::input);

struct ValidateSettings {
  std::string path;
  bool json = false;
  bool verbose = false;
  std::size_t max_errors = 100;
};

formats::ValidationReport validate_path(const ValidateSettings& settings) {
  try {
    // Mapped, not read: the trace sections are checked in place (validate_file), so a world larger than
    // memory validates (file_mapping.h).
    const formats::MappedReadGuard guard("probebake", settings.path);
    const formats::FileMapping file = formats::FileMapping::of(settings.path);
    return formats::validate_file(file.bytes(), settings.path, formats::ValidateOptions{settings.max_errors});
  } catch (const Error& error) { // the file cannot be read at all: same verdict as a bad container
    formats::ValidationReport report;
    report.name = settings.path;
    report.readable = false;
    report.violations.push_back(formats::Violation{"container", "container", -1, error.what()});
    return report;
  }
}

// The violations of one invariant: one corrupt node can break thousands of elements in the same way, so
// the text report names each problem once.
struct ProblemClass {
  const formats::Violation* first;
  std::size_t count;
};

// In order of first appearance, which is the validator's cheap-first phase order.
std::vector<ProblemClass> problem_classes(const formats::ValidationReport& report) {
  std::vector<ProblemClass> classes;
  for (const formats::Violation& violation : report.violations) {
    auto same = [&](const ProblemClass& c) { return c.first->invariant == violation.invariant; };
    if (auto it = std::find_if(classes.begin(), classes.end(), same); it != classes.end()) {
      ++it->count;
    } else {
      classes.push_back(ProblemClass{&violation, 1});
    }
  }
  return classes;
}

std::string plural(std::size_t count, const char* noun) {
  return fmt::format("{} {}{}", count, noun, count == 1 ? "" : "s");
}

// Files that stream (format 1.6) have each cell checked on its own: say how many, and which are damaged.
void print_cells(const formats::ValidationReport& report) {
  if (report.cells_checked == 0) return;
  std::vector<const formats::Violation*> damaged;
  for (const formats::Violation& violation : report.violations)
    if (violation.invariant == "cell_checksum" && violation.index >= 0) damaged.push_back(&violation);
  fmt::print("{}: {} checked on their own, {} damaged\n", report.name, plural(report.cells_checked, "cell"),
             damaged.size());
  constexpr std::size_t kNamed = 10;
  for (std::size_t i = 0; i < std::min(damaged.size(), kNamed); ++i)
    fmt::print("{}: damaged: {}: {}\n", report.name, formats::violation_place(*damaged[i]), damaged[i]->message);
  if (damaged.size() > kNamed)
    fmt::print("{}: damaged: {} more (--json lists them)\n", report.name, damaged.size() - kNamed);
}

void print_text(const formats::ValidationReport& report, bool verbose) {
  if (!report.readable) { // one "container" violation, already "<file>: <place>: <reason>"
    for (const formats::Violation& violation : report.violations) fmt::print("{}\n", violation.message);
    fmt::print("{}: unreadable\n", report.name);
    return;
  }
  if (verbose) {
    for (const formats::Violation& violation : report.violations)
      fmt::print("{}: {}\n", report.name, formats::format_violation(violation));
  }
  const std::vector<ProblemClass> classes = problem_classes(report);
  for (const ProblemClass& c : classes) {
    fmt::print("{}: invalid: {}: {}, first: {}: {}\n", report.name, c.first->invariant, plural(c.count, "violation"),
               formats::violation_place(*c.first), c.first->message);
  }
  print_cells(report);
  if (report.valid()) {
    fmt::print("{}: valid\n", report.name);
  } else {
    fmt::print("{}: invalid: {} of {}{}\n", report.name, plural(report.violations.size(), "violation"),
               plural(classes.size(), "invariant"), report.truncated ? " (stopped at --max-errors)" : "");
  }
}

int run_validate(const ValidateSettings& settings) {
  const formats::ValidationReport report = validate_path(settings);
  if (settings.json) {
    std::puts(formats::report_to_json(report).dump(2).c_str());
  } else {
    print_text(report, settings.verbose);
  }
  if (!report.readable) return kExitUnreadable;
  return report.valid() ? kExitValid : kExitInvalid;
}

} // namespace

Command add_validate_command(CLI::App& root) {
  auto settings = std::make_shared<ValidateSettings>();
  CLI::App* app = root.add_subcommand("validate", "Check a .probes file against every invariant of the format "
                                                  "(exit 0 valid, 1 invalid, 2 unreadable)");
  app->add_option("file", settings->path, ".probes file")->required();
  app->add_flag("--json", settings->json, "Print the report as one JSON object, with every violation");
  app->add_flag("-v,--verbose", settings->verbose, "Also print every violation, not only one line per invariant");
  app->add_option("--max-errors", settings->max_errors, "Stop after N violations (0: report all)")
      ->capture_default_str();
  return {app, [settings] { return run_validate(*settings); }};
}

} // namespace probebake::cli
