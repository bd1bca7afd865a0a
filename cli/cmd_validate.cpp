// `probebake validate FILE.probes [--json] [--max-errors N]`: checks the container and every invariant of
// the model (formats/validate.h). Exit 0 valid, 1 invalid, 2 unreadable or not a .probes file.
#include <cstdio>
#include <memory>
#include <string>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "probebake/formats/error.h"
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
  std::size_t max_errors = 100;
};

formats::ValidationReport validate_path(const ValidateSettings& settings) {
  try {
    const std::vector<std::uint8_t> bytes = formats::read_file_bytes(settings.path);
    return formats::validate_file(bytes, settings.path, formats::ValidateOptions{settings.max_errors});
  } catch (const Error& error) { // the file cannot be read at all: same verdict as a bad container
    formats::ValidationReport report;
    report.name = settings.path;
    report.readable = false;
    report.violations.push_back(formats::Violation{"container", "container", -1, error.what()});
    return report;
  }
}

void print_text(const formats::ValidationReport& report) {
  for (const formats::Violation& violation : report.violations) {
    if (violation.invariant == "container") { // already "<file>: <place>: <reason>"
      fmt::print("{}\n", violation.message);
    } else {
      fmt::print("{}: {}\n", report.name, formats::format_violation(violation));
    }
  }
  if (report.valid()) {
    fmt::print("{}: valid\n", report.name);
  } else if (!report.readable) {
    fmt::print("{}: unreadable\n", report.name);
  } else {
    fmt::print("{}: invalid: {} violation{}{}\n", report.name, report.violations.size(), report.violations.size() == 1 ? "" : "s",
               report.truncated ? " (stopped at --max-errors)" : "");
  }
}

int run_validate(const ValidateSettings& settings) {
  const formats::ValidationReport report = validate_path(settings);
  if (settings.json) {
    std::puts(formats::report_to_json(report).dump(2).c_str());
  } else {
    print_text(report);
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
  app->add_flag("--json", settings->json, "Print the report as one JSON object");
  app->add_option("--max-errors", settings->max_errors, "Stop after N violations (0: report all)")->capture_default_str();
  return {app, [settings] { return run_validate(*settings); }};
}

} // namespace probebake::cli
