// The Cornell box from the measured data published by the Cornell University Program of Computer
// Graphics ("Cornell Box Data", www.graphics.cornell.edu/online/box/data.html), millimetres in a frame
// where the camera at z = -800 looks along +Z. Albedos and the (17, 12, 4) light radiance follow the
// common physically based renditions (e.g. PBRT's and Mitsuba's cornell-box scenes).
#include "probebake/samples/scenes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/vector_relational.hpp>

namespace probebake::samples {
namespace {

using Corners = std::array<glm::vec3, 4>;

// Measured millimetres -> our metres: rotated 180 degrees about Y (so the open side faces +Z, towards
// glTF's default camera) and centred on the floor's middle.
glm::vec3 from_measured(glm::vec3 mm) { return glm::vec3(278.0f - mm.x, mm.y, 279.6f - mm.z) / 1000.0f; }

MeshData measured_quad(const Corners& mm, glm::vec3 reference_mm, Facing facing) {
  return oriented_quad(from_measured(mm[0]), from_measured(mm[1]), from_measured(mm[2]), from_measured(mm[3]),
                       from_measured(reference_mm), facing);
}

constexpr glm::vec3 room_centre_mm{278.0f, 274.4f, 279.6f};

const Corners floor_mm{{{552.8f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 559.2f}, {549.6f, 0.0f, 559.2f}}};
const Corners ceiling_mm{
    {{556.0f, 548.8f, 0.0f}, {556.0f, 548.8f, 559.2f}, {0.0f, 548.8f, 559.2f}, {0.0f, 548.8f, 0.0f}}};
const Corners back_mm{{{549.6f, 0.0f, 559.2f}, {0.0f, 0.0f, 559.2f}, {0.0f, 548.8f, 559.2f}, {556.0f, 548.8f, 559.2f}}};
const Corners green_wall_mm{{{0.0f, 0.0f, 559.2f}, {0.0f, 0.0f, 0.0f}, {0.0f, 548.8f, 0.0f}, {0.0f, 548.8f, 559.2f}}};
const Corners red_wall_mm{
    {{552.8f, 0.0f, 0.0f}, {549.6f, 0.0f, 559.2f}, {556.0f, 548.8f, 559.2f}, {556.0f, 548.8f, 0.0f}}};
// The measured light sits at the ceiling (548.8); 0.5 mm lower keeps it from coinciding with the ceiling.
const Corners light_mm{
    {{343.0f, 548.3f, 227.0f}, {343.0f, 548.3f, 332.0f}, {213.0f, 548.3f, 332.0f}, {213.0f, 548.3f, 227.0f}}};

// Blocks: top face then four sides (no bottom, as in the measured data).
const std::array<Corners, 5> short_block_mm{{
    {{{130.0f, 165.0f, 65.0f}, {82.0f, 165.0f, 225.0f}, {240.0f, 165.0f, 272.0f}, {290.0f, 165.0f, 114.0f}}},
    {{{290.0f, 0.0f, 114.0f}, {290.0f, 165.0f, 114.0f}, {240.0f, 165.0f, 272.0f}, {240.0f, 0.0f, 272.0f}}},
    {{{130.0f, 0.0f, 65.0f}, {130.0f, 165.0f, 65.0f}, {290.0f, 165.0f, 114.0f}, {290.0f, 0.0f, 114.0f}}},
    {{{82.0f, 0.0f, 225.0f}, {82.0f, 165.0f, 225.0f}, {130.0f, 165.0f, 65.0f}, {130.0f, 0.0f, 65.0f}}},
    {{{240.0f, 0.0f, 272.0f}, {240.0f, 165.0f, 272.0f}, {82.0f, 165.0f, 225.0f}, {82.0f, 0.0f, 225.0f}}},
}};
const std::array<Corners, 5> tall_block_mm{{
    {{{423.0f, 330.0f, 247.0f}, {265.0f, 330.0f, 296.0f}, {314.0f, 330.0f, 456.0f}, {472.0f, 330.0f, 406.0f}}},
    {{{423.0f, 0.0f, 247.0f}, {423.0f, 330.0f, 247.0f}, {472.0f, 330.0f, 406.0f}, {472.0f, 0.0f, 406.0f}}},
    {{{472.0f, 0.0f, 406.0f}, {472.0f, 330.0f, 406.0f}, {314.0f, 330.0f, 456.0f}, {314.0f, 0.0f, 456.0f}}},
    {{{314.0f, 0.0f, 456.0f}, {314.0f, 330.0f, 456.0f}, {265.0f, 330.0f, 296.0f}, {265.0f, 0.0f, 296.0f}}},
    {{{265.0f, 0.0f, 296.0f}, {265.0f, 330.0f, 296.0f}, {423.0f, 330.0f, 247.0f}, {423.0f, 0.0f, 247.0f}}},
}};

MeshData block(const std::array<Corners, 5>& faces_mm) {
  glm::vec3 centre(0.0f); // middle of the top face, at half height: inside the block
  for (const glm::vec3& corner : faces_mm[0]) centre += corner * 0.25f;
  centre.y *= 0.5f;
  MeshData mesh;
  for (const Corners& face : faces_mm) mesh.append(measured_quad(face, centre, Facing::outward));
  return mesh;
}

// The light's footprint as a closed box 3 cm tall, its top `gap` below the ceiling, every face outward.
MeshData light_box(float gap) {
  const glm::vec3 a = from_measured(light_mm[0]), c = from_measured(light_mm[2]);
  const float top = from_measured(ceiling_mm[0]).y - gap;
  return box(glm::vec3(std::min(a.x, c.x), top - 0.03f, std::min(a.z, c.z)),
             glm::vec3(std::max(a.x, c.x), top, std::max(a.z, c.z)), Facing::outward);
}

NodeId add_object(SceneBuilder& scene, const char* name, MeshData mesh, MaterialId material) {
  return scene.add_mesh_node(name, scene.add_mesh(name, std::move(mesh), material));
}

// The model's uniform scale and translation so that it fits 60% of the box and stands centred on the floor.
Transform fit_in_box(const Bounds& model) {
  const glm::vec3 box_extent(0.5496f, 0.5488f, 0.5592f); // the smallest inner extents of the measured box
  float scale = std::numeric_limits<float>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    if (model.extent()[axis] > 0.0f) scale = std::min(scale, 0.6f * box_extent[axis] / model.extent()[axis]);
  }
  Transform fit;
  fit.scale = glm::vec3(scale);
  fit.translation = -scale * glm::vec3(model.centre().x, model.min.y, model.centre().z);
  return fit;
}

} // namespace

