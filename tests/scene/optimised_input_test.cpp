// glTF as optimisers write it (issue #18): EXT_meshopt_compression geometry (every mode and filter, the
// fallback buffer, bounded input), WebP and KTX2 textures with fallbacks, undecodable textures as one
// warning (an error with strict), and what the spec allows that tinygltf alone refuses.
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>

#include <gtest/gtest.h>
#include <meshoptimizer.h>
#include <stb_image_write.h>
#include <webp/encode.h>

#include "gltf_internal.h"
#include "mini_gltf.h"
#include "probebake/scene/scene.h"
#include "probebake/formats/error.h"

// stb_image_write's zlib writer: libstb exports it (C linkage), its header declares it only with the implementation.
extern "C" unsigned char* stbi_zlib_compress(unsigned char* data, int data_len, int* out_len, int quality);

namespace probebake::test {
namespace {

using Bytes = std::vector<unsigned char>;
const std::vector<glm::vec3> kQuad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
const std::vector<std::uint32_t> kQuadIndices = {0, 1, 2, 0, 2, 3};

std::string load_error(const std::filesystem::path& path, const scene::LoadOptions& options = {}) {
  try {
    scene::load_scene(path, options);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// ---- EXT_meshopt_compression streams: each mode and filter against meshoptimizer's own encoder --------

const scene::detail::Context kCtx{"test.glb"};

Bytes encode_vertices(const void* data, std::size_t count, std::size_t stride) {
  Bytes out(meshopt_encodeVertexBufferBound(count, stride));
  out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), data, count, stride));
  return out;
}

TEST(MeshoptStream, AttributesRoundTripExactly) {
  const Bytes encoded = encode_vertices(kQuad.data(), kQuad.size(), 12);
  const Bytes decoded = scene::detail::decode_meshopt_stream(encoded, 4, 12, "ATTRIBUTES", "NONE", kCtx, "v");
  ASSERT_EQ(decoded.size(), 48u);
  EXPECT_EQ(std::memcmp(decoded.data(), kQuad.data(), 48), 0);
}

TEST(MeshoptStream, TrianglesAndIndexSequencesRoundTrip) {
  const std::vector<unsigned int> indices = {0, 1, 2, 2, 1, 3, 3, 1, 4, 7, 5, 6};
  Bytes tri(meshopt_encodeIndexBufferBound(indices.size(), 8));
  tri.resize(meshopt_encodeIndexBuffer(tri.data(), tri.size(), indices.data(), indices.size()));
  Bytes seq(meshopt_encodeIndexSequenceBound(indices.size(), 8));
  seq.resize(meshopt_encodeIndexSequence(seq.data(), seq.size(), indices.data(), indices.size()));
  for (std::size_t stride : {2u, 4u}) {
    for (const auto& [mode, bytes] : {std::pair{"TRIANGLES", tri}, std::pair{"INDICES", seq}}) {
      const Bytes out = scene::detail::decode_meshopt_stream(bytes, indices.size(), stride, mode, "NONE", kCtx, "i");
      std::vector<std::uint32_t> got(indices.size());
      for (std::size_t i = 0; i < indices.size(); ++i) std::memcpy(&got[i], &out[i * stride], stride);
      for (std::size_t t = 0; t < indices.size(); t += 3) {
        // The triangle codec keeps each triangle and its winding but may rotate its corners.
        bool same = false;
        for (std::size_t r = 0; r < 3; ++r)
          same |= got[t] == indices[t + r] && got[t + 1] == indices[t + (r + 1) % 3] &&
                  got[t + 2] == indices[t + (r + 2) % 3];
        EXPECT_TRUE(same) << mode << " stride " << stride << " triangle " << t / 3;
        if (std::string(mode) == "INDICES") {
          EXPECT_EQ(got[t], indices[t]) << "sequences are exact";
        }
      }
    }
  }
}

// Filtered streams decode to what meshoptimizer's reference filter decoders give, and close to the input.
Bytes filtered_roundtrip(const Bytes& filtered, std::size_t count, std::size_t stride, const char* filter) {
  const Bytes encoded = encode_vertices(filtered.data(), count, stride);
  return scene::detail::decode_meshopt_stream(encoded, count, stride, "ATTRIBUTES", filter, kCtx, "f");
}

TEST(MeshoptStream, OctahedralQuaternionAndExponentialFilters) {
  const std::vector<float> normals = {0, 0, 1, 1, 0.6f, 0.8f, 0, 1, -0.48f, 0.6f, 0.64f, 1};
  Bytes oct(3 * 8);
  meshopt_encodeFilterOct(oct.data(), 3, 8, 16, normals.data());
  const Bytes oct_out = filtered_roundtrip(oct, 3, 8, "OCTAHEDRAL");
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t c = 0; c < 3; ++c) {
      std::int16_t v = 0;
      std::memcpy(&v, &oct_out[i * 8 + c * 2], 2);
      EXPECT_NEAR(float(v) / 32767.0f, normals[i * 4 + c], 2e-4f) << "normal " << i;
    }
  const std::vector<float> quats = {0, 0, 0, 1, 0.5f, 0.5f, 0.5f, 0.5f};
  Bytes quat(2 * 8);
  meshopt_encodeFilterQuat(quat.data(), 2, 8, 16, quats.data());
  Bytes reference = quat;
  meshopt_decodeFilterQuat(reference.data(), 2, 8);
  EXPECT_EQ(filtered_roundtrip(quat, 2, 8, "QUATERNION"), reference);
  const std::vector<float> values = {1.5f, -2.25f, 1000.0f, 0.125f};
  Bytes exp(4 * 4);
  meshopt_encodeFilterExp(exp.data(), 4, 4, 23, values.data());
  const Bytes exp_out = filtered_roundtrip(exp, 4, 4, "EXPONENTIAL");
  for (std::size_t i = 0; i < 4; ++i) {
    float v = 0;
    std::memcpy(&v, &exp_out[i * 4], 4);
    EXPECT_FLOAT_EQ(v, values[i]);
  }
}

