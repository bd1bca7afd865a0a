// Embree 3 triangle BVH over the flattened scene, in Embree-owned buffers; the device and scene handles are
// owned here and released in the destructor. The BVH is built on one thread (run_on_one_thread) so that the
// tree, and with it the choice between exactly coincident hits, is the same on every run and for every
// --threads (bakes must be deterministic); queries then run on all threads.
#include <embree3/rtcore.h>
#include <fmt/core.h>
#include <glm/geometric.hpp>

#include "probebake/scene/ray_scene.h"
#include "probebake/formats/error.h"
#include "probebake/common/parallel.h"

namespace probebake::scene {
namespace {

void throw_embree_error(RTCDevice device, const char* what) {
  throw Error(ErrorKind::internal, fmt::format("Embree: {} failed (error {})", what, int(rtcGetDeviceError(device))));
}

} // namespace

struct RayScene::Impl {
  const Scene* scene = nullptr;
  RTCDevice device = nullptr;
  RTCScene handle = nullptr;

  ~Impl() {
    if (handle != nullptr) rtcReleaseScene(handle);
    if (device != nullptr) rtcReleaseDevice(device);
  }
};

RayScene::RayScene(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  impl_->scene = &scene;
  impl_->device = rtcNewDevice(nullptr);
  if (impl_->device == nullptr) throw Error(ErrorKind::internal, "Embree: rtcNewDevice failed");
  impl_->handle = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->handle, RTC_BUILD_QUALITY_HIGH);
  if (!scene.triangles.empty()) {
    RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree reads 16 bytes past the last vertex; the scene's vector has no such padding, so copy.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 sizeof(float) * 3, scene.positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   sizeof(unsigned) * 3, scene.triangles.size()));
    if (vertices == nullptr || indices == nullptr) throw_embree_error(impl_->device, "buffer allocation");
    for (std::size_t i = 0; i < scene.positions.size(); ++i)
      for (int c = 0; c < 3; ++c) vertices[3 * i + std::size_t(c)] = scene.positions[i][c];
    for (std::size_t i = 0; i < scene.triangles.size(); ++i)
      for (int c = 0; c < 3; ++c) indices[3 * i + std::size_t(c)] = scene.triangles[i][c];
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(impl_->handle, geometry);
    rtcReleaseGeometry(geometry);
  }
  run_on_one_thread([&] { rtcCommitScene(impl_->handle); });
  if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE) throw_embree_error(impl_->device, "scene build");
}

RayScene::~RayScene() = default;
RayScene::RayScene(RayScene&&) noexcept = default;
RayScene& RayScene::operator=(RayScene&&) noexcept = default;

const Scene& RayScene::scene() const { return *impl_->scene; }

std::optional<RayHit> RayScene::intersect(const glm::vec3& origin, const glm::vec3& direction, float t_min,
                                          float t_max) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayhit{};
  rayhit.ray.org_x = origin.x;
  rayhit.ray.org_y = origin.y;
  rayhit.ray.org_z = origin.z;
  rayhit.ray.dir_x = direction.x;
  rayhit.ray.dir_y = direction.y;
  rayhit.ray.dir_z = direction.z;
  rayhit.ray.tnear = t_min;
  rayhit.ray.tfar = t_max;
  rayhit.ray.mask = 0xffffffffu;
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->handle, &context, &rayhit);
  if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  RayHit hit;
  hit.distance = rayhit.ray.tfar;
  hit.triangle = rayhit.hit.primID;
  hit.u = rayhit.hit.u;
  hit.v = rayhit.hit.v;
  // Embree's Ng is cross(e1, e0) for CCW winding, i.e. it points to the back side; use our own normal.
  hit.normal = triangle_normal(*impl_->scene, hit.triangle);
  hit.backface = glm::dot(hit.normal, direction) > 0.0f;
  hit.double_sided = is_double_sided(*impl_->scene, hit.triangle);
  return hit;
}

bool RayScene::occluded(const glm::vec3& origin, const glm::vec3& direction, float t_min, float t_max) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = origin.x;
  ray.org_y = origin.y;
  ray.org_z = origin.z;
  ray.dir_x = direction.x;
  ray.dir_y = direction.y;
  ray.dir_z = direction.z;
  ray.tnear = t_min;
  ray.tfar = t_max;
  ray.mask = 0xffffffffu;
  rtcOccluded1(impl_->handle, &context, &ray);
  return ray.tfar < 0.0f; // Embree sets tfar to -inf on a hit
}

} // namespace probebake::scene
