// make-scene: writes a procedural glTF 2.0 test scene as .glb.
//   make-scene KIND [options] [-o OUT.glb]
// Exit codes (probebake's): 0 written (or --help), 1 usage error, 2 unreadable input (e.g. --with),
// 3 output not writable, 4 internal error.
#include "probebake/formats/atomic_file.h"
#include "probebake/samples/flip_gltf.h"
#include "probebake/samples/meshopt_gltf.h"
#include "probebake/samples/scenes.h"
#include "probebake/version.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <string>
#include <vector>

namespace samples = probebake::samples;

namespace {

constexpr int exit_ok = 0;
constexpr int exit_usage = static_cast<int>(probebake::ErrorKind::usage);
constexpr int exit_internal = static_cast<int>(probebake::ErrorKind::internal);

struct Settings {
  std::string output; // empty: KIND.glb in the current folder
  float scale = 1.0f;
  std::vector<float> offset; // empty or X Y Z
  bool quiet = false;
  bool meshopt = false;      // geometry through meshoptimizer's encoder (EXT_meshopt_compression)
  bool flip = false;         // `convert`: every surface's sides swapped, materials double-sided
  std::string convert_input; // `convert`: the glTF to rewrite
};

// Each kind's options, filled by CLI11.
struct KindOptions {
  samples::CornellOptions cornell;
  samples::WindowRoomOptions window_room;
  samples::CourtyardOptions courtyard;
  samples::TinyEmitterOptions tiny_emitter;
  samples::CavityOptions cavity;
  std::string cornell_with;
  samples::FurnaceOptions furnace;
  samples::LeakOptions leak;
  samples::PlaneLightOptions plane_light;
  samples::RoomsOptions rooms;
};

using MakeScene = std::function<samples::SceneBuilder()>;

CLI::App* add_kind(CLI::App& app, std::map<CLI::App*, MakeScene>& makers, const std::string& name,
                   const std::string& description, MakeScene make) {
  CLI::App* kind = app.add_subcommand(name, description);
  kind->fallthrough(); // -o, --scale, --offset may follow the kind
  makers[kind] = std::move(make);
  return kind;
}

void add_kinds(CLI::App& app, std::map<CLI::App*, MakeScene>& makers, KindOptions& o) {
  CLI::App* cornell = add_kind(app, makers, "cornell", "the classic Cornell box (32 triangles)", [&o] {
    if (!o.cornell_with.empty()) o.cornell.with_model = o.cornell_with;
    return samples::cornell(o.cornell);
  });
  cornell->add_option("--with", o.cornell_with, "replace the tall block with this .glb/.gltf model");
  cornell->add_option("--light-scale", o.cornell.light_scale, "multiply the light's radiance (17, 12, 4)");
  cornell->add_option("--light-box", o.cornell.light_box_gap,
                      "the light as a closed emissive box 3 cm tall whose top is GAP metres below the ceiling");
  cornell->add_option("--light-albedo", o.cornell.light_albedo, "the light's albedo (0.78)");
  cornell->add_flag("--dynamic", o.cornell.dynamic, "mark the blocks (or the short block and the model) dynamic");

  CLI::App* furnace = add_kind(app, makers, "furnace", "closed emitting box: irradiance pi L / (1 - R) inside",
                               [&o] { return samples::furnace(o.furnace); });
  furnace->add_option("--albedo", o.furnace.albedo, "albedo R of every face, in [0, 1]")->capture_default_str();
  furnace->add_option("--emission", o.furnace.emission, "emitted radiance L of every face")->capture_default_str();
  furnace->add_option("--size", o.furnace.size, "edge length, metres")->capture_default_str();
  furnace->add_option("--subdivisions", o.furnace.subdivisions, "cells per face edge")->capture_default_str();

  CLI::App* leak = add_kind(app, makers, "leak", "two rooms and a thin wall, a light in one room only",
                            [&o] { return samples::leak(o.leak); });
  leak->add_option("--wall-thickness", o.leak.wall_thickness, "metres")->capture_default_str();
  leak->add_option("--intensity", o.leak.intensity, "point light, candela")->capture_default_str();
  leak->add_option("--subdivisions", o.leak.subdivisions, "cells per face edge")->capture_default_str();

  CLI::App* plane = add_kind(app, makers, "plane-light", "a plane and a point light above it: E = I cos(theta) / r^2",
                             [&o] { return samples::plane_light(o.plane_light); });
  plane->add_option("--size", o.plane_light.size, "edge length of the square plane, metres")->capture_default_str();
  plane->add_option("--height", o.plane_light.height, "light height above the plane, metres")->capture_default_str();
  plane->add_option("--intensity", o.plane_light.intensity, "point light, candela")->capture_default_str();
  plane->add_option("--albedo", o.plane_light.albedo, "albedo of the plane, in [0, 1]")->capture_default_str();
  plane->add_option("--subdivisions", o.plane_light.subdivisions, "cells per plane edge")->capture_default_str();

  CLI::App* rooms = add_kind(app, makers, "rooms", "a grid of furnished rooms (586,316 triangles by default)",
                             [&o] { return samples::rooms(o.rooms); });
  rooms->add_option("--count", o.rooms.count, "number of rooms, 1..4096")->capture_default_str();
  rooms->add_option("--detail", o.rooms.detail, "sphere subdivisions, 1..256")->capture_default_str();
  rooms->add_option("--seed", o.rooms.seed, "layout seed")->capture_default_str();
  rooms->add_option("--light-range", o.rooms.light_range, "range of each room's light in metres, 0 = unbounded")
      ->capture_default_str();
  rooms->add_flag("--windows", o.rooms.windows,
                  "a 3 x 1 m window in every wall that faces out of the grid (for a sky)");

  CLI::App* window = add_kind(app, makers, "window-room", "a closed room lit by the sun through small windows",
                              [&o] { return samples::window_room(o.window_room); });
  window->add_option("--windows", o.window_room.windows, "0.5 m windows in the +X wall, 1..4")->capture_default_str();
  window->add_option("--albedo", o.window_room.albedo, "albedo of every face")->capture_default_str();
  window->add_option("--sun", o.window_room.sun, "directional light, lux")->capture_default_str();
  CLI::App* tiny = add_kind(app, makers, "tiny-emitter", "a closed room lit by one tiny, very bright emitter",
                            [&o] { return samples::tiny_emitter(o.tiny_emitter); });
  tiny->add_option("--size", o.tiny_emitter.size, "side of the square emitter, metres")->capture_default_str();
  tiny->add_option("--radiance", o.tiny_emitter.radiance, "its radiance")->capture_default_str();
  CLI::App* cavity = add_kind(app, makers, "cavity", "a closed box of high albedo with a small emitter inside",
                              [&o] { return samples::cavity(o.cavity); });
  cavity->add_option("--albedo", o.cavity.albedo, "albedo of every face")->capture_default_str();

  CLI::App* yard = add_kind(app, makers, "courtyard", "an outdoor courtyard with a house, lit by a sky (--sky)",
                            [&o] { return samples::courtyard(o.courtyard); });
  yard->add_option("--ground-albedo", o.courtyard.ground_albedo, "albedo of the ground")->capture_default_str();

  add_kind(app, makers, "triangle", "one triangle and a point light", [] { return samples::triangle(); });
  add_kind(app, makers, "empty", "a valid glTF with no triangles", [] { return samples::empty(); });
}

void apply_placement(samples::SceneBuilder& scene, const Settings& settings) {
  samples::Transform placement;
  placement.scale = glm::vec3(settings.scale);
  if (settings.offset.size() == 3) placement.translation = {settings.offset[0], settings.offset[1], settings.offset[2]};
  if (!placement.is_identity()) scene.wrap_roots("placement", placement);
}

// `inputs`: files the scene reads (cornell --with), which the output must not overwrite.
int make(const std::string& kind, const MakeScene& make_scene, const Settings& settings,
         const std::vector<std::filesystem::path>& inputs) {
  const std::string output = settings.output.empty() ? kind + ".glb" : settings.output;
  probebake::check_output_path(output, inputs); // before a large scene is built
  samples::SceneBuilder scene = make_scene();
  apply_placement(scene, settings);
  std::vector<std::uint8_t> bytes = scene.to_glb();
  if (settings.meshopt) bytes = samples::meshopt_compress_gltf(bytes, ".");
  samples::write_file_atomically(output, bytes);
  if (!settings.quiet) {
    std::printf("make-scene: wrote %s: %zu triangles, %zu materials, %zu lights, %zu bytes\n", output.c_str(),
                scene.triangle_count(), scene.materials().size(), scene.lights().size(), bytes.size());
  }
  return exit_ok;
}

int convert(const Settings& settings) {
  if (!settings.meshopt && !settings.flip)
    throw probebake::Error(probebake::ErrorKind::usage, "convert needs --flip and/or --meshopt");
  const std::string output = settings.output.empty() ? "converted.glb" : settings.output;
  const std::vector<std::filesystem::path> inputs{settings.convert_input};
  probebake::check_output_path(output, inputs);
  std::vector<std::uint8_t> bytes;
  if (settings.flip) {
    bytes = samples::flip_sides_file(settings.convert_input);
    // The flipped .glb is self-contained: nothing left to resolve against a folder.
    if (settings.meshopt) bytes = samples::meshopt_compress_gltf(bytes, ".");
  } else {
    bytes = samples::meshopt_compress_file(settings.convert_input);
  }
  samples::write_file_atomically(output, bytes);
  if (!settings.quiet) std::printf("make-scene: wrote %s: %zu bytes\n", output.c_str(), bytes.size());
  return exit_ok;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Writes a procedural glTF 2.0 test scene (.glb) for probebake. Metres, Y up.\n"
               "Exit codes: 0 ok, 1 usage, 2 unreadable input, 3 output not writable, 4 internal error.",
               "make-scene"};
  app.set_version_flag("--version", PROBEBAKE_VERSION_STRING);
  app.require_subcommand(1);
  Settings settings;
  app.add_option("-o,--output", settings.output, "output .glb (default: KIND.glb in the current folder)");
  app.add_option("--scale", settings.scale, "scale the whole scene (light intensities are not scaled)")
      ->check(CLI::PositiveNumber);
  app.add_option("--offset", settings.offset, "move the whole scene by X Y Z metres")->expected(3);
  app.add_flag("-q,--quiet", settings.quiet, "print nothing on success");
  app.add_flag("--meshopt", settings.meshopt,
               "write geometry through meshoptimizer's encoder (EXT_meshopt_compression, as gltfpack -cc)");
  CLI::App* convert_kind = app.add_subcommand("convert", "rewrite an existing .glb/.gltf (--flip and/or --meshopt)");
  convert_kind->fallthrough();
  convert_kind->add_flag("--flip", settings.flip,
                         "reverse every triangle's winding, negate NORMAL, make every material doubleSided "
                         "(the same scene by the glTF spec, seen from the other side of every surface)");
  convert_kind->add_option("input", settings.convert_input, "the .glb or .gltf to rewrite")->required();
  KindOptions options;
  std::map<CLI::App*, MakeScene> makers;
  add_kinds(app, makers, options);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e); // --help, --version
    const std::vector<std::string> unparsed = app.remaining();
    const std::string message = app.get_subcommands().empty() && !unparsed.empty()
                                    ? "unknown kind '" + unparsed.front() + "'" // clearer than CLI11's
                                    : std::string(e.what());
    std::fprintf(stderr, "make-scene: error: %s (see make-scene --help)\n", message.c_str());
    return exit_usage;
  }
  CLI::App* kind = app.get_subcommands().front();
  std::vector<std::filesystem::path> inputs;
  if (kind->get_name() == "cornell" && !options.cornell_with.empty()) inputs.emplace_back(options.cornell_with);
  try {
    if (kind == convert_kind) return convert(settings);
    return make(kind->get_name(), makers.at(kind), settings, inputs);
  } catch (const probebake::Error& e) {
    std::fprintf(stderr, "make-scene: error: %s\n", e.what());
    return e.exit_code();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make-scene: error: internal: %s\n", e.what());
    return exit_internal;
  }
}
