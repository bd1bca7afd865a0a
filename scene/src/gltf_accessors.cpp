// glTF accessor decoding with every offset, stride and count checked (glTF 2.0 spec §3.6.2, §3.6.2.3).
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include <fmt/core.h>
#include <tiny_gltf.h>

#include "gltf_internal.h"

namespace probebake::scene::detail {
namespace {

struct ComponentInfo {
  int size = 0;
  bool is_float = false;
};

ComponentInfo component_info(int component_type) {
  switch (component_type) {
  case TINYGLTF_COMPONENT_TYPE_BYTE:
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return {1, false};
  case TINYGLTF_COMPONENT_TYPE_SHORT:
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return {2, false};
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return {4, false};
  case TINYGLTF_COMPONENT_TYPE_FLOAT: return {4, true};
  default: return {0, false};
  }
}

// One stored component of type T as a double: exact for every glTF integer type; a normalized integer maps to
// [0, 1] (unsigned) or [-1, 1] (signed, clamped), per spec §3.11.
template <typename T>
double read_as(const unsigned char* p, bool normalized) {
  T v;
  std::memcpy(&v, p, sizeof v);
  if (!normalized || std::is_floating_point_v<T>) return double(v);
  const double scaled = double(v) / double(std::numeric_limits<T>::max());
  return std::is_signed_v<T> ? std::max(scaled, -1.0) : scaled;
}

double read_component(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
  case TINYGLTF_COMPONENT_TYPE_BYTE: return read_as<std::int8_t>(p, normalized);
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return read_as<std::uint8_t>(p, normalized);
  case TINYGLTF_COMPONENT_TYPE_SHORT: return read_as<std::int16_t>(p, normalized);
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return read_as<std::uint16_t>(p, normalized);
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return read_as<std::uint32_t>(p, normalized);
  default: return read_as<float>(p, normalized);
  }
}

// A checked view of `count` elements of `element_size` bytes inside a buffer view.
struct ElementView {
  const unsigned char* base = nullptr;
  std::size_t stride = 0;
};

ElementView checked_view(const tinygltf::Model& model, int buffer_view, std::size_t byte_offset, std::size_t count,
                         std::size_t element_size, bool allow_stride, const Context& ctx, const std::string& place) {
  if (buffer_view < 0 || std::size_t(buffer_view) >= model.bufferViews.size())
    ctx.fail(place, fmt::format("bufferView {} does not exist", buffer_view));
  const tinygltf::BufferView& view = model.bufferViews[std::size_t(buffer_view)];
  if (view.buffer < 0 || std::size_t(view.buffer) >= model.buffers.size())
    ctx.fail(place, fmt::format("bufferView {} references missing buffer {}", buffer_view, view.buffer));
  const std::vector<unsigned char>& data = model.buffers[std::size_t(view.buffer)].data;
  if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
    ctx.fail(place, fmt::format("bufferView {} (offset {}, length {}) reaches past its buffer of {} bytes", buffer_view,
                                view.byteOffset, view.byteLength, data.size()));
  std::size_t stride = (allow_stride && view.byteStride != 0) ? view.byteStride : element_size;
  if (stride < element_size) ctx.fail(place, fmt::format("byteStride {} is smaller than an element", stride));
  if (count == 0) return {data.data() + view.byteOffset, stride};
  // Last byte touched: byte_offset + (count - 1) * stride + element_size, computed without overflow.
  const std::size_t limit = view.byteLength;
  if (byte_offset > limit || (count - 1) > (limit - byte_offset) / stride ||
      (count - 1) * stride + element_size > limit - byte_offset)
    ctx.fail(place, fmt::format("accessor reaches past bufferView {} ({} elements of {} bytes, stride {}, offset {}, "
                                "view length {})",
                                buffer_view, count, element_size, stride, byte_offset, limit));
  return {data.data() + view.byteOffset + byte_offset, stride};
}

const tinygltf::Accessor& checked_accessor(const tinygltf::Model& model, int accessor, const Context& ctx,
                                           const std::string& place) {
  if (accessor < 0 || std::size_t(accessor) >= model.accessors.size())
    ctx.fail(place, fmt::format("accessor {} does not exist", accessor));
  return model.accessors[std::size_t(accessor)];
}

// Elements stored as doubles, `components` per element (the accessor's own component count).
std::vector<double> read_accessor(const tinygltf::Model& model, const tinygltf::Accessor& acc, const Context& ctx,
                                  const std::string& place) {
  const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type));
  const ComponentInfo info = component_info(acc.componentType);
  if (components <= 0 || info.size == 0)
    ctx.fail(place, fmt::format("unsupported accessor type {} / componentType {}", acc.type, acc.componentType));
  if (acc.count > (std::size_t(1) << 31)) ctx.fail(place, fmt::format("accessor count {} is too large", acc.count));
  const std::size_t nc = std::size_t(components);
  // The view is checked before anything is allocated: a declared count must fit in its buffer. An
  // accessor without bufferView is all zeros (spec) and only the memory budget bounds it.
  ElementView view;
  if (acc.bufferView >= 0)
    view =
        checked_view(model, acc.bufferView, acc.byteOffset, acc.count, nc * std::size_t(info.size), true, ctx, place);
  ctx.charge(acc.count * nc, sizeof(double) + sizeof(float), place);
  std::vector<double> out(acc.count * nc, 0.0);
  if (acc.bufferView >= 0) {
    for (std::size_t i = 0; i < acc.count; ++i)
      for (std::size_t c = 0; c < nc; ++c)
        out[i * nc + c] =
            read_component(view.base + i * view.stride + c * std::size_t(info.size), acc.componentType, acc.normalized);
  }
  if (acc.sparse.isSparse) {
    const auto& sparse = acc.sparse;
    const std::size_t n = std::size_t(std::max(sparse.count, 0));
    if (sparse.count < 0 || n > acc.count) ctx.fail(place, fmt::format("sparse count {} is invalid", sparse.count));
    const ComponentInfo index_info = component_info(sparse.indices.componentType);
    if (index_info.size == 0 || index_info.is_float) ctx.fail(place, "sparse indices have an invalid componentType");
    ElementView indices = checked_view(model, sparse.indices.bufferView, std::size_t(sparse.indices.byteOffset), n,
                                       std::size_t(index_info.size), false, ctx, place + ".sparse.indices");
    ElementView values = checked_view(model, sparse.values.bufferView, std::size_t(sparse.values.byteOffset), n,
                                      nc * std::size_t(info.size), false, ctx, place + ".sparse.values");
    for (std::size_t i = 0; i < n; ++i) {
      const double index = read_component(indices.base + i * indices.stride, sparse.indices.componentType, false);
      if (index >= double(acc.count))
        ctx.fail(place, fmt::format("sparse index {} is past the accessor count {}", index, acc.count));
      for (std::size_t c = 0; c < nc; ++c)
        out[std::size_t(index) * nc + c] = read_component(values.base + i * values.stride + c * std::size_t(info.size),
                                                          acc.componentType, acc.normalized);
    }
  }
  return out;
}

} // namespace

