// The C++ face of the shared probe irradiance code (probebake/sh_code.h).
#include "probebake/formats/sh_codec.h"

#include <algorithm>
#include <iterator>

namespace probebake::formats {

std::string_view sh_codec_name(ShCodec codec) {
  switch (codec) {
  case ShCodec::float32: return "float";
  case ShCodec::l2: return "l2";
  case ShCodec::l1: return "l1";
  }
  return "?";
}

std::optional<ShCodec> parse_sh_codec(std::string_view name) {
  for (ShCodec codec : kShCodecs)
    if (sh_codec_name(codec) == name) return codec;
  return std::nullopt;
}

int sh_codec_bytes(ShCodec codec) {
  switch (codec) {
  case ShCodec::float32: return int(sizeof(float)) * gpu::PROBE_SH_FLOATS;
  case ShCodec::l2: return gpu::SH_CODE_L2_BYTES;
  case ShCodec::l1: return gpu::SH_CODE_L1_BYTES;
  }
  return 0;
}

gpu::ShCode encode_sh(ShCodec codec, const ShCoefficients& sh) {
  return gpu::sh_code_encode(sh.data(), codec == ShCodec::l2);
}

ShCoefficients decode_sh(const gpu::ShCode& code) {
  ShCoefficients sh{};
  const glm::vec3 l0 = gpu::sh_code_l0(code.band01);
  for (int j = 0; j < gpu::PROBE_SH_FLOATS; ++j) sh[std::size_t(j)] = gpu::sh_code_coefficient(code, l0, j);
  return sh;
}

ShCoefficients round_trip_sh(ShCodec codec, const ShCoefficients& sh) {
  return codec == ShCodec::float32 ? sh : decode_sh(encode_sh(codec, sh));
}

ProbeVolume with_sh_codec(const ProbeVolume& volume, ShCodec codec) {
  ProbeVolume coded = volume;
  for (gpu::Probe& probe : coded.probes) {
    ShCoefficients sh;
    std::copy(std::begin(probe.irradiance_sh), std::end(probe.irradiance_sh), sh.begin());
    sh = round_trip_sh(codec, sh);
    std::copy(sh.begin(), sh.end(), std::begin(probe.irradiance_sh));
  }
  return coded;
}

} // namespace probebake::formats
