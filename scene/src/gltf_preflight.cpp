// Checks a glTF's JSON before any parser builds a tree from it (untrusted input, README "Security"):
// nesting depth (tinygltf converts `extras` recursively, so deep nesting would overflow the stack), data
// URIs that are not base64, and external URIs that are absolute, carry a scheme or resolve outside the
// allowed folders. nlohmann's SAX parser is iterative, so this pass itself is safe at any depth.
#include <cmath>
#include <string>
#include <unordered_set>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "gltf_internal.h"
#include "probebake/scene/scene.h"

namespace probebake::scene::detail {
namespace {

bool is_base64_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '+' || c == '/';
}

// The payload of a data URI is RFC 4648 base64: alphabet characters, then at most two '=' at the end.
// Unpadded tails are accepted (some exporters drop the padding), a lone trailing character is not.
bool is_valid_base64(std::string_view text) {
  std::size_t end = text.size();
  int padding = 0;
  while (end > 0 && text[end - 1] == '=' && padding < 2) {
    --end;
    ++padding;
  }
  for (std::size_t i = 0; i < end; ++i)
    if (!is_base64_char(text[i])) return false;
  if (padding > 0) return text.size() % 4 == 0;
  return end % 4 != 1;
}

// Why a data URI cannot be decoded, or empty. Recorded rather than refused here: the rewrite refuses it
// when a primitive or texture may read the object and hides it otherwise (gltf_rewrite.cpp).
std::string data_uri_problem(const std::string& uri) {
  const std::size_t comma = uri.find(',');
  if (comma == std::string::npos) return "data URI has no ',' before its payload";
  const std::string_view header(uri.data(), comma);
  if (!header.ends_with(";base64")) return "data URI is not base64 (glTF requires ';base64,')";
  if (!is_valid_base64(std::string_view(uri).substr(comma + 1))) return "data URI payload is not valid base64";
  return {};
}

bool is_accessor_type(const std::string& type) {
  for (const char* known : {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"})
    if (type == known) return true;
  return false;
}

bool is_component_type(double type) {
  for (const double known : {5120.0, 5121.0, 5122.0, 5123.0, 5125.0, 5126.0})
    if (type == known) return true;
  return false;
}

// 2^53: beyond it a double no longer holds every integer, so no integer property is written that way.
constexpr double kLargestExactInteger = 9007199254740992.0;

// The data URI headers tinygltf 2.7 decodes for images (it refuses others, e.g. image/webp, image/ktx2).
bool is_tinygltf_media_type(const std::string& uri) {
  for (const char* header : {"data:image/png;base64,", "data:image/jpeg;base64,", "data:image/bmp;base64,",
                             "data:image/gif;base64,", "data:application/octet-stream;base64,"})
    if (uri.starts_with(header)) return true;
  return false;
}

// A URI with a scheme ("http:", "file:", "c:") names no file inside the scene's folder.
bool has_scheme(const std::string& uri) {
  const std::size_t colon = uri.find(':');
  if (colon == std::string::npos || colon == 0) return false;
  for (std::size_t i = 0; i < colon; ++i) {
    const char c = uri[i];
    const bool ok = std::isalpha(static_cast<unsigned char>(c)) ||
                    (i > 0 && (std::isdigit(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.'));
    if (!ok) return false;
  }
  return true;
}

void check_file_uri(const std::string& uri, const InputPolicy& policy, const Context& ctx, const std::string& place) {
  const std::string path = scene::percent_decode(uri);
  const std::string quoted = fmt::format("'{}'", uri);
  if (path.empty()) ctx.fail(place, "URI is empty");
  if (path.find('\0') != std::string::npos) ctx.fail(place, fmt::format("URI {} holds a NUL character", quoted));
  if (path.front() == '/' || path.front() == '\\' || has_scheme(uri))
    ctx.fail(place, fmt::format("URI {} is absolute or has a scheme; external files must be relative paths "
                                "inside the scene's folder",
                                quoted));
  if (!policy.allows(policy.base_dir / path))
    ctx.fail(place, fmt::format("URI {} resolves outside the scene's folder {} (allow a folder with --allow-path)",
                                quoted, policy.base_dir.string()));
}

// SAX consumer: tracks depth and the path of the value being read, checks every `buffers[i].uri` and
// `images[i].uri`. Everything else is left to tinygltf.
class Preflight : public nlohmann::json_sax<nlohmann::json> {
public:
  Preflight(const InputPolicy& policy, const Context& ctx) : policy_(policy), ctx_(ctx) {}

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t v) override { return number(double(v)); }
  bool number_unsigned(number_unsigned_t v) override { return number(double(v)); }
  bool number_float(number_float_t v, const string_t&) override {
    // JSON does not tell 1 from 1.0: an integral float is an integer wherever glTF asks for one.
    if (std::abs(v) <= kLargestExactInteger && v == std::floor(v) && !inside_extras()) facts.integral_floats = true;
    return number(v);
  }
  bool binary(binary_t&) override { return value(); }
  bool string(string_t& text) override {
    if (is_uri_value()) check_uri(text);
    if (is_element_value("accessors", "type") && !is_accessor_type(text)) record_enum(text);
    if (is_element_value("cameras", "type") && text != "perspective" && text != "orthographic") record_enum(text);
    return value();
  }
  bool start_object(std::size_t) override { return open(false); }
  bool start_array(std::size_t) override { return open(true); }
  bool end_object() override {
    if (is_top_level_element()) record_element(frames_.back());
    return close();
  }
  bool end_array() override { return close(); }
  bool key(string_t& name) override {
    // A repeated key means two readers (this pass and the tree that tinygltf and the rewrite build) may each
    // keep a different value; the facts checked here would then not be the ones used.
    if (!frames_.back().keys.insert(name).second)
      ctx_.fail("json", fmt::format("key \"{}\" appears twice in one object", name));
    frames_.back().key = name;
    return true;
  }

  PreflightFacts facts;
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) override {
    ctx_.fail("json", fmt::format("byte {}: {}", position, strip_prefix(e.what())));
  }

private:
  struct Frame {
    bool array = false;
    std::size_t index = 0;                // arrays: index of the next element
    std::string key;                      // objects: the key of the value being read
    std::unordered_set<std::string> keys; // objects: every key seen so far
  };

  static std::string strip_prefix(const char* what) { // "[json.exception.parse_error.101] parse error at ..."
    std::string text(what);
    const std::size_t bracket = text.find("] ");
    return bracket == std::string::npos ? text : text.substr(bracket + 2);
  }

  bool value() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
    return true;
  }
  bool open(bool array) {
    if (frames_.size() >= kMaxJsonDepth)
      ctx_.fail("json", fmt::format("nesting is deeper than {} levels", kMaxJsonDepth));
    frames_.push_back({array, 0, {}, {}});
    return true;
  }
  bool close() {
    frames_.pop_back();
    return value();
  }
  // Root object -> top-level array -> element object (frames_.back()).
  bool is_top_level_element() const { return frames_.size() == 3 && frames_[1].array; }
  void record_element(const Frame& element) {
    const int index = int(frames_[1].index);
    if (frames_[0].key == "buffers" && !element.keys.contains("uri")) facts.buffers_without_uri.push_back(index);
    if (frames_[0].key == "accessors" && !element.keys.contains("bufferView"))
      facts.accessors_without_view.push_back(index);
  }
  // Root object -> `array` -> element object -> `key`.
  bool is_element_value(const char* array, const char* key) const {
    return frames_.size() == 3 && frames_[2].key == key && frames_[1].array && frames_[0].key == array;
  }
  bool is_uri_value() const { return is_element_value("buffers", "uri") || is_element_value("images", "uri"); }
  bool inside_extras() const {
    for (const Frame& frame : frames_)
      if (!frame.array && frame.key == "extras") return true;
    return false;
  }
  bool number(double v) {
    if (is_element_value("accessors", "componentType") && !is_component_type(v)) record_enum(fmt::format("{}", v));
    return value();
  }
  void record_enum(const std::string& text) {
    facts.unknown_enums.push_back({frames_[0].key, int(frames_[1].index), frames_[2].key, text});
  }
  void check_uri(const std::string& uri) {
    const std::string place = fmt::format("{}[{}].uri", frames_[0].key, frames_[1].index);
    if (!uri.starts_with("data:")) return check_file_uri(uri, policy_, ctx_, place);
    if (std::string problem = data_uri_problem(uri); !problem.empty())
      return facts.bad_data_uris.push_back({frames_[0].key, int(frames_[1].index), "uri", std::move(problem)});
    if (frames_[0].key == "images" && !is_tinygltf_media_type(uri))
      facts.images_with_other_media.push_back(int(frames_[1].index));
  }

  const InputPolicy& policy_;
  const Context& ctx_;
  std::vector<Frame> frames_;
};

} // namespace

std::string_view gltf_json_text(std::span<const unsigned char> bytes, bool is_glb, const Context& ctx) {
  if (!is_glb) return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
  const std::span<const unsigned char> json = split_glb(bytes, ctx).json;
  return {reinterpret_cast<const char*>(json.data()), json.size()};
}

PreflightFacts preflight_gltf_json(std::string_view json, const InputPolicy& policy, const Context& ctx) {
  Preflight sax(policy, ctx);
  nlohmann::json::sax_parse(json.begin(), json.end(), &sax);
  return std::move(sax.facts);
}

} // namespace probebake::scene::detail

namespace probebake::scene {

std::string percent_decode(const std::string& uri) {
  // The same decoding tinygltf applies before opening a file (including '+' as a space), so the path
  // checked here is the path it opens.
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return 0;
  };
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      out += ' ';
    } else if (uri[i] == '%' && uri.size() > i + 2) {
      out += static_cast<char>((hex(uri[i + 1]) << 4) | hex(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

} // namespace probebake::scene
