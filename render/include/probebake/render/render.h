// Pictures of a probe volume in its scene (`probebake render`): the scene shaded with the probes'
// irradiance, and debug views that show where the probes are, how the octree and the SVO divide space and
// which probes the bake moved out of geometry, so that a person can see leaks, seams and holes.
//
// Primary visibility is Embree's (camera_surface_points, the same rays as `probebake reference --image`),
// direct light is the bake's (lighting::direct_irradiance), and the probes' irradiance comes from an IndirectSampler
// the caller gives: the runtime's lookup on its Vulkan device in `probebake render`, probe_index::sample_irradiance
// on the CPU in tests. Irradiance views hold W/m^2 (compare them with `reference --image` and
// `eval --error-map`); debug views hold display colours in [0, 1].
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/eval/reference.h"
#include "probebake/formats/probe_volume.h"
#include "probebake/scene/ray_scene.h"
#include "probebake/scene/scene.h"

namespace probebake::render {

enum class View {
  final,              // direct + probe irradiance at the first visible surface (W/m^2)
  indirect,           // the probe lookup alone: what a game takes from the volume (W/m^2)
  probes,             // every live probe as a sphere showing its irradiance SH in each direction, over the indirect
                      // view in grey (W/m^2)
  octree,             // surfaces coloured by the depth of the octree leaf they lie in, leaf borders dark (colour)
  svo,                // surfaces coloured by the probes their SVO lookup blends (1-4), magenta where it finds none
                      // and the runtime shows direct light only; SVO voxel borders dark (colour)
  relocation,         // probes at their cube's centre (blue-grey), probes the bake moved out of geometry (orange,
                      // a line from the centre they left), leaves without a probe (red, at the cube's centre) (colour)
  reference,          // the path-traced irradiance at the first visible surface, to set beside final (W/m^2)
  reference_indirect, // the same less its direct part, to set beside indirect (W/m^2)
};
// What `--view all` renders: every view but the path-traced ones, which cost minutes.
inline constexpr std::array<View, 6> kViews = {View::final,  View::indirect, View::probes,
                                               View::octree, View::svo,      View::relocation};
inline constexpr std::array<View, 8> kEveryView = {
    View::final, View::indirect,   View::probes,    View::octree,
    View::svo,   View::relocation, View::reference, View::reference_indirect};

std::string_view view_name(View view);
std::optional<View> view_from_name(std::string_view name);
// Whether the view's pixels are irradiance (W/m^2) rather than display colours.
bool is_irradiance_view(View view);
// Whether the view needs the probes' lookup (final, indirect, probes).
bool reads_probes(View view);
// One line that says what the view's colours mean (empty for the irradiance images).
std::string_view view_legend(View view);

// The relocation view's colours (the spheres are shaded by up to 40 % where they face up or down).
inline constexpr glm::vec3 kProbeAtCentreColour{0.55f, 0.62f, 0.75f};
inline constexpr glm::vec3 kRelocatedProbeColour{1.0f, 0.55f, 0.08f};
inline constexpr glm::vec3 kLeafWithoutProbeColour{0.90f, 0.10f, 0.10f};

// Irradiance the volume's probes give at surface points (out[i] for positions[i], normals[i]).
using IndirectSampler =
    std::function<std::vector<glm::vec3>(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals)>;

struct RenderInputs {
  const scene::Scene* scene = nullptr;          // in the pose the volume was lit for
  const scene::RayScene* rays = nullptr;        // built over *scene
  const formats::ProbeVolume* volume = nullptr; // the probes, octree and SVO (debug views only)
  bake::Camera camera;
  IndirectSampler indirect;          // for final, indirect and probes
  bool emitters_as_lights = false;   // the volume's emitters are lit as lights (direct light)
  float probe_radius = 0.0f;         // sphere radius in metres; 0: a tenth of each probe's cell
  bake::ReferenceSettings reference; // the path tracer of the reference views (paths per pixel)
};

// Renders views of one camera; the primary rays are cast once, the probe lookups made once.
class Renderer {
public:
  explicit Renderer(RenderInputs inputs); // Error(usage) on an unusable camera
  // Error(usage) when the inputs cannot show the view: a debug view without a volume, octree or relocation
  // of a volume without octree placement, svo of a volume without an SVO, final, indirect or probes
  // without a lookup.
  bake::Image render(View view);

private:
  struct Canvas;
  const std::vector<glm::vec3>& indirect();
  Canvas surfaces(const std::function<glm::vec3(std::size_t pixel)>& colour) const;
  glm::vec3 shade(std::size_t pixel, glm::vec3 colour) const;
  float border_width(glm::vec3 p) const;
  bake::Image render_irradiance(bool with_direct);
  bake::Image render_reference(bool indirect_only);
  bake::Image render_probes();
  bake::Image render_octree() const;
  bake::Image render_svo() const;
  bake::Image render_relocation() const;
  const formats::ProbeVolume& volume() const;

  RenderInputs in_;
  bake::CameraFrame frame_;
  std::vector<std::optional<bake::SamplePoint>> hits_;
  std::vector<float> distances_;    // to the first hit on either side, +inf for a miss
  std::vector<glm::vec3> indirect_; // per pixel, sampled on first use
  bool sampled_ = false;
  std::optional<bake::ReferenceResult> reference_; // per hit pixel, traced on first use
};

// PNG display scale of an irradiance image: 1 / the 99th percentile of its luminance (1 for a black image).
float exposure_of(const bake::Image& image);
// Writes `image` atomically by the path's extension: .exr (linear floats, as they are) or .png (8-bit sRGB
// of pixel * exposure, clipped). Error(usage) for another extension, Error(output) when it cannot be written.
void write_image(const std::filesystem::path& path, const bake::Image& image, float exposure = 1.0f);

} // namespace probebake::render
