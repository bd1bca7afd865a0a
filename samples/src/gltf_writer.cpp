// SceneBuilder -> glTF 2.0 binary (.glb) via tinygltf. One buffer, embedded in the BIN chunk; one
// bufferView per accessor, 4-byte aligned; POSITION (with min/max), NORMAL and indices (uint16 when
// every index fits, else uint32) per primitive.
#include "gltf_writer.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <charconv>
#include <sstream>
#include <string>

#include "probebake/common/enum_names.h"

namespace probebake::samples {
namespace {

constexpr int array_buffer = 34962;         // bufferView.target for vertex attributes
constexpr int element_array_buffer = 34963; // bufferView.target for indices

// The shortest decimal that reads back as the same float (0.556, not 0.5559999942779541) so the JSON is
// readable; the float value is unchanged.
double tidy(float value) {
  char text[32];
  const auto written = std::to_chars(text, text + sizeof text, value);
  double result = static_cast<double>(value);
  std::from_chars(text, written.ptr, result);
  return result;
}

std::vector<double> tidy3(glm::vec3 v) { return {tidy(v.x), tidy(v.y), tidy(v.z)}; }

class BufferWriter {
public:
  explicit BufferWriter(tinygltf::Model& model) : model_(model) {}

  int add_view(const void* data, std::size_t bytes, int target) {
    std::vector<unsigned char>& buffer = model_.buffers.at(0).data;
    buffer.resize((buffer.size() + 3) & ~std::size_t{3}, 0); // accessors need 4-byte alignment
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buffer.size();
    view.byteLength = bytes;
    view.target = target;
    const auto* first = static_cast<const unsigned char*>(data);
    buffer.insert(buffer.end(), first, first + bytes);
    model_.bufferViews.push_back(view);
    return static_cast<int>(model_.bufferViews.size()) - 1;
  }

