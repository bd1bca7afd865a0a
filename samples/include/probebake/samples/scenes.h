// Procedural test scenes for the probe baker (what `make-scene KIND` writes).
//
// All scenes: metres, Y up, counter-clockwise front faces, room surfaces facing into the rooms. Each
// function validates its options (probebake::Error with ErrorKind::usage) and returns a SceneBuilder
// ready to be written; same options, same bytes.
#pragma once

#include "probebake/samples/scene_builder.h"

#include <cstdint>
#include <filesystem>
#include <optional>

namespace probebake::samples {

// The classic Cornell box from its measured data (Cornell University Program of Computer Graphics),
// rotated 180 degrees about Y and centred so that it spans x, z in about [-0.28, 0.28] and y in
// [0, 0.5488], open towards +Z (glTF's default camera looks down -Z): red wall at -X, green wall at +X,
// white floor, ceiling, back wall and blocks, and a 0.13 x 0.105 m light quad 0.5 mm below the ceiling.
struct CornellOptions {
  // Replaces the tall block with this model's triangles, scaled uniformly to fit 60% of the box and
  // centred on the middle of the floor (it may intersect the short block).
  std::optional<std::filesystem::path> with_model;
  float light_scale = 1.0f; // multiplies the light's radiance cornell_light_radiance, >= 0
  // When set, the light is a closed emissive box (the light's footprint, 3 cm tall, every face emitting)
  // whose top lies this many metres below the ceiling: the stiff case of issue #39 (0.00013 m).
  std::optional<float> light_box_gap;
  float light_albedo = 0.78f; // the light's diffuse albedo, in [0, 1]
  // Marks the blocks (or the short block and the model) dynamic: objects the runtime moves (the octree
  // thesis's animated Cornell test, `probebake run --animate`).
  bool dynamic = false;
};
inline constexpr float cornell_light_radiance[3] = {17.0f, 12.0f, 4.0f};
SceneBuilder cornell(const CornellOptions& options = {});

// A closed cube [-size/2, size/2]^3 whose every face looks inward, with one material of albedo R and
// emitted radiance L: irradiance is pi L / (1 - R) at every point inside, in every direction.
struct FurnaceOptions {
  float albedo = 0.5f;   // in [0, 1]
  float emission = 1.0f; // >= 0; KHR_materials_emissive_strength is used when > 1
  float size = 1.0f;     // > 0, metres
  int subdivisions = 1;  // cells per face edge: 12 * subdivisions^2 triangles
};
SceneBuilder furnace(const FurnaceOptions& options = {});

// Two closed rooms (3 x 2.5 x 3 m inside) side by side along X, separated by a wall of the given
// thickness, with a point light at the centre of the -X room only: any light in the +X room is a leak.
struct LeakOptions {
  float wall_thickness = 0.02f; // > 0, metres
  float intensity = 100.0f;     // candela, >= 0
  int subdivisions = 1;         // per room face edge
};
SceneBuilder leak(const LeakOptions& options = {});

// A size x size square at y = 0 facing +Y, centred on the origin, and a point light of `intensity`
// candela at (0, height, 0): irradiance on the plane at distance r and incidence angle theta is
// E = I cos(theta) / r^2 (exact everywhere when albedo is 0, the default).
struct PlaneLightOptions {
  float size = 10.0f;
  float height = 1.0f;
  float intensity = 100.0f;
  float albedo = 0.0f;
  int subdivisions = 1;
};
SceneBuilder plane_light(const PlaneLightOptions& options = {});

// A grid of closed 6 x 3 x 6 m rooms (walls 0.2 m thick) with furniture, cube spheres, a rug, a point
// light each and an emissive ceiling panel in every third room (index % 3 == 0); one sphere per room is
// dynamic. The shell and sphere meshes are instanced. Triangles: count * (7844 + 72 * detail^2) +
// 2 * ceil(count / 3); the defaults give 586,316. Room i sits at (6.2 * (i % columns), 0,
// 6.2 * (i / columns)) with columns = ceil(sqrt(count)).
struct RoomsOptions {
  int count = 16;           // rooms, 1..4096
  int detail = 20;          // cube sphere subdivisions, 1..256
  std::uint32_t seed = 1;   // layout, colours and light intensities
  float light_range = 0.0f; // KHR_lights_punctual range of every room's light in metres (0 = unbounded)
  // A 3 x 1 m window (1-2 m high, centred) in every wall that faces out of the grid, so that a sky lights the rooms
  // (192 triangles fewer per window); the rooms stay apart, the gaps between them closed by no wall.
  bool windows = false;
};
SceneBuilder rooms(const RoomsOptions& options = {});

// Stiff scenes (issue #39, scene_stiff.cpp). A closed 4 x 2.5 x 4 m room (faces inward, x, z in -2..2, y in
// 0..2.5) lit only by a directional sun (`sun` lux) through `windows` 0.5 x 0.5 m openings in its +X wall.
struct WindowRoomOptions {
  int windows = 2;     // 1..4
  float albedo = 0.7f; // every face
  float sun = 10.0f;   // lux
};
SceneBuilder window_room(const WindowRoomOptions& options = {});
// The same room shut, lit only by a square emitter of side `size` and radiance `radiance` facing down 1 cm
// under the ceiling's centre.
struct TinyEmitterOptions {
  float size = 0.01f;         // metres
  float radiance = 100000.0f; // W/(m^2 sr)
};
SceneBuilder tiny_emitter(const TinyEmitterOptions& options = {});
// A closed 1 m box of albedo `albedo` with a block inside and a 10 cm emitter (radiance 10) under its
// ceiling: probe irradiance is bounded by pi 10 / (1 - albedo).
struct CavityOptions {
  float albedo = 0.95f;
};
SceneBuilder cavity(const CavityOptions& options = {});

// Outdoor (issue #43, scene_outdoor.cpp): a 40 m ground square around a courtyard closed on three sides by
// blocks 6-12 m high (x, z in -10..10), with a 4 x 2.5 x 4 m house (double-sided shell, two 0.5 m windows in
// its +X wall) at (-3, 0, 5). No lights: a sky (`probebake --sky physical --sun ELEVATION,AZIMUTH`) lights it.
struct CourtyardOptions {
  float ground_albedo = 0.3f;
};
SceneBuilder courtyard(const CourtyardOptions& options = {});

// One white triangle (0,0,0), (1,0,0), (0,0,-1) facing +Y, lit by a 10 cd point light 1 m above.
SceneBuilder triangle();

// A valid glTF with one empty scene: no nodes, meshes, materials or lights.
SceneBuilder empty();

} // namespace probebake::samples