TEST(MeshoptStream, InvalidLayoutsAndCorruptDataAreOneLineErrors) {
  const Bytes encoded = encode_vertices(kQuad.data(), 4, 12);
  auto error = [&](std::size_t count, std::size_t stride, const char* mode, const char* filter, const Bytes& data) {
    try {
      scene::detail::decode_meshopt_stream(data, count, stride, mode, filter, kCtx, "bufferViews[0]");
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error(4, 10, "ATTRIBUTES", "NONE", encoded).find("multiple of 4"), std::string::npos);
  EXPECT_NE(error(4, 260, "ATTRIBUTES", "NONE", encoded).find("multiple of 4 up to 256"), std::string::npos);
  EXPECT_NE(error(4, 2, "TRIANGLES", "NONE", encoded).find("not a multiple of 3"), std::string::npos);
  EXPECT_NE(error(3, 8, "TRIANGLES", "NONE", encoded).find("must be 2 or 4"), std::string::npos);
  EXPECT_NE(error(3, 4, "INDICES", "OCTAHEDRAL", encoded).find("cannot have filter"), std::string::npos);
  EXPECT_NE(error(4, 12, "ATTRIBUTES", "OCTAHEDRAL", encoded).find("must be 4 or 8"), std::string::npos);
  EXPECT_NE(error(4, 4, "ATTRIBUTES", "QUATERNION", encoded).find("must be 8"), std::string::npos);
  EXPECT_NE(error(4, 12, "POINTS", "NONE", encoded).find("unknown mode"), std::string::npos);
  EXPECT_NE(error(4, 12, "ATTRIBUTES", "ZIP", encoded).find("unknown filter"), std::string::npos);
  const Bytes truncated(encoded.begin(), encoded.begin() + std::ptrdiff_t(encoded.size() / 2));
  EXPECT_NE(error(4, 12, "ATTRIBUTES", "NONE", truncated).find("corrupted meshopt ATTRIBUTES data"), std::string::npos);
}

// ---- EXT_meshopt_compression in files ------------------------------------------------------------------

// The quad with positions (ATTRIBUTES, EXPONENTIAL) and indices (INDICES mode) compressed into buffer 0 and
// bufferViews on a uri-less fallback buffer 1: the layout gltfpack -cc writes.
MiniGltf meshopt_quad() {
  MiniGltf g = MiniGltf::one_mesh_node();
  g.json["extensionsUsed"] = nlohmann::json::array({"EXT_meshopt_compression"});
  g.json["extensionsRequired"] = nlohmann::json::array({"EXT_meshopt_compression"});
  Bytes exp(4 * 12);
  meshopt_encodeFilterExp(exp.data(), 4 * 3, 4, 23, &kQuad[0].x);
  const Bytes positions = encode_vertices(exp.data(), 4, 12);
  Bytes indices(meshopt_encodeIndexSequenceBound(6, 4));
  indices.resize(meshopt_encodeIndexSequence(indices.data(), indices.size(), kQuadIndices.data(), 6));
  const int pv = g.add_view(positions.data(), positions.size());
  const int iv = g.add_view(indices.data(), indices.size());
  auto compressed = [&](int source, std::size_t offset, std::size_t count, std::size_t stride, const char* mode,
                        const char* filter) {
    const nlohmann::json& view = g.json["bufferViews"][source];
    return nlohmann::json{{"buffer", 1},
                          {"byteOffset", offset},
                          {"byteLength", count * stride},
                          {"extensions",
                           {{"EXT_meshopt_compression",
                             {{"buffer", 0},
                              {"byteOffset", view["byteOffset"]},
                              {"byteLength", view["byteLength"]},
                              {"byteStride", stride},
                              {"count", count},
                              {"mode", mode},
                              {"filter", filter}}}}}};
  };
  g.json["bufferViews"].push_back(compressed(pv, 0, 4, 12, "ATTRIBUTES", "EXPONENTIAL"));
  g.json["bufferViews"].push_back(compressed(iv, 48, 6, 4, "INDICES", "NONE"));
  g.json["bufferViews"][2]["byteStride"] = 12;
  g.json["buffers"].push_back(
      {{"byteLength", 72}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
  const int pa = g.add_accessor(2, 5126, 4, "VEC3");
  g.json["accessors"][pa]["min"] = {0, 0, 0};
  g.json["accessors"][pa]["max"] = {1, 1, 0};
  const int ia = g.add_accessor(3, 5125, 6, "SCALAR");
  g.json["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pa}}}, {"indices", ia}}}}}};
  return g;
}

void expect_quad(const scene::Scene& s) {
  ASSERT_EQ(s.triangle_count(), 2u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(s.positions[i], kQuad[i]);
  EXPECT_EQ(s.triangles[0], glm::uvec3(0, 1, 2));
  EXPECT_EQ(s.triangles[1], glm::uvec3(0, 2, 3));
}

TEST(MeshoptFiles, GlbAndGltfWithUrilessFallbackBufferLoad) {
  const MiniGltf g = meshopt_quad();
  const auto dir = test_dir("meshopt-quad");
  g.write_glb(dir / "quad.glb");
  g.write_gltf(dir / "quad.gltf", "quad.bin");
  expect_quad(scene::load_scene(dir / "quad.glb"));
  const scene::Scene s = scene::load_scene(dir / "quad.gltf");
  expect_quad(s);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
}

TEST(MeshoptFiles, SizesAndRangesAreCheckedBeforeDecoding) {
  const auto dir = test_dir("meshopt-bad");
  auto refused = [&](const std::string& name, const std::function<void(nlohmann::json&)>& edit) {
    MiniGltf g = meshopt_quad();
    edit(g.json);
    g.write_glb(dir / (name + ".glb"));
    const std::string message = load_error(dir / (name + ".glb"), {.max_memory = 1 << 20});
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    return message;
  };
  auto ext = [](nlohmann::json& j) -> nlohmann::json& {
    return j["bufferViews"][2]["extensions"]["EXT_meshopt_compression"];
  };
  EXPECT_NE(refused("count", [&](auto& j) { ext(j)["count"] = 5; }).find("is not the bufferView's byteLength"),
            std::string::npos);
  EXPECT_NE(refused("stride", [&](auto& j) { j["bufferViews"][2]["byteStride"] = 16; }).find("differs from"),
            std::string::npos);
  EXPECT_NE(refused("past", [&](auto& j) { ext(j)["byteLength"] = 100000; }).find("reaches past buffer 0"),
            std::string::npos);
  EXPECT_NE(refused("source", [&](auto& j) { ext(j)["buffer"] = 7; }).find("buffer 7 does not exist"),
            std::string::npos);
  EXPECT_NE(refused("huge",
                    [&](auto& j) {
                      ext(j)["count"] = 100000000;
                      j["bufferViews"][2]["byteLength"] = 1200000000;
                    })
                .find("memory budget"),
            std::string::npos);
  EXPECT_NE(refused("mode", [&](auto& j) { ext(j).erase("mode"); }).find("mode must be"), std::string::npos);
  EXPECT_NE(refused("negative", [&](auto& j) { ext(j)["byteOffset"] = -4; }).find("non-negative integer"),
            std::string::npos);
}

// ---- Textures --------------------------------------------------------------------------------------------

Bytes png_bytes(unsigned char r, unsigned char g, unsigned char b) {
  std::vector<unsigned char> rgb;
  for (int i = 0; i < 16; ++i) rgb.insert(rgb.end(), {r, g, b});
  Bytes out;
  stbi_write_png_to_func(
      [](void* ctx, void* data, int size) {
        auto* o = static_cast<Bytes*>(ctx);
        o->insert(o->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
      },
      &out, 4, 4, 3, rgb.data(), 12);
  return out;
}

Bytes webp_bytes(unsigned char r, unsigned char g, unsigned char b) {
  std::vector<unsigned char> rgba;
  for (int i = 0; i < 16; ++i) rgba.insert(rgba.end(), {r, g, b, 255});
  std::uint8_t* encoded = nullptr;
  const std::size_t size = WebPEncodeLosslessRGBA(rgba.data(), 4, 4, 16, &encoded);
  Bytes out(encoded, encoded + size);
  WebPFree(encoded);
  return out;
}

const Bytes kKtx2 = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n', 0, 0, 0, 0};

// The quad with UVs and material 0 whose baseColorTexture is texture 0, made by `texture` from images
// appended with `add_image`.
struct TexturedQuad {
  MiniGltf g = MiniGltf::triangles(kQuad, kQuadIndices);
  TexturedQuad() {
    const std::vector<float> uv = {0, 0, 1, 0, 1, 1, 0, 1};
    const int tv = g.add_view(uv.data(), uv.size() * 4);
    g.json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = g.add_accessor(tv, 5126, 4, "VEC2");
    g.json["meshes"][0]["primitives"][0]["material"] = 0;
    g.json["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    g.json["images"] = nlohmann::json::array();
  }
  int add_image(const Bytes& bytes, const char* mime) {
    g.json["images"].push_back({{"bufferView", g.add_view(bytes.data(), bytes.size())}, {"mimeType", mime}});
    return int(g.json["images"].size()) - 1;
  }
  scene::Scene load(const std::string& name, const scene::LoadOptions& options = {}) const {
    const auto path = test_dir(name) / "scene.glb";
    g.write_glb(path);
    return scene::load_scene(path, options);
  }
};

float srgb(unsigned char c) { return std::pow((float(c) / 255.0f + 0.055f) / 1.055f, 2.4f); }

TEST(Textures, WebpIsDecodedLikePng) {
  TexturedQuad png, webp, fallback;
  png.g.json["textures"] = {{{"source", png.add_image(png_bytes(200, 100, 50), "image/png")}}};
  const int webp_image = webp.add_image(webp_bytes(200, 100, 50), "image/webp");
  webp.g.json["textures"] = {{{"extensions", {{"EXT_texture_webp", {{"source", webp_image}}}}}}};
  webp.g.json["extensionsRequired"] = webp.g.json["extensionsUsed"] = {"EXT_texture_webp"};
  // EXT_texture_webp with a PNG fallback of another colour: the WebP is preferred.
  const int fallback_png = fallback.add_image(png_bytes(10, 10, 10), "image/png");
  const int fallback_webp = fallback.add_image(webp_bytes(200, 100, 50), "image/webp");
  fallback.g.json["textures"] = {
      {{"source", fallback_png}, {"extensions", {{"EXT_texture_webp", {{"source", fallback_webp}}}}}}};
  const glm::vec3 expected(srgb(200), srgb(100), srgb(50));
  for (const auto& [name, quad] :
       {std::pair{"png", &png}, std::pair{"webp", &webp}, std::pair{"webp-fallback", &fallback}}) {
    const scene::Scene s = quad->load(std::string("tex-") + name);
    ASSERT_EQ(s.triangle_count(), 2u);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.triangle_albedo[0][c], expected[c], 1e-6f) << name;
    EXPECT_TRUE(s.warnings.empty()) << name << ": " << s.warnings.front();
  }
}

TEST(Textures, BasisuUsesItsFallbackSource) {
  TexturedQuad q;
  const int ktx = q.add_image(kKtx2, "image/ktx2");
  const int png = q.add_image(png_bytes(200, 100, 50), "image/png");
  q.g.json["textures"] = {{{"source", png}, {"extensions", {{"KHR_texture_basisu", {{"source", ktx}}}}}}};
  q.g.json["extensionsUsed"] = {"KHR_texture_basisu"};
  const scene::Scene s = q.load("tex-basisu-fallback", {.strict = true});
  EXPECT_NEAR(s.triangle_albedo[1].r, srgb(200), 1e-6f);
  EXPECT_TRUE(s.warnings.empty());
}

TEST(Textures, UndecodableTextureIsOneWarningAndAnErrorWhenStrict) {
  TexturedQuad q;
  q.g.json["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {0.5, 0.25, 1.0, 1.0};
  q.g.json["materials"].push_back(q.g.json["materials"][0]); // a second material using the same texture
  q.g.json["textures"] = {{{"extensions", {{"KHR_texture_basisu", {{"source", q.add_image(kKtx2, "image/ktx2")}}}}}}};
  q.g.json["extensionsUsed"] = q.g.json["extensionsRequired"] = {"KHR_texture_basisu"};
  const scene::Scene s = q.load("tex-ktx2-only");
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("textures[0]: image 0: KTX2/Basis Universal"), std::string::npos) << s.warnings[0];
  EXPECT_EQ(s.triangle_albedo[0], glm::vec3(0.5f, 0.25f, 1.0f)); // the factor alone
  std::string strict;
  try {
    q.load("tex-ktx2-strict", {.strict = true});
  } catch (const Error& e) {
    strict = e.what();
  }
  EXPECT_NE(strict.find("textures[0]: image 0: KTX2"), std::string::npos) << strict;
  EXPECT_NE(strict.find("(--strict)"), std::string::npos) << strict;

  TexturedQuad garbage;
  garbage.g.json["textures"] = {{{"source", garbage.add_image(Bytes(64, 0x42), "image/png")}}};
  const scene::Scene g = garbage.load("tex-garbage");
  ASSERT_EQ(g.warnings.size(), 1u);
  EXPECT_NE(g.warnings[0].find("unknown image format"), std::string::npos) << g.warnings[0];
}

// The quad's one texture is `png` over the factor (0.5, 0.25, 1): the load's one warning, once the texture
// has fallen back to the factor alone.
std::string refused_png_warning(const Bytes& png, const std::string& name) {
  TexturedQuad q;
  q.g.json["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {0.5, 0.25, 1.0, 1.0};
  q.g.json["textures"] = {{{"source", q.add_image(png, "image/png")}}};
  const scene::Scene s = q.load(name);
  EXPECT_EQ(s.triangle_albedo[0], glm::vec3(0.5f, 0.25f, 1.0f)); // the factor alone
  EXPECT_EQ(s.warnings.size(), 1u);
  return s.warnings.empty() ? std::string() : s.warnings[0];
}

// A PNG chunk that declares more bytes than the file holds: stb grows its IDAT buffer to the declared length
// before it reads the chunk (fuzz_scene_loader: a 38 KB texture declaring a 1.1 GB chunk made libstb ask for
// 2 GB). The loader's stb stops at its cap; the texture falls back to its factor with one warning.
TEST(Textures, APngChunkLongerThanItsFileIsRefusedWhileDecoding) {
  Bytes png = png_bytes(200, 100, 50);
  const std::size_t idat = 8 + 12 + 13; // after the signature and IHDR's 13 bytes
  ASSERT_EQ(std::string(png.begin() + idat + 4, png.begin() + idat + 8), "IDAT");
  const std::uint32_t declared = 1167327232u;
  for (int k = 0; k < 4; ++k) png[idat + std::size_t(k)] = static_cast<unsigned char>(declared >> (24 - 8 * k));
  const std::string warning = refused_png_warning(png, "tex-png-long-chunk");
  EXPECT_NE(warning.find("decoding asks for more than"), std::string::npos) << warning;
}

// PNG's CRC-32 (ISO 3309), bit by bit: a few hundred bytes per test.
std::uint32_t png_crc(const unsigned char* bytes, std::size_t size) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) {
    crc ^= bytes[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

// A PNG of `width` x `height` RGBA8 pixels whose IDAT holds `raw` deflated (stb's zlib writer), with CRCs.
Bytes png_of(std::uint32_t width, std::uint32_t height, bool interlaced, std::vector<unsigned char> raw) {
  Bytes out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  const auto be32 = [&](std::uint32_t v) {
    for (int k = 3; k >= 0; --k) out.push_back(static_cast<unsigned char>(v >> (8 * k)));
  };
  const auto chunk = [&](const char* type, const unsigned char* data, std::size_t size) {
    be32(std::uint32_t(size));
    const std::size_t start = out.size();
    out.insert(out.end(), type, type + 4);
    out.insert(out.end(), data, data + size);
    be32(png_crc(out.data() + start, out.size() - start));
  };
  std::vector<unsigned char> ihdr;
  for (std::uint32_t v : {width, height})
    for (int k = 3; k >= 0; --k) ihdr.push_back(static_cast<unsigned char>(v >> (8 * k)));
  ihdr.insert(ihdr.end(), {8, 6, 0, 0, static_cast<unsigned char>(interlaced ? 1 : 0)}); // 8 bits, RGBA
  chunk("IHDR", ihdr.data(), ihdr.size());
  int size = 0;
  unsigned char* deflated = stbi_zlib_compress(raw.data(), int(raw.size()), &size, 8);
  chunk("IDAT", deflated, std::size_t(size));
  std::free(deflated);
  chunk("IEND", nullptr, 0);
  return out;
}

// Rows of one colour, each with filter byte 0, for the passes of a 16 x 16 image (one pass, or Adam7's seven).
std::vector<unsigned char> rows_of_colour(bool interlaced) {
  const std::vector<std::pair<int, int>> passes =
      interlaced ? std::vector<std::pair<int, int>>{{2, 2}, {2, 2}, {4, 2}, {4, 4}, {8, 4}, {8, 8}, {16, 8}}
                 : std::vector<std::pair<int, int>>{{16, 16}};
  std::vector<unsigned char> raw;
  for (const auto& [w, h] : passes)
    for (int y = 0; y < h; ++y) {
      raw.push_back(0);
      for (int x = 0; x < w; ++x) raw.insert(raw.end(), {200, 100, 50, 255});
    }
  return raw;
}

// Debian's libstb inflates a PNG's pixel data into a buffer it doubles as the stream demands, whatever the
// header says: a 16 x 16 texture whose pixel data inflates to 16 MiB decoded silently, taking a thousand times
// its bytes. The loader's own stb (stb_capped.h) stops at a few times the header's pixels: the bomb falls
// back to its factor with one warning, and the same image with exact data, plain or Adam7, decodes.
TEST(Textures, APngWhosePixelDataInflatesPastItsHeaderIsRefusedWhileDecoding) {
  for (const bool interlaced : {false, true}) {
    const std::vector<unsigned char> raw = rows_of_colour(interlaced);
    EXPECT_EQ(raw.size(), interlaced ? 1054u : 1040u);
    TexturedQuad exact;
    exact.g.json["textures"] = {{{"source", exact.add_image(png_of(16, 16, interlaced, raw), "image/png")}}};
    const scene::Scene s = exact.load(interlaced ? "tex-png-adam7" : "tex-png-exact");
    EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
    EXPECT_NEAR(s.triangle_albedo[0].g, srgb(100), 1e-6f) << "interlaced " << interlaced;
  }
  const Bytes bomb = png_of(16, 16, false, std::vector<unsigned char>(16u << 20, 0));
  EXPECT_LT(bomb.size(), 256u << 10);
  const std::string warning = refused_png_warning(bomb, "tex-png-bomb");
  EXPECT_NE(warning.find("corrupt image data: decoding asks for more than"), std::string::npos) << warning;
  EXPECT_NE(warning.find("more than its 16x16 pixels need"), std::string::npos) << warning;
}

TEST(Textures, WebpAndKtx2DataUrisAreAccepted) {
  TexturedQuad q;
  const Bytes webp = webp_bytes(200, 100, 50);
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string b64;
  for (std::size_t i = 0; i < webp.size(); i += 3) {
    const std::uint32_t n = (std::uint32_t(webp[i]) << 16) | (i + 1 < webp.size() ? webp[i + 1] << 8 : 0) |
                            (i + 2 < webp.size() ? webp[i + 2] : 0);
    for (std::size_t k = 0; k < 4; ++k) b64 += i + k <= webp.size() ? kAlphabet[(n >> (18 - 6 * k)) & 63] : '=';
  }
  q.g.json["images"] = {{{"uri", "data:image/webp;base64," + b64}}};
  q.g.json["textures"] = {{{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}}};
  const scene::Scene s = q.load("tex-webp-data-uri");
  EXPECT_NEAR(s.triangle_albedo[0].g, srgb(100), 1e-6f);
  EXPECT_TRUE(s.warnings.empty());
}

// ---- What the spec allows ------------------------------------------------------------------------------

TEST(SpecValid, UnusedUrilessBufferGltfBufferDataUriAndViewlessAccessors) {
  const auto dir = test_dir("spec-valid");
  MiniGltf unused = MiniGltf::triangles(kQuad, kQuadIndices);
  unused.json["buffers"].push_back({{"byteLength", 1u << 30}}); // nothing reads it: never allocated
  unused.write_gltf(dir / "unused.gltf", "unused.bin");
  expect_quad(scene::load_scene(dir / "unused.gltf", {.max_memory = 1 << 20}));

  MiniGltf data = MiniGltf::triangles(kQuad, kQuadIndices);
  data.write_gltf(dir / "data.gltf", "");
  std::ifstream in(dir / "data.gltf");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::size_t at = text.find("data:application/octet-stream");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, std::strlen("data:application/octet-stream"), "data:application/gltf-buffer");
  std::ofstream(dir / "gltf-buffer.gltf") << text;
  expect_quad(scene::load_scene(dir / "gltf-buffer.gltf"));

  // POSITION without bufferView (zeros) but sparse values for all four vertices; indices without bufferView.
  MiniGltf sparse = MiniGltf::triangles(kQuad, kQuadIndices);
  const std::vector<std::uint16_t> which = {0, 1, 2, 3};
  const int wv = sparse.add_view(which.data(), 8);
  const int vv = sparse.add_view(kQuad.data(), 48);
  sparse.json["accessors"][0].erase("bufferView");
  sparse.json["accessors"][0]["sparse"] = {
      {"count", 4}, {"indices", {{"bufferView", wv}, {"componentType", 5123}}}, {"values", {{"bufferView", vv}}}};
  sparse.json["accessors"][1].erase("bufferView");
  sparse.write_glb(dir / "sparse.glb");
  const scene::Scene s = scene::load_scene(dir / "sparse.glb");
  ASSERT_EQ(s.triangle_count(), 2u);
  EXPECT_EQ(s.positions[3], kQuad[3]);
  EXPECT_EQ(s.triangles[1], glm::uvec3(0, 0, 0)); // all-zero indices: degenerate, but valid
}

TEST(SpecValid, ReadingAPlaceholderBufferIsAnError) {
  MiniGltf g = MiniGltf::triangles(kQuad, kQuadIndices);
  g.json["buffers"].push_back({{"byteLength", 48}});
  g.json["bufferViews"].push_back({{"buffer", 1}, {"byteLength", 48}});
  g.json["accessors"][0]["bufferView"] = 2;
  const auto dir = test_dir("placeholder-read");
  g.write_glb(dir / "scene.glb");
  const std::string message = load_error(dir / "scene.glb");
  EXPECT_NE(message.find("reaches past its buffer of 0 bytes"), std::string::npos) << message;
}

} // namespace
} // namespace probebake::test
