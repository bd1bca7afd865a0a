// Probe irradiance codecs: how many bytes a probe's L2 SH irradiance takes where a game looks it up. The
// encoder and decoder are probebake/sh_code.h's, shared with the shaders; this is their C++ face.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include "probebake/formats/probe_volume.h"
#include "probebake/sh_code.h"

namespace probebake::formats {

enum class ShCodec : std::uint8_t {
  float32, // the probes section's 27 floats (108 bytes)
  l2,      // 32 bytes: L0 in half floats, bands 1 and 2 in 8 bits per coefficient (sh_code.h)
  l1,      // 16 bytes: L0 and band 1 of the l2 code; band 2 dropped
};
inline constexpr std::array<ShCodec, 3> kShCodecs = {ShCodec::float32, ShCodec::l2, ShCodec::l1};

std::string_view sh_codec_name(ShCodec codec); // "float", "l2", "l1"
std::optional<ShCodec> parse_sh_codec(std::string_view name);
int sh_codec_bytes(ShCodec codec); // 108, 32, 16

using ShCoefficients = std::array<float, gpu::PROBE_SH_FLOATS>;

gpu::ShCode encode_sh(ShCodec codec, const ShCoefficients& sh); // codec l2 or l1
ShCoefficients decode_sh(const gpu::ShCode& code);
// sh as a game sees it through `codec` (decode of encode; float32 returns sh).
ShCoefficients round_trip_sh(ShCodec codec, const ShCoefficients& sh);
// `volume` with every probe's irradiance replaced by its round trip through `codec`.
ProbeVolume with_sh_codec(const ProbeVolume& volume, ShCodec codec);

} // namespace probebake::formats
