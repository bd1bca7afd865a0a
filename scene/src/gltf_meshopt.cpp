// EXT_meshopt_compression (glTF vendor extension; the files gltfpack -cc and gltf-transform meshopt write):
// each compressed bufferView is decoded with meshoptimizer into a buffer of its own. Every property is
// checked against the extension's rules and every range against its buffer before the decoder runs, and
// the output (count * byteStride bytes, which must equal the bufferView's byteLength) is charged to the
// memory budget before it is allocated. The decoders themselves bound every read by the input size.
#include <fmt/core.h>
#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include "gltf_internal.h"

namespace probebake::scene::detail {
namespace {

constexpr const char* kExtension = "EXT_meshopt_compression";

struct MeshoptView {
  int buffer = -1;
  std::size_t byte_offset = 0, byte_length = 0, byte_stride = 0, count = 0;
  std::string mode, filter = "NONE";
};

std::size_t size_property(const tinygltf::Value& object, const char* key, bool required, const Context& ctx,
                          const std::string& place) {
  const tinygltf::Value& value = member(object, key);
  if ((value.Type() == tinygltf::NULL_TYPE) && !required) return 0;
  if (!value.IsNumber() || value.GetNumberAsDouble() < 0 || value.GetNumberAsDouble() > 9007199254740992.0 ||
      value.GetNumberAsDouble() != double(std::uint64_t(value.GetNumberAsDouble())))
    ctx.fail(place, fmt::format("{} must be a non-negative integer", key));
  return std::size_t(value.GetNumberAsDouble());
}

MeshoptView read_extension(const tinygltf::Value& json, const Context& ctx, const std::string& place) {
  MeshoptView v;
  v.buffer = int(std::min<std::size_t>(size_property(json, "buffer", true, ctx, place), INT32_MAX));
  v.byte_offset = size_property(json, "byteOffset", false, ctx, place);
  v.byte_length = size_property(json, "byteLength", true, ctx, place);
  v.byte_stride = size_property(json, "byteStride", true, ctx, place);
  v.count = size_property(json, "count", true, ctx, place);
  if (!member(json, "mode").IsString()) ctx.fail(place, "mode must be ATTRIBUTES, TRIANGLES or INDICES");
  v.mode = member(json, "mode").Get<std::string>();
  if (member(json, "filter").IsString())
    v.filter = member(json, "filter").Get<std::string>();
  else if (member(json, "filter").Type() != tinygltf::NULL_TYPE)
    ctx.fail(place, "filter must be a string");
  return v;
}

// The extension's validity rules (EXT_meshopt_compression README, "JSON schema updates").
void check_layout(const std::string& mode, const std::string& filter, std::size_t count, std::size_t stride,
                  const Context& ctx, const std::string& place) {
  const bool indices = mode == "TRIANGLES" || mode == "INDICES";
  if (mode != "ATTRIBUTES" && !indices) ctx.fail(place, fmt::format("unknown mode '{}'", mode));
  if (filter != "NONE" && filter != "OCTAHEDRAL" && filter != "QUATERNION" && filter != "EXPONENTIAL")
    ctx.fail(place, fmt::format("unknown filter '{}'", filter));
  if (mode == "ATTRIBUTES" && (stride == 0 || stride % 4 != 0 || stride > 256))
    ctx.fail(place, fmt::format("ATTRIBUTES byteStride {} must be a multiple of 4 up to 256", stride));
  if (indices && stride != 2 && stride != 4)
    ctx.fail(place, fmt::format("{} byteStride {} must be 2 or 4", mode, stride));
  if (indices && filter != "NONE") ctx.fail(place, fmt::format("{} data cannot have filter {}", mode, filter));
  if (mode == "TRIANGLES" && count % 3 != 0)
    ctx.fail(place, fmt::format("TRIANGLES count {} is not a multiple of 3", count));
  if (filter == "OCTAHEDRAL" && stride != 4 && stride != 8)
    ctx.fail(place, fmt::format("OCTAHEDRAL byteStride {} must be 4 or 8", stride));
  if (filter == "QUATERNION" && stride != 8) ctx.fail(place, fmt::format("QUATERNION byteStride {} must be 8", stride));
}

void apply_filter(std::vector<unsigned char>& data, std::size_t count, std::size_t stride, const std::string& filter) {
  if (count == 0) return;
  if (filter == "OCTAHEDRAL")
    meshopt_decodeFilterOct(data.data(), count, stride);
  else if (filter == "QUATERNION")
    meshopt_decodeFilterQuat(data.data(), count, stride);
  else if (filter == "EXPONENTIAL")
    meshopt_decodeFilterExp(data.data(), count, stride);
}

// `file_buffers`: the buffers the file declares (decoded ones are appended after them).
std::span<const unsigned char> source_bytes(const tinygltf::Model& model, std::size_t file_buffers,
                                            const MeshoptView& v, const Context& ctx, const std::string& place) {
  if (v.buffer < 0 || std::size_t(v.buffer) >= file_buffers)
    ctx.fail(place, fmt::format("buffer {} does not exist", v.buffer));
  const std::vector<unsigned char>& data = model.buffers[std::size_t(v.buffer)].data;
  if (v.byte_offset > data.size() || v.byte_length > data.size() - v.byte_offset)
    ctx.fail(place, fmt::format("compressed data (offset {}, length {}) reaches past buffer {} of {} bytes",
                                v.byte_offset, v.byte_length, v.buffer, data.size()));
  return {data.data() + v.byte_offset, v.byte_length};
}

} // namespace

std::vector<unsigned char> decode_meshopt_stream(std::span<const unsigned char> source, std::size_t count,
                                                 std::size_t stride, const std::string& mode, const std::string& filter,
                                                 const Context& ctx, const std::string& place) {
  check_layout(mode, filter, count, stride, ctx, place);
  if (count > (std::size_t(1) << 31)) ctx.fail(place, fmt::format("count {} is too large", count));
  ctx.charge(count, stride, place);
  std::vector<unsigned char> out(count * stride);
  if (count == 0) return out;
  int rc = 0;
  if (mode == "ATTRIBUTES")
    rc = meshopt_decodeVertexBuffer(out.data(), count, stride, source.data(), source.size());
  else if (mode == "TRIANGLES")
    rc = meshopt_decodeIndexBuffer(out.data(), count, stride, source.data(), source.size());
  else
    rc = meshopt_decodeIndexSequence(out.data(), count, stride, source.data(), source.size());
  if (rc != 0) ctx.fail(place, fmt::format("corrupted meshopt {} data (decoder error {})", mode, rc));
  apply_filter(out, count, stride, filter);
  return out;
}

void decode_meshopt_buffer_views(tinygltf::Model& model, const Context& ctx) {
  const std::size_t file_buffers = model.buffers.size();
  for (std::size_t i = 0; i < model.bufferViews.size(); ++i) {
    auto extension = model.bufferViews[i].extensions.find(kExtension);
    if (extension == model.bufferViews[i].extensions.end()) continue;
    const std::string place = fmt::format("bufferViews[{}].{}", i, kExtension);
    const MeshoptView v = read_extension(extension->second, ctx, place);
    tinygltf::BufferView& view = model.bufferViews[i];
    if (view.byteStride != 0 && view.byteStride != v.byte_stride)
      ctx.fail(place, fmt::format("byteStride {} differs from the bufferView's {}", v.byte_stride, view.byteStride));
    if (v.count > view.byteLength / std::max<std::size_t>(v.byte_stride, 1) ||
        v.count * v.byte_stride != view.byteLength)
      ctx.fail(place, fmt::format("count {} x byteStride {} is not the bufferView's byteLength {}", v.count,
                                  v.byte_stride, view.byteLength));
    std::vector<unsigned char> decoded = decode_meshopt_stream(source_bytes(model, file_buffers, v, ctx, place),
                                                               v.count, v.byte_stride, v.mode, v.filter, ctx, place);
    tinygltf::Buffer buffer;
    buffer.data = std::move(decoded);
    model.buffers.push_back(std::move(buffer));
    view.buffer = int(model.buffers.size() - 1); // `view` is still valid: bufferViews did not change
    view.byteOffset = 0;
  }
}

} // namespace probebake::scene::detail
