// Validator phase for the sky (format 1.9, sky_map.h): only beside the lighting sections, a header of sizes in
// range and its texels, finite radiance >= 0, and a physical sky's turbidity, sun direction and sun light.
#include "probebake/formats/sky_section.h"
#include "text.h"
#include "validate_internal.h"

namespace probebake::formats::detail {
namespace {

constexpr const char* kInvariant = "sky";
constexpr const char* kSection = "sky";

void check_texels(const SkyView& view, Reporter& out) {
  for (std::size_t k = 0; k < view.texels.size(); ++k) {
    const glm::vec3 t = view.texels[k];
    if (!finite3(t) || t.x < 0.0f || t.y < 0.0f || t.z < 0.0f) {
      out.add(kInvariant, kSection, static_cast<long long>(k), "texel radiance is not finite and >= 0");
      return; // one report: a corrupt map has many
    }
  }
}

void check_sun(const ProbeVolume& volume, const gpu::SkyHeader& h, Reporter& out) {
  if (h.kind == gpu::SKY_KIND_ENVIRONMENT) {
    if (!zero_bits({h.turbidity, h.sun_direction.x, h.sun_direction.y, h.sun_direction.z}) || h.sun_light != -1)
      out.add(kInvariant, kSection, -1, "an environment with a turbidity, sun direction or sun light");
    return;
  }
  if (!(h.turbidity >= 1.7f && h.turbidity <= 10.0f))
    out.add(kInvariant, kSection, -1, concat("turbidity ", h.turbidity, " outside [1.7, 10]"));
  if (!finite3(h.sun_direction) || !unit(h.sun_direction))
    out.add(kInvariant, kSection, -1, "sun direction is not a unit vector");
  if (h.sun_light < -1 || h.sun_light >= static_cast<int>(volume.punctual_lights.size())) {
    out.add(kInvariant, kSection, -1, concat("sun light ", h.sun_light, " is not a punctual light"));
    return;
  }
  if (h.sun_light >= 0 && volume.punctual_lights[std::size_t(h.sun_light)].type != gpu::LIGHT_DIRECTIONAL)
    out.add(kInvariant, kSection, -1, concat("sun light ", h.sun_light, " is not directional"));
}

} // namespace

void check_sky(const ProbeVolume& volume, Reporter& out) {
  if (volume.sky.empty()) return;
  if (!volume.lighting) {
    out.add(kInvariant, kSection, -1, "a sky without the lighting sections");
    return;
  }
  const std::optional<SkyView> view = sky_view(volume.sky);
  if (!view) {
    out.add(kInvariant, kSection, -1,
            concat(volume.sky.size(), " words are not a header and its texels (width 4..", gpu::SKY_MAX_WIDTH,
                   ", height 2..", gpu::SKY_MAX_HEIGHT, ")"));
    return;
  }
  if (view->header.kind != gpu::SKY_KIND_ENVIRONMENT && view->header.kind != gpu::SKY_KIND_PHYSICAL) {
    out.add(kInvariant, kSection, -1, concat("kind ", view->header.kind, " is not a sky kind"));
    return;
  }
  check_sun(volume, view->header, out);
  check_texels(*view, out);
}

} // namespace probebake::formats::detail
