// The report of `probebake bake` and `merge`: what the bake did and wrote, as JSON (--json) and as text.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "probebake/bake/bake.h"
#include "probebake/formats/probe_volume.h"

namespace probebake::cli {

// The report of a bake written to `output` (`bytes` long) holding `v`.
nlohmann::ordered_json bake_report_json(const bake::BakeReport& r, const std::string& output, std::size_t bytes,
                                        const formats::ProbeVolume& v);
// The report as text on stdout.
void print_bake_report(const nlohmann::ordered_json& j);

} // namespace probebake::cli