SceneBuilder cornell(const CornellOptions& options) {
  if (options.light_box_gap && !(*options.light_box_gap > 0.0f && *options.light_box_gap < 0.5f)) {
    throw Error(ErrorKind::usage, "cornell: --light-box gap must be in (0, 0.5) metres");
  }
  if (!std::isfinite(options.light_scale) || options.light_scale < 0.0f) {
    throw Error(ErrorKind::usage, "cornell: --light-scale must be finite and >= 0");
  }
  SceneBuilder scene("cornell");
  const MaterialId white = scene.add_material({"white", {0.725f, 0.71f, 0.68f}, {}});
  const MaterialId red = scene.add_material({"red", {0.63f, 0.065f, 0.05f}, {}});
  const MaterialId green = scene.add_material({"green", {0.14f, 0.45f, 0.091f}, {}});
  const glm::vec3 radiance = glm::vec3(cornell_light_radiance[0], cornell_light_radiance[1], cornell_light_radiance[2]);
  // The light box is double-sided, as exporters write it (Blender's default): its inside is then a closed
  // cavity of emitting walls, open space by the glTF rules.
  const MaterialId light = scene.add_material(
      {"light", glm::vec3(options.light_albedo), radiance * options.light_scale, options.light_box_gap.has_value()});

  add_object(scene, "floor", measured_quad(floor_mm, room_centre_mm, Facing::inward), white);
  add_object(scene, "ceiling", measured_quad(ceiling_mm, room_centre_mm, Facing::inward), white);
  add_object(scene, "back_wall", measured_quad(back_mm, room_centre_mm, Facing::inward), white);
  add_object(scene, "red_wall", measured_quad(red_wall_mm, room_centre_mm, Facing::inward), red);
  add_object(scene, "green_wall", measured_quad(green_wall_mm, room_centre_mm, Facing::inward), green);
  add_object(scene, "light",
             options.light_box_gap ? light_box(*options.light_box_gap)
                                   : measured_quad(light_mm, room_centre_mm, Facing::inward),
             light);
  scene.set_dynamic(add_object(scene, "short_block", block(short_block_mm), white), options.dynamic);
  if (!options.with_model) {
    scene.set_dynamic(add_object(scene, "tall_block", block(tall_block_mm), white), options.dynamic);
    return scene;
  }
  const MeshId model = scene.add_model(*options.with_model, "model");
  const Bounds bounds = scene.mesh_bounds(model);
  if (glm::all(glm::equal(bounds.extent(), glm::vec3(0.0f)))) {
    throw Error(ErrorKind::input, "cornell: the model '" + options.with_model->string() + "' has no extent");
  }
  scene.set_dynamic(scene.add_mesh_node("model", model, fit_in_box(bounds)), options.dynamic);
  return scene;
}

} // namespace probebake::samples