const tinygltf::Value& member(const tinygltf::Value& value, const char* key) {
  static const tinygltf::Value null_value;
  return value.IsObject() && value.Has(key) ? value.Get(key) : null_value;
}

float number_at(const tinygltf::Value& array, int i, float fallback) {
  if (!array.IsArray() || i < 0 || std::size_t(i) >= array.ArrayLen() || !array.Get(i).IsNumber()) return fallback;
  return float(array.Get(i).GetNumberAsDouble());
}

std::vector<float> read_accessor_floats(const tinygltf::Model& model, int accessor, int components, const Context& ctx,
                                        const std::string& place) {
  const tinygltf::Accessor& acc = checked_accessor(model, accessor, ctx, place);
  const int have = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type));
  if (have != components)
    ctx.fail(place, fmt::format("accessor {} has {} components, expected {}", accessor, have, components));
  const std::vector<double> values = read_accessor(model, acc, ctx, place);
  std::vector<float> out(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) out[i] = static_cast<float>(values[i]);
  return out;
}

std::vector<std::uint32_t> read_accessor_indices(const tinygltf::Model& model, int accessor, const Context& ctx,
                                                 const std::string& place) {
  const tinygltf::Accessor& acc = checked_accessor(model, accessor, ctx, place);
  if (acc.type != TINYGLTF_TYPE_SCALAR || component_info(acc.componentType).is_float ||
      acc.componentType == TINYGLTF_COMPONENT_TYPE_BYTE || acc.componentType == TINYGLTF_COMPONENT_TYPE_SHORT)
    ctx.fail(place, fmt::format("index accessor {} must hold unsigned integer scalars", accessor));
  const std::vector<double> values = read_accessor(model, acc, ctx, place);
  std::vector<std::uint32_t> out(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) out[i] = static_cast<std::uint32_t>(values[i]);
  return out;
}

} // namespace probebake::scene::detail

namespace probebake::scene::detail {

PrimitiveGeometry read_plain_primitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                       const Context& ctx, const std::string& place) {
  PrimitiveGeometry g;
  auto position = primitive.attributes.find("POSITION");
  if (position == primitive.attributes.end()) ctx.fail(place, "primitive has no POSITION attribute");
  const std::vector<float> p = read_accessor_floats(model, position->second, 3, ctx, place + ".POSITION");
  g.positions.resize(p.size() / 3);
  for (std::size_t i = 0; i < g.positions.size(); ++i) g.positions[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
  const char* texcoord_names[2] = {"TEXCOORD_0", "TEXCOORD_1"};
  for (int set = 0; set < 2; ++set) {
    auto uv = primitive.attributes.find(texcoord_names[set]);
    if (uv == primitive.attributes.end()) continue;
    const std::vector<float> t = read_accessor_floats(model, uv->second, 2, ctx, place + "." + texcoord_names[set]);
    for (std::size_t i = 0; i + 1 < t.size(); i += 2) g.texcoords[set].push_back({t[i], t[i + 1]});
  }
  if (primitive.indices >= 0) {
    g.indices = read_accessor_indices(model, primitive.indices, ctx, place + ".indices");
  } else {
    g.indices.resize(g.positions.size());
    for (std::size_t i = 0; i < g.indices.size(); ++i) g.indices[i] = static_cast<std::uint32_t>(i);
  }
  return g;
}

} // namespace probebake::scene::detail
