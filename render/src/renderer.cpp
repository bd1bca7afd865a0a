#include <algorithm>
#include <cmath>

#include <fmt/core.h>
#include <glm/geometric.hpp>

#include "canvas.h"
#include "probebake/lighting/direct_light.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/formats/error.h"
#include "probebake/formats/octree.h"
#include "probebake/render/render.h"

namespace probebake::render {
namespace {

constexpr std::array<std::string_view, 8> kViewNames = {"final", "indirect",   "probes",    "octree",
                                                        "svo",   "relocation", "reference", "reference-indirect"};

float luminance(glm::vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// One hue per octree depth (0-12), distinct neighbours.
glm::vec3 depth_colour(int depth) {
  // clang-format off
  static constexpr std::array<glm::vec3, 13> kPalette = {{
      {0.60f, 0.60f, 0.60f}, {0.12f, 0.47f, 0.71f}, {1.00f, 0.50f, 0.05f}, {0.17f, 0.63f, 0.17f}, {0.84f, 0.15f, 0.16f},
      {0.58f, 0.40f, 0.74f}, {0.55f, 0.34f, 0.29f}, {0.89f, 0.47f, 0.76f}, {0.74f, 0.74f, 0.13f}, {0.09f, 0.75f, 0.81f},
      {0.20f, 0.20f, 0.55f}, {0.55f, 0.80f, 0.30f}, {0.95f, 0.85f, 0.55f}}};
  // clang-format on
  return kPalette[std::size_t(std::clamp(depth, 0, 12))];
}

// Lookups that blend 1, 2, 3 or 4 probes: dark blue to yellow; none: magenta.
glm::vec3 stencil_colour(int probes) {
  static constexpr std::array<glm::vec3, 5> kRamp = {
      {{1.0f, 0.0f, 1.0f}, {0.15f, 0.20f, 0.65f}, {0.10f, 0.60f, 0.60f}, {0.45f, 0.80f, 0.25f}, {0.98f, 0.90f, 0.15f}}};
  return kRamp[std::size_t(std::clamp(probes, 0, 4))];
}

// Whether `p` lies within `width` of a face of the cube (min, size) that the surface with normal `n` crosses:
// the cube's border drawn as a line on the surface.
bool on_cube_border(glm::vec3 p, glm::vec3 n, glm::vec3 min, float size, float width) {
  for (int a = 0; a < 3; ++a) {
    if (std::abs(n[a]) > 0.9f) continue; // a face parallel to the surface would colour it whole
    const float d = std::min(p[a] - min[a], min[a] + size - p[a]);
    if (d < width) return true;
  }
  return false;
}

float cube_size(const gpu::VolumeInfo& info, int depth) {
  return info.root_size / float(1 << std::clamp(depth, 0, 30));
}

// A tenth of the probe's cell: its octree cube, the grid's cell, or (skeleton) a quarter of an SVO voxel.
float default_radius(const gpu::VolumeInfo& info, const gpu::Probe& probe) {
  if (probe.node >= 0) return 0.1f * cube_size(info, probe.depth);
  if (info.grid_resolution > 0) return 0.1f * info.root_size / float(info.grid_resolution);
  return 0.25f * cube_size(info, info.svo_depth);
}

} // namespace

struct Renderer::Canvas : detail::Canvas {};

std::string_view view_name(View view) { return kViewNames[std::size_t(view)]; }

std::optional<View> view_from_name(std::string_view name) {
  for (View v : kEveryView)
    if (view_name(v) == name) return v;
  return std::nullopt;
}

bool is_irradiance_view(View view) {
  return view == View::final || view == View::indirect || view == View::probes || view == View::reference ||
         view == View::reference_indirect;
}

bool reads_probes(View view) { return view == View::final || view == View::indirect || view == View::probes; }

std::string_view view_legend(View view) {
  switch (view) {
  case View::final:
  case View::indirect:
  case View::reference:
  case View::reference_indirect: return "";
  case View::probes: return "spheres: each live probe's irradiance in every direction, over the indirect view in grey";
  case View::octree:
    return "colour: depth of the octree leaf (0 grey, 1 blue, 2 orange, 3 green, 4 red, 5 purple, 6 brown, ...); dark "
           "lines: leaf borders";
  case View::svo:
    return "colour: probes the lookup blends (1 dark blue, 2 teal, 3 green, 4 yellow); magenta: none (direct light "
           "only); dark lines: SVO voxels";
  case View::relocation:
    return "blue-grey: probe at its cube's centre; orange: moved out of geometry (line from the centre); red: leaf "
           "without a probe";
  }
  return "";
}

Renderer::Renderer(RenderInputs inputs) : in_(std::move(inputs)), frame_((bake::check_camera(in_.camera), in_.camera)) {
  if (in_.scene == nullptr || in_.rays == nullptr)
    throw Error(ErrorKind::internal, "Renderer: scene and rays are required");
  hits_ = bake::camera_surface_points(*in_.rays, in_.camera, &distances_);
}

const std::vector<glm::vec3>& Renderer::indirect() {
  if (sampled_) return indirect_;
  if (!in_.indirect) throw Error(ErrorKind::usage, "the irradiance views need the probes' lookup");
  std::vector<glm::vec3> positions, normals;
  for (const auto& hit : hits_)
    if (hit) positions.push_back(hit->position), normals.push_back(hit->normal);
  const std::vector<glm::vec3> values = in_.indirect(positions, normals);
  if (values.size() != positions.size())
    throw Error(ErrorKind::internal,
                fmt::format("the lookup returned {} values for {} points", values.size(), positions.size()));
  indirect_.assign(hits_.size(), glm::vec3(0.0f));
  for (std::size_t i = 0, k = 0; i < hits_.size(); ++i)
    if (hits_[i]) indirect_[i] = values[k++];
  sampled_ = true;
  return indirect_;
}

const formats::ProbeVolume& Renderer::volume() const {
  if (in_.volume == nullptr) throw Error(ErrorKind::usage, "the debug views need the probe volume");
  return *in_.volume;
}

// Three quarters of a pixel's footprint at `p`: cell borders drawn on surfaces stay about a pixel wide.
float Renderer::border_width(glm::vec3 p) const {
  return 0.75f * 2.0f * frame_.tan_half_y / float(frame_.height) * glm::length(p - frame_.position);
}

// Surfaces lit from the eye, so that shapes read in the flat-coloured views.
glm::vec3 Renderer::shade(std::size_t pixel, glm::vec3 colour) const {
  const float facing = std::abs(glm::dot(hits_[pixel]->normal, frame_.pixel_direction(pixel)));
  return colour * (0.35f + 0.65f * facing);
}

Renderer::Canvas Renderer::surfaces(const std::function<glm::vec3(std::size_t)>& colour) const {
  Canvas canvas;
  canvas.image = {in_.camera.width, in_.camera.height, std::vector<glm::vec3>(hits_.size(), glm::vec3(0.0f))};
  canvas.depth = distances_; // the back of a single-sided surface is black but hides what lies behind it
  for (std::size_t i = 0; i < hits_.size(); ++i)
    if (hits_[i]) canvas.image.pixels[i] = colour(i);
  return canvas;
}

bake::Image Renderer::render(View view) {
  switch (view) {
  case View::final: return render_irradiance(true);
  case View::indirect: return render_irradiance(false);
  case View::reference: return render_reference(false);
  case View::reference_indirect: return render_reference(true);
  case View::probes: return render_probes();
  case View::octree: return render_octree();
  case View::svo: return render_svo();
  case View::relocation: return render_relocation();
  }
  throw Error(ErrorKind::internal, "unknown view");
}

bake::Image Renderer::render_irradiance(bool with_direct) {
  const std::vector<glm::vec3>& probes = indirect();
  if (!with_direct) return surfaces([&](std::size_t i) { return probes[i]; }).image;
  lighting::LightingSettings light_settings;
  light_settings.emissive_as_lights = in_.emitters_as_lights;
  const lighting::detail::DirectLighting direct(*in_.scene, *in_.rays, light_settings); // the bake's own
  return surfaces([&](std::size_t i) { return probes[i] + direct.irradiance(hits_[i]->position, hits_[i]->normal); })
      .image;
}

// The path tracer at every pixel's first hit (the receivers of `probebake reference`, one per pixel).
bake::Image Renderer::render_reference(bool indirect_only) {
  if (!reference_) {
    std::vector<bake::SamplePoint> points;
    for (const auto& hit : hits_)
      if (hit) points.push_back(*hit);
    reference_ = bake::reference_irradiance(*in_.scene, *in_.rays, points, in_.reference);
  }
  std::vector<std::size_t> point_of(hits_.size(), 0); // pixel -> its traced point
  for (std::size_t i = 0, k = 0; i < hits_.size(); ++i)
    if (hits_[i]) point_of[i] = k++;
  return surfaces([&](std::size_t i) {
           const std::size_t k = point_of[i];
           return indirect_only ? reference_->irradiance[k] - reference_->direct[k] : reference_->irradiance[k];
         })
      .image;
}

bake::Image Renderer::render_probes() {
  const std::vector<glm::vec3>& probes = indirect();
  Canvas canvas = surfaces([&](std::size_t i) { return glm::vec3(0.3f * luminance(probes[i])); });
  const formats::ProbeVolume& v = volume();
  for (const gpu::Probe& probe : v.probes) {
    if (probe.link == 0) continue;
    const float radius = in_.probe_radius > 0.0f ? in_.probe_radius : default_radius(v.info, probe);
    canvas.sphere(frame_, probe.position, radius, [&](glm::vec3 n) {
      return glm::max(probe_index::evaluate_sh(probe.irradiance_sh, n), glm::vec3(0.0f));
    });
  }
  return canvas.image;
}

bake::Image Renderer::render_octree() const {
  const formats::ProbeVolume& v = volume();
  if (v.info.placement != gpu::PLACEMENT_OCTREE)
    throw Error(ErrorKind::usage, "the octree view needs a volume with octree placement");
  return surfaces([&](std::size_t i) {
           const bake::SamplePoint& hit = *hits_[i];
           const auto leaf = formats::find_leaf(v, hit.position);
           if (!leaf) return shade(i, glm::vec3(0.25f));
           const glm::vec3 colour = depth_colour(leaf->depth);
           return shade(i, on_cube_border(hit.position, hit.normal, leaf->min, leaf->size, border_width(hit.position))
                               ? 0.25f * colour
                               : colour);
         })
      .image;
}

bake::Image Renderer::render_svo() const {
  const formats::ProbeVolume& v = volume();
  if (v.svo_nodes.empty()) throw Error(ErrorKind::usage, "the svo view needs a volume with an SVO probe index");
  return surfaces([&](std::size_t i) {
           const bake::SamplePoint& hit = *hits_[i];
           const probe_index::ProbeStencil stencil = probe_index::svo_stencil(v, hit.position, hit.normal);
           int used = 0;
           for (int k = 0; k < gpu::SVO_PROBES_PER_LEAF; ++k)
             used += stencil.probes[k] >= 0 && stencil.weights[k] > 0.0f;
           glm::vec3 colour = stencil_colour(used);
           int depth = 0;
           const glm::vec3 p = hit.position + hit.normal * probe_index::normal_bias(v.info); // where the lookup looks
           if (probe_index::find_svo_leaf(v, p, &depth) >= 0) {
             const float size = cube_size(v.info, depth);
             const glm::vec3 min = v.info.root_min + glm::floor((p - v.info.root_min) / size) * size;
             if (on_cube_border(p, hit.normal, min, size, border_width(p))) colour *= 0.25f;
           }
           return shade(i, colour);
         })
      .image;
}

bake::Image Renderer::render_relocation() const {
  const formats::ProbeVolume& v = volume();
  if (v.info.placement != gpu::PLACEMENT_OCTREE)
    throw Error(ErrorKind::usage,
                "the relocation view needs a volume with octree placement (probes start at their cube's centre)");
  Canvas canvas = surfaces([&](std::size_t i) { return shade(i, glm::vec3(0.5f)); });
  formats::for_each_leaf(v, [&](const formats::NodeCube& leaf) {
    const int element = v.octree[std::size_t(leaf.node)];
    const float cell_radius = in_.probe_radius > 0.0f ? in_.probe_radius : 0.1f * leaf.size;
    if (element == 0) {
      canvas.sphere(frame_, leaf.centre(), 0.6f * cell_radius,
                    [&](glm::vec3 n) { return kLeafWithoutProbeColour * (0.6f + 0.4f * std::abs(n.y)); });
      return;
    }
    if (element > 0 || std::size_t(~element) >= v.probes.size()) return; // a parent, or a link validate() refuses
    const glm::vec3 position = v.probes[std::size_t(~element)].position;
    const bool moved = glm::length(position - leaf.centre()) > 1e-4f * leaf.size;
    const glm::vec3 colour = moved ? kRelocatedProbeColour : kProbeAtCentreColour;
    canvas.sphere(frame_, position, cell_radius, [&](glm::vec3 n) { return colour * (0.6f + 0.4f * std::abs(n.y)); });
    if (moved) canvas.line(frame_, leaf.centre(), position, kRelocatedProbeColour);
  });
  return canvas.image;
}

} // namespace probebake::render