  int add_accessor(int view, int component_type, int type, std::size_t count) {
    tinygltf::Accessor accessor;
    accessor.bufferView = view;
    accessor.componentType = component_type;
    accessor.type = type;
    accessor.count = count;
    model_.accessors.push_back(accessor);
    return static_cast<int>(model_.accessors.size()) - 1;
  }

private:
  tinygltf::Model& model_;
};

int add_vec3_accessor(BufferWriter& writer, const std::vector<glm::vec3>& values) {
  const int view = writer.add_view(values.data(), values.size() * sizeof(glm::vec3), array_buffer);
  return writer.add_accessor(view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, values.size());
}

int add_positions(tinygltf::Model& model, BufferWriter& writer, const MeshData& mesh) {
  const int accessor = add_vec3_accessor(writer, mesh.positions);
  const Bounds bounds = bounds_of(mesh); // min/max exact (required for POSITION)
  model.accessors[static_cast<std::size_t>(accessor)].minValues = {bounds.min.x, bounds.min.y, bounds.min.z};
  model.accessors[static_cast<std::size_t>(accessor)].maxValues = {bounds.max.x, bounds.max.y, bounds.max.z};
  return accessor;
}

int add_indices(BufferWriter& writer, const MeshData& mesh) {
  // glTF forbids the component type's maximum value as an index, hence "< 65535 vertices" for uint16.
  if (mesh.positions.size() < 65535) {
    std::vector<std::uint16_t> small(mesh.indices.begin(), mesh.indices.end());
    const int view = writer.add_view(small.data(), small.size() * sizeof(std::uint16_t), element_array_buffer);
    return writer.add_accessor(view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR, small.size());
  }
  const int view =
      writer.add_view(mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t), element_array_buffer);
  return writer.add_accessor(view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, mesh.indices.size());
}

tinygltf::Mesh encode_mesh(tinygltf::Model& model, BufferWriter& writer, const SceneBuilder::MeshEntry& entry) {
  tinygltf::Mesh mesh;
  mesh.name = entry.name;
  for (const Primitive& source : entry.primitives) {
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.material = source.material.index;
    primitive.attributes["POSITION"] = add_positions(model, writer, source.geometry);
    primitive.attributes["NORMAL"] = add_vec3_accessor(writer, source.geometry.normals);
    primitive.indices = add_indices(writer, source.geometry);
    mesh.primitives.push_back(std::move(primitive));
  }
  return mesh;
}

// Emission L is written as emissiveFactor = L / s with s = max(L) when max(L) > 1
// (KHR_materials_emissive_strength = s), else as emissiveFactor = L.
tinygltf::Material encode_material(const Material& source, bool& uses_strength) {
  tinygltf::Material material;
  material.name = source.name;
  material.pbrMetallicRoughness.baseColorFactor = {tidy(source.albedo.r), tidy(source.albedo.g), tidy(source.albedo.b),
                                                   1.0};
  material.pbrMetallicRoughness.metallicFactor = 0.0; // purely diffuse
  material.pbrMetallicRoughness.roughnessFactor = 1.0;
  material.doubleSided = source.double_sided;
  const float strength = std::max({source.emission.r, source.emission.g, source.emission.b});
  if (strength <= 1.0f) {
    material.emissiveFactor = tidy3(source.emission);
    return material;
  }
  const double s = tidy(strength);
  material.emissiveFactor = {tidy(source.emission.r) / s, tidy(source.emission.g) / s, tidy(source.emission.b) / s};
  tinygltf::Value::Object extension{{"emissiveStrength", tinygltf::Value(s)}};
  material.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(std::move(extension));
  uses_strength = true;
  return material;
}

// KHR_lights_punctual's type names.
constexpr EnumName<LightType> kLightTypeNames[] = {
    {LightType::point, "point"},
    {LightType::spot, "spot"},
    {LightType::directional, "directional"},
};

tinygltf::Light encode_light(const Light& source) {
  tinygltf::Light light;
  light.name = source.name;
  light.type = std::string(name_in(kLightTypeNames, source.type, "point"));
  light.color = tidy3(source.color);
  light.intensity = tidy(source.intensity);
  light.range = tidy(source.range);
  if (source.type == LightType::spot) {
    light.spot.innerConeAngle = tidy(source.inner_cone_angle);
    light.spot.outerConeAngle = tidy(source.outer_cone_angle);
  }
  return light;
}

tinygltf::Value dynamic_extras() {
  tinygltf::Value::Object probebake{{"dynamic", tinygltf::Value(true)}};
  tinygltf::Value::Object extras{{"probebake", tinygltf::Value(std::move(probebake))}};
  return tinygltf::Value(std::move(extras));
}

tinygltf::Node encode_node(const SceneBuilder::NodeEntry& source, tinygltf::Model& model) {
  tinygltf::Node node;
  node.name = source.name;
  const Transform& t = source.transform;
  if (t.translation != glm::vec3(0.0f)) node.translation = tidy3(t.translation);
  if (t.rotation != glm::quat(1.0f, 0.0f, 0.0f, 0.0f)) {
    node.rotation = {t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w}; // glTF order: x, y, z, w
  }
  if (t.scale != glm::vec3(1.0f)) node.scale = tidy3(t.scale);
  if (source.mesh) node.mesh = source.mesh->index;
  if (source.light) {
    tinygltf::Value::Object light{{"light", tinygltf::Value(source.light->index)}};
    node.extensions["KHR_lights_punctual"] = tinygltf::Value(std::move(light));
  }
  if (source.camera_yfov) {
    tinygltf::Camera camera;
    camera.type = "perspective";
    camera.perspective.yfov = *source.camera_yfov;
    camera.perspective.aspectRatio = 1.0;
    camera.perspective.znear = 0.01;
    node.camera = int(model.cameras.size());
    model.cameras.push_back(camera);
  }
  if (source.dynamic) node.extras = dynamic_extras();
  node.children = source.children;
  return node;
}

tinygltf::Model encode_model(const SceneBuilder& scene) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "probebake make-scene";
  if (!scene.meshes().empty()) model.buffers.emplace_back(); // an empty buffer would be invalid glTF
  BufferWriter writer(model);
  for (const auto& mesh : scene.meshes()) model.meshes.push_back(encode_mesh(model, writer, mesh));
  bool uses_strength = false;
  for (const Material& material : scene.materials())
    model.materials.push_back(encode_material(material, uses_strength));
  if (uses_strength) model.extensionsUsed.push_back("KHR_materials_emissive_strength");
  for (const Light& light : scene.lights()) model.lights.push_back(encode_light(light)); // adds KHR_lights_punctual
  for (const auto& node : scene.nodes()) model.nodes.push_back(encode_node(node, model));
  tinygltf::Scene gltf_scene;
  gltf_scene.name = scene.scene_name();
  gltf_scene.nodes = scene.roots();
  model.scenes.push_back(std::move(gltf_scene));
  model.defaultScene = 0;
  return model;
}

} // namespace

std::vector<std::uint8_t> encode_glb(const SceneBuilder& scene) {
  const tinygltf::Model model = encode_model(scene);
  std::ostringstream stream(std::ios::binary);
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, stream, false, true)) {
    throw Error(ErrorKind::output, "tinygltf could not encode the scene");
  }
  const std::string bytes = stream.str();
  return std::vector<std::uint8_t>(bytes.begin(), bytes.end());
}

} // namespace probebake::samples
