#include "scene_input.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "probebake/formats/error.h"

namespace probebake::cli {
namespace {

// Address space beyond the budget: code, thread stacks and allocator arenas, which are reserved, not used.
constexpr std::uint64_t kAddressSpaceHeadroom = std::uint64_t(4) << 30;

std::uint64_t default_budget() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page_size = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return 0;
  return std::uint64_t(pages) * std::uint64_t(page_size) / 4 * 3;
}

void cap_address_space(std::uint64_t budget) {
#if !defined(PROBEBAKE_SANITIZED)
  rlimit limit{};
  if (budget == 0 || ::getrlimit(RLIMIT_AS, &limit) != 0) return;
  // Only ever lowered: a tighter limit set by the caller (ulimit -v) stays in force, even for root.
  const rlim_t cap = budget + kAddressSpaceHeadroom;
  limit.rlim_cur = std::min(limit.rlim_cur, cap);
  limit.rlim_max = std::min(limit.rlim_max, cap);
  ::setrlimit(RLIMIT_AS, &limit);
#else
  (void)budget; // sanitizers reserve terabytes of address space
#endif
}

// The number at the start of `text` and its length in `used` (0: none).
double leading_number(const std::string& text, std::size_t& used) {
  used = 0;
  try {
    return std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
    return 0.0;
  }
}

// "R,G,B" or one value for all three.
glm::vec3 parse_colour(const std::string& text) {
  std::vector<float> values;
  std::size_t at = 0;
  while (at <= text.size() && values.size() < 4) {
    const std::size_t comma = std::min(text.find(',', at), text.size());
    const std::string part = text.substr(at, comma - at);
    std::size_t used = 0;
    const double v = leading_number(part, used);
    if (used == 0 || used != part.size())
      throw Error(ErrorKind::usage, "--sky: '" + text + "' is not R,G,B, one value, a .exr file or 'physical'");
    values.push_back(float(v));
    at = comma + 1;
  }
  if (values.size() == 1) return glm::vec3(values[0]);
  if (values.size() != 3)
    throw Error(ErrorKind::usage, "--sky: '" + text + "' is not R,G,B, one value, a .exr file or 'physical'");
  return {values[0], values[1], values[2]};
}

} // namespace

std::uint64_t parse_byte_size(const std::string& text) {
  std::size_t used = 0;
  const double value = leading_number(text, used);
  const std::string suffix = text.substr(used);
  double scale = 1.0;
  if (suffix == "K" || suffix == "KiB")
    scale = 1024.0;
  else if (suffix == "M" || suffix == "MiB")
    scale = 1024.0 * 1024.0;
  else if (suffix == "G" || suffix == "GiB")
    scale = 1024.0 * 1024.0 * 1024.0;
  else if (suffix == "T" || suffix == "TiB")
    scale = 1024.0 * 1024.0 * 1024.0 * 1024.0;
  else if (!suffix.empty())
    used = 0;
  if (used == 0 || !std::isfinite(value) || value < 0.0 || value * scale > 1.8e19)
    throw Error(ErrorKind::usage, "--max-memory: '" + text + "' is not a size like 512M, 8G or a byte count");
  return static_cast<std::uint64_t>(value * scale);
}

void add_scene_input_options(CLI::App* app, SceneInputOptions& options) {
  app->add_option("--allow-path", options.allow_paths,
                  "Also let the scene's external buffers and images come from DIR (repeatable; default: only the "
                  "scene's own folder)");
  app->add_option("--max-memory", options.max_memory,
                  "Memory budget, e.g. 8G (default: 3/4 of physical memory; 0: no limit)");
  app->add_flag("--strict", options.strict,
                "Fail on a texture that cannot be decoded (default: warn and use the material's factor)");
  app->add_option("--dynamic", options.dynamic_nodes,
                  "Node NAME moves at run time with its subtree (repeatable or comma-separated; as glTF node extras "
                  "{\"probebake\": {\"dynamic\": true}})")
      ->delimiter(',');
  app->add_option("--sky", options.sky,
                  "Light of rays that leave the scene: R,G,B (or one value) radiance, FILE.exr (equirectangular), or "
                  "'physical' (daylight sky of --sun, with the sun as a directional light); default none");
  app->add_option("--sun", options.sun, "Physical sky: the sun's ELEVATION,AZIMUTH in degrees (azimuth from -Z to +X)")
      ->expected(2)
      ->delimiter(',');
  app->add_option("--turbidity", options.turbidity, "Physical sky: haze, 1.7 (clear) to 10 (hazy); default 2.5");
  app->add_option("--sky-intensity", options.sky_intensity, "Scale of the sky's radiance (not the sun's); default 1");
}

std::optional<sky::Sky> sky_from_options(const SceneInputOptions& o) {
  if (!o.sun.empty() && o.sky != "physical") throw Error(ErrorKind::usage, "--sun needs --sky physical");
  if (o.sky.empty()) return std::nullopt;
  if (!std::isfinite(o.sky_intensity) || o.sky_intensity < 0.0f)
    throw Error(ErrorKind::usage, "--sky-intensity must be finite and >= 0");
  sky::Sky result;
  if (o.sky == "physical") {
    if (o.sun.size() != 2) throw Error(ErrorKind::usage, "--sky physical needs --sun ELEVATION,AZIMUTH");
    result = sky::physical_sky({sky::direction_from_angles(o.sun[0], o.sun[1]), o.turbidity});
  } else if (o.sky.size() > 4 && (o.sky.ends_with(".exr") || o.sky.ends_with(".EXR"))) {
    return sky::environment_sky(o.sky, o.sky_intensity);
  } else {
    result = sky::constant_sky(parse_colour(o.sky));
  }
  result.colour *= o.sky_intensity;
  return result;
}

CLI::App* add_scene_subcommand(CLI::App& root, const std::string& name, const std::string& description,
                               std::string& scene, SceneInputOptions& input) {
  CLI::App* app = root.add_subcommand(name, description);
  app->add_option("scene", scene, "Scene (.gltf or .glb)")->required();
  add_scene_input_options(app, input);
  return app;
}

scene::LoadOptions load_options(const SceneInputOptions& options, bool require_triangles) {
  scene::LoadOptions load;
  load.require_triangles = require_triangles;
  load.strict = options.strict;
  load.dynamic_nodes = options.dynamic_nodes;
  for (const std::string& dir : options.allow_paths) load.allowed_paths.emplace_back(dir);
  load.max_memory = options.max_memory.empty() ? default_budget() : parse_byte_size(options.max_memory);
  cap_address_space(load.max_memory);
  load.sky = sky_from_options(options);
  return load;
}

} // namespace probebake::cli
