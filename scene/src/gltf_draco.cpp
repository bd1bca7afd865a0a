// KHR_draco_mesh_compression: decodes a primitive's Draco bitstream with the Draco library and checks every
// attribute id, point index and face index before use. (tinygltf's own Draco path does not check its
// inputs, so the loader never enables it.)
#include <fmt/core.h>
#include <tiny_gltf.h>

#include <draco/compression/decode.h>
#include <draco/core/decoder_buffer.h>

#include "gltf_internal.h"

namespace probebake::scene::detail {
namespace {

const unsigned char* checked_view_bytes(const tinygltf::Model& model, int buffer_view, std::size_t& size,
                                        const Context& ctx, const std::string& place) {
  if (buffer_view < 0 || std::size_t(buffer_view) >= model.bufferViews.size())
    ctx.fail(place, fmt::format("Draco bufferView {} does not exist", buffer_view));
  const tinygltf::BufferView& view = model.bufferViews[std::size_t(buffer_view)];
  if (view.buffer < 0 || std::size_t(view.buffer) >= model.buffers.size())
    ctx.fail(place, fmt::format("Draco bufferView {} references missing buffer {}", buffer_view, view.buffer));
  const auto& data = model.buffers[std::size_t(view.buffer)].data;
  if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
    ctx.fail(place, fmt::format("Draco bufferView {} reaches past its buffer", buffer_view));
  size = view.byteLength;
  return data.data() + view.byteOffset;
}

// Reads attribute `name` (by the unique id the extension maps it to) as `N` floats per point.
template <int N>
std::vector<float> draco_attribute(const draco::Mesh& mesh, const tinygltf::Value& attributes, const char* name,
                                   const Context& ctx, const std::string& place) {
  const tinygltf::Value& id = attributes.Get(name);
  if (!id.IsInt()) return {};
  const draco::PointAttribute* attribute = mesh.GetAttributeByUniqueId(static_cast<std::uint32_t>(id.Get<int>()));
  if (attribute == nullptr)
    ctx.fail(place, fmt::format("Draco attribute {} (id {}) is not in the bitstream", name, id.Get<int>()));
  if (attribute->num_components() < N)
    ctx.fail(place, fmt::format("Draco attribute {} has {} components, expected {}", name,
                                int(attribute->num_components()), N));
  std::vector<float> out(std::size_t(mesh.num_points()) * N);
  for (draco::PointIndex i(0); i < mesh.num_points(); ++i) {
    const draco::AttributeValueIndex value = attribute->mapped_index(i);
    if (value.value() >= attribute->size())
      ctx.fail(place, fmt::format("Draco attribute {} maps point {} out of range", name, i.value()));
    if (!attribute->ConvertValue<float, N>(value, &out[std::size_t(i.value()) * N]))
      ctx.fail(place, fmt::format("Draco attribute {} cannot be read as floats", name));
  }
  return out;
}

} // namespace

PrimitiveGeometry decode_draco_primitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                         const Context& ctx, const std::string& place) {
  const tinygltf::Value& extension = primitive.extensions.at("KHR_draco_mesh_compression");
  const tinygltf::Value& view_value = member(extension, "bufferView");
  const tinygltf::Value& attributes = member(extension, "attributes");
  if (!view_value.IsInt() || !attributes.IsObject())
    ctx.fail(place, "KHR_draco_mesh_compression needs an integer bufferView and an attributes object");

  std::size_t size = 0;
  const unsigned char* bytes = checked_view_bytes(model, view_value.Get<int>(), size, ctx, place);
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes), size);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) ctx.fail(place, fmt::format("corrupted Draco payload: {}", decoded.status().error_msg_string()));
  const draco::Mesh& mesh = *decoded.value();

  PrimitiveGeometry geometry;
  const std::vector<float> positions = draco_attribute<3>(mesh, attributes, "POSITION", ctx, place);
  if (positions.empty()) ctx.fail(place, "Draco primitive has no POSITION attribute");
  geometry.positions.resize(positions.size() / 3);
  for (std::size_t i = 0; i < geometry.positions.size(); ++i)
    geometry.positions[i] = {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
  const char* texcoord_names[2] = {"TEXCOORD_0", "TEXCOORD_1"};
  for (int set = 0; set < 2; ++set) {
    const std::vector<float> uv = draco_attribute<2>(mesh, attributes, texcoord_names[set], ctx, place);
    for (std::size_t i = 0; i + 1 < uv.size(); i += 2) geometry.texcoords[set].push_back({uv[i], uv[i + 1]});
  }
  geometry.indices.reserve(std::size_t(mesh.num_faces()) * 3);
  for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f) {
    const draco::Mesh::Face& face = mesh.face(f);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t index = face[k].value();
      if (index >= mesh.num_points())
        ctx.fail(place, fmt::format("Draco face {} references point {} of {}", f.value(), index, mesh.num_points()));
      geometry.indices.push_back(index);
    }
  }
  return geometry;
}

} // namespace probebake::scene::detail
