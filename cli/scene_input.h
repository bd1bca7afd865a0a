// Options every command that reads a glTF scene shares (README "Security"): folders besides the scene's own
// that external files may come from, and the memory budget of the load and of the whole process.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "probebake/scene/scene.h"

namespace probebake::cli {

struct SceneInputOptions {
  std::vector<std::string> allow_paths;
  std::string max_memory;                 // "" = the default (3/4 of physical memory); "0" = no limit
  bool strict = false;                    // an undecodable texture is an error, not a warning
  std::vector<std::string> dynamic_nodes; // nodes that move at run time, besides those the glTF marks
  // The sky (docs/LIGHTING.md "The sky"): "" none (black), "R,G,B" or "L" a constant radiance, FILE.exr an
  // equirectangular environment, "physical" the daylight sky of --sun with its sun.
  std::string sky;
  std::vector<float> sun;     // elevation, azimuth in degrees (physical sky)
  float turbidity = 2.5f;     // physical sky
  float sky_intensity = 1.0f; // scales the sky's radiance (not the sun's)
};

void add_scene_input_options(CLI::App* app, SceneInputOptions& options);

// A subcommand of `root` that reads a glTF scene: its required positional `scene` and the scene input options.
CLI::App* add_scene_subcommand(CLI::App& root, const std::string& name, const std::string& description,
                               std::string& scene, SceneInputOptions& input);

// Loader options; also caps the process's address space at the budget plus headroom (not under
// sanitizers), so an allocation no check foresaw fails as std::bad_alloc instead of exhausting the machine.
scene::LoadOptions load_options(const SceneInputOptions& options, bool require_triangles);

// The sky the options describe (nullopt: none). Throws Error(usage) for a malformed --sky or --sun, Error(input)
// for an environment file that cannot be read.
std::optional<sky::Sky> sky_from_options(const SceneInputOptions& options);

// "512M", "8G", "1.5G", "1048576" -> bytes. Throws Error(usage) on anything else.
std::uint64_t parse_byte_size(const std::string& text);

} // namespace probebake::cli
